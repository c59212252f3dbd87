// libFuzzer target: the GP model file reader (JSON, kernel, hyperparameters, basis, weights) on arbitrary bytes.

#include <cstddef>
#include <cstdint>
#include <stdexcept>

#include "models/gpr/gpr_io.h"
#include "tests/fuzz/fuzz_input_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  const auto path = mb::fuzz::WriteFuzzInput(data, size, "model.json");
  try {
    (void)mb::LoadGprModel(path);
  } catch (const std::exception&) {
  }
  return 0;
}

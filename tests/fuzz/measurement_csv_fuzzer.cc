// libFuzzer target: the CSV measurement-log reader (header, cells, NaN/Inf, time order, gaps) on arbitrary bytes.

#include <cstddef>
#include <cstdint>
#include <stdexcept>

#include "models/diagnosis/measurement_log.h"
#include "tests/fuzz/fuzz_input_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  const auto path = mb::fuzz::WriteFuzzInput(data, size, "log.csv");
  try {
    (void)mb::ReadMeasurementLog(path.string(), mb::MeasurementLogOptions{.required_columns = {}, .min_rows = 2});
  } catch (const std::exception&) {
  }
  return 0;
}

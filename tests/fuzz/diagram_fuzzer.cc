// libFuzzer target: the diagram loader (JSON parse with depth and duplicate-key checks, schema validation,
// subsystem expansion, parameter and connection checks, execution order) on arbitrary bytes. Any exception the
// loader documents is a clean refusal; a crash, a leak, undefined behaviour or a hang is a finding.

#include <cstddef>
#include <cstdint>
#include <stdexcept>

#include "engine/diagram_loader.h"
#include "tests/fuzz/fuzz_input_file.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, std::size_t size) {
  const auto path = mb::fuzz::WriteFuzzInput(data, size, "diagram.json");
  try {
    (void)mb::LoadDiagram(path);
  } catch (const std::exception&) {
    // A refusal with a message is the expected outcome for almost every input.
  }
  return 0;
}

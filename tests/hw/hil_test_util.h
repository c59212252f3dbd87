#pragma once
// Shared helpers of the HIL tests: the shipped HIL diagram with its plant swapped for board I/O.

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/diagram_loader.h"
#include "hw/hil_diagram.h"

namespace mb::testing {

inline std::filesystem::path HilDiagramDir() { return std::filesystem::path(MB_SOURCE_DIR) / "diagrams" / "hil"; }

/// diagrams/hil/pd_rigid_body.json with plant → subsystems/hil_io.json, stop time `stop_time` [s].
inline nlohmann::json HilDiagramJson(double stop_time) {
  const auto path = HilDiagramDir() / "pd_rigid_body.json";
  std::vector<std::string> dropped;
  nlohmann::json j = ReplaceSubsystem(ReadDiagramJson(path),
                                      {"plant", HilDiagramDir() / "subsystems" / "hil_io.json"}, path.string(),
                                      &dropped);
  j["defaultExperiment"]["stopTime"] = stop_time;
  return j;
}

}  // namespace mb::testing

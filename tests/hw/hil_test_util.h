#pragma once
// Shared helpers of the HIL tests: the shipped HIL diagram with its plant swapped for board I/O.

#include <algorithm>
#include <cmath>
#include <cstddef>
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

/// The median of |a_i − b_i| over the common length of two logged columns (a HIL run against the simulated one).
inline double MedianAbsoluteDifference(const std::vector<double>& a, const std::vector<double>& b) {
  std::vector<double> difference(std::min(a.size(), b.size()));
  if (difference.empty()) return 0.0;
  for (std::size_t i = 0; i < difference.size(); ++i) difference[i] = std::abs(a[i] - b[i]);
  const auto middle = difference.begin() + static_cast<std::ptrdiff_t>(difference.size() / 2);
  std::nth_element(difference.begin(), middle, difference.end());
  return *middle;
}

}  // namespace mb::testing

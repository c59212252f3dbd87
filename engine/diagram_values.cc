// Reading one value of a diagram's JSON, appending a problem instead of throwing (diagram_values.h).
#include "engine/diagram_values.h"

#include <exception>

#include <fmt/format.h>

namespace mb {

using nlohmann::json;

double NumberOr(const json& j, const char* key, double fallback, const std::string& ptr,
                std::vector<std::string>* problems) {
  if (!j.contains(key)) return fallback;
  if (!j[key].is_number()) {
    problems->push_back(fmt::format("{}/{}: must be a number, got {}", ptr, key, j[key].dump()));
    return fallback;
  }
  return j[key].get<double>();
}

std::optional<SampleTime> ParseSampleTime(const json& j, const std::string& ptr, std::vector<std::string>* problems) {
  double period = 0.0, offset = 0.0;
  if (j.is_number()) {
    period = j.get<double>();
  } else if (j.is_array() && (j.size() == 1 || j.size() == 2) && j[0].is_number() &&
             (j.size() == 1 || j[1].is_number())) {
    period = j[0].get<double>();
    offset = j.size() == 2 ? j[1].get<double>() : 0.0;
  } else {
    problems->push_back(fmt::format("{}: sampleTime must be Ts or [Ts, offset] in seconds, got {}", ptr, j.dump()));
    return std::nullopt;
  }
  try {
    return SampleTime::Discrete(period, offset);
  } catch (const std::exception& e) {
    problems->push_back(fmt::format("{}: {}", ptr, e.what()));
    return std::nullopt;
  }
}

}  // namespace mb

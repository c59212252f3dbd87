#pragma once
// Helpers for block tests: one-line diagram skeletons and error-message capture.

#include <numbers>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "engine/diagram_loader.h"
#include "engine/execution_order.h"
#include "engine/simulator.h"
#include "tests/engine/test_util.h"

namespace mb::testing {

inline constexpr double kTwoPi = 2.0 * std::numbers::pi;

/// `v` as an array: a braced list of ONE json value, {x}, is x itself (copy construction wins), not [x].
inline nlohmann::json AsArray(const nlohmann::json& v) {
  return v.is_array() ? v : nlohmann::json::array({v});
}

/// A diagram with the given elements, connections and logged signals (arrays, or one of each), run from 0 to
/// `stop` with log step `step`.
inline nlohmann::json MakeDiagram(const nlohmann::json& elements, const nlohmann::json& connections,
                                  const nlohmann::json& log, double stop, double step,
                                  const nlohmann::json& solver = {{"type", "rk4"}, {"step", 1e-3}}) {
  return {{"schemaVersion", "1.0"},
          {"defaultExperiment", {{"startTime", 0.0}, {"stopTime", stop}, {"stepSize", step}}},
          {"solver", solver},
          {"elements", AsArray(elements)},
          {"connections", AsArray(connections)},
          {"log", AsArray(log)}};
}

/// The text of the error BuildDiagram throws for `j` ("" if it builds).
inline std::string BuildError(const nlohmann::json& j, const std::string& base = ".") {
  try {
    BuildDiagram(j, base, "test.json");
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

/// One element {"name", "type", "parameters"} (and "sampleTime" when given).
inline nlohmann::json Element(const std::string& name, const std::string& type,
                              const nlohmann::json& parameters = nlohmann::json::object(),
                              const nlohmann::json& sample_time = nullptr) {
  nlohmann::json e = {{"name", name}, {"type", type}, {"parameters", parameters}};
  if (!sample_time.is_null()) e["sampleTime"] = sample_time;
  return e;
}

}  // namespace mb::testing

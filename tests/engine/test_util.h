#pragma once
// Helpers for engine tests: build diagrams from inline JSON.

#include <nlohmann/json.hpp>

#include "engine/diagram_loader.h"
#include "engine/simulator.h"

namespace mb::testing {

inline nlohmann::json Connect(const std::string& from, const std::string& to) {
  auto split = [](const std::string& s) {
    const auto dot = s.find('.');
    return std::pair{s.substr(0, dot), dot == std::string::npos ? std::string() : s.substr(dot + 1)};
  };
  auto [se, sc] = split(from);
  auto [ee, ec] = split(to);
  return {{"startElement", se}, {"startConnector", sc}, {"endElement", ee}, {"endConnector", ec}};
}

/// A constant feeding a gain (c.y → g.u), g.y logged: the smallest valid diagram.
inline nlohmann::json MinimalDiagram() {
  return {{"schemaVersion", "1.0"},
          {"elements",
           {{{"name", "c"}, {"type", "constant"}, {"parameters", {{"value", 1.0}}}},
            {{"name", "g"}, {"type", "gain"}, {"parameters", {{"gain", 2.0}}}}}},
          {"connections", {Connect("c.y", "g.u")}},
          {"log", {"g.y"}}};
}

inline Diagram Build(const nlohmann::json& j) { return BuildDiagram(j, ".", "test.json"); }

}  // namespace mb::testing

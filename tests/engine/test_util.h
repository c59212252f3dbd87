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

inline Diagram Build(const nlohmann::json& j) { return BuildDiagram(j, ".", "test.json"); }

}  // namespace mb::testing

#pragma once
// What the sweep suites share: a tiny diagram to sweep, and runs.csv read for comparison across engines.

#include <algorithm>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/csv.h"

namespace mb::testing {

// y = K·c at every step; metrics: the final y and the final c.
inline nlohmann::json GainDiagram() {
  return nlohmann::json::parse(R"({
    "schemaVersion": "1.0", "name": "gain",
    "defaultExperiment": {"startTime": 0, "stopTime": 0.01, "stepSize": 0.001},
    "solver": {"type": "rk4", "step": 0.001},
    "elements": [
      {"name": "c", "type": "constant", "parameters": {"value": 2.0}},
      {"name": "k", "type": "gain", "parameters": {"gain": 1.0}}],
    "connections": [{"startElement": "c", "startConnector": "y", "endElement": "k", "endConnector": "u"}],
    "log": ["k.y", "c.y"],
    "metrics": [{"name": "y_final", "type": "final", "signal": "k.y", "unit": "1"},
                {"name": "c_final", "type": "final", "signal": "c.y", "unit": "1"}]})");
}

// runs.csv as rows of cells (the header first) without the wall_time_s column: the only cells that differ between
// two runs of the same sweep (on one process, in shards, under MPI).
inline std::vector<std::vector<std::string>> RunsWithoutWallTime(const std::filesystem::path& runs_csv) {
  const CsvTextTable table = ReadCsvTextTable(runs_csv.string());
  const auto column = std::find(table.header.begin(), table.header.end(), "wall_time_s") - table.header.begin();
  std::vector<std::vector<std::string>> rows = {table.header};
  rows.insert(rows.end(), table.rows.begin(), table.rows.end());
  for (auto& row : rows) {
    if (static_cast<std::size_t>(column) < row.size()) row.erase(row.begin() + column);
  }
  return rows;
}

}  // namespace mb::testing

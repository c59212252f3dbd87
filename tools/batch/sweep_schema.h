#pragma once
// The JSON Schema (draft-07) of a sweep file (tools/batch/sweep_spec.h): printed by `motionblocks schema --sweep`, kept
// in diagrams/sweep.schema.json for editors, and enforced by ParseSweep (valijson, engine/json_schema.h).

#include <vector>

#include <nlohmann/json.hpp>

#include "engine/json_schema.h"

namespace mb {

/// The sweep schema: description, diagram, set, and exactly one of grid, list or random.
nlohmann::json SweepSchema();

/// The problems of `sweep` against SweepSchema(), each with its JSON pointer.
std::vector<SchemaProblem> SweepSchemaProblems(const nlohmann::json& sweep);

}  // namespace mb

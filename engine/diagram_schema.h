#pragma once
// The JSON Schema (draft-07) of a diagram file, generated from the block registry so that it cannot drift:
// every block type with its parameters (type, unit, enum, bounds, default, description), sampleTime rule and ports
// (in its description: DefaultPorts, engine/registry.h), every port name as a completion suggestion ("examples") for
// a connection's startConnector / endConnector, and every section the loader reads. `motionblocks schema` prints it; diagrams/schema.json is a copy for
// editors (a test keeps it equal). Every diagram and subsystem file is validated against it (valijson) before
// it is built; the loader keeps its own checks for what a schema cannot say (units, wiring, "did you mean").

#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/json_schema.h"
#include "engine/registry.h"

namespace mb {

/// The diagram schema for the block types in `registry` (one `definitions/blocks/<type>` per type, selected by
/// the element's "type" with if/then; a subsystem's inline "diagram" refers back to the root).
nlohmann::json DiagramSchema(const BlockRegistry& registry);

/// The problems of `diagram` (as the user wrote it) against DiagramSchema(BlockRegistry::Global()), worded for
/// people with the JSON pointer of each. Problems in the parameters, sampleTime and type of an element whose
/// type is a string are left to the loader, which words them better (unknown parameter with the block's list,
/// unit mismatch, "did you mean" for types).
std::vector<SchemaProblem> DiagramSchemaProblems(const nlohmann::json& diagram);

}  // namespace mb

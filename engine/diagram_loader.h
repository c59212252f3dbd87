#pragma once
// Loading a diagram from JSON (schema: diagrams/schema.json; names from SSP, DESIGN.md): validate everything
// first, collecting every problem with its JSON pointer, then build the blocks and sort them.

#include <filesystem>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/diagram.h"
#include "engine/execution_order.h"

namespace mb {

/// The schema version this build reads and writes.
inline constexpr const char* kDiagramSchemaVersion = "1.0";
/// The element type of a nested diagram, expanded by the loader (ExpandSubsystems) rather than a registered block.
inline constexpr const char* kSubsystemType = "subsystem";

/// Every problem found in a diagram, each "<file>: <json pointer>: <message and fix>".
class DiagramError : public std::runtime_error {
 public:
  DiagramError(const std::string& source, std::vector<std::string> problems);
  const std::vector<std::string>& problems() const { return problems_; }

 private:
  std::vector<std::string> problems_;
};

/// A parameter override `block.param=value` (value parsed as JSON when it parses, else taken as a string).
struct ParameterOverride {
  std::string block;
  std::string parameter;
  nlohmann::json value;
  /// Parses "block.param=value". @throws std::invalid_argument on a malformed text.
  static ParameterOverride Parse(const std::string& text);
};

/// Writes the overrides into the diagram JSON (`/elements/<i>/parameters/<param>`): a number (or array of numbers)
/// is in the parameter's SI unit whatever unit the diagram wrote (written in that unit when the diagram wrote a
/// quantity {"value", "unit"}), a quantity object `{"value": 2, "unit": "kg"}` replaces the written value as given
/// (ReplacedParameterSlot, engine/parameters.h). An override of "solver.<key>" or "defaultExperiment.<key>" (`--set solver.type=cvode`,
/// `--set defaultExperiment.stopTime=2`) sets that key of the section, as a sweep does (the diagram's schema then
/// checks the key). @throws DiagramError if a block is unknown (listing the blocks).
void ApplyOverrides(nlohmann::json* diagram, const std::vector<ParameterOverride>& overrides,
                    const std::string& source);

/// Reads the JSON file (clear error with line/column on a syntax error).
nlohmann::json ReadDiagramJson(const std::filesystem::path& path);

/// Expands `subsystem` elements (a nested diagram, in a file `"diagram": "plant.json"` relative to the parent,
/// or inline under "diagram") into the parent: inner elements become "<subsystem>/<element>", connections to
/// the subsystem's ports are rewired to the inner connectors' endpoints. Recursive. A subsystem file must lie in the
/// parent's folder (or one allowed with --allow-path) and be a regular file (engine/file_access.h). @throws DiagramError.
nlohmann::json ExpandSubsystems(const nlohmann::json& diagram, const std::filesystem::path& base_directory,
                                const std::string& source);

/// Most elements a diagram may hold, its subsystems expanded. 100,000 blocks load and run (tests/hostile); a million
/// took minutes before the first step, without a word (issue 41). Beyond this, BuildDiagram refuses the diagram at
/// once, before the schema, the expansion or any block is built.
inline constexpr std::size_t kMaxDiagramElements = 200000;
/// The problem a diagram of `count` elements (`or_more`: counting stopped there) beyond kMaxDiagramElements is:
/// "/elements: N elements[ or more][ once its subsystems are expanded], more than the 200000 a diagram may hold (…)".
std::string TooManyElementsProblem(std::size_t count, bool or_more, bool expanded);

/// Whether BuildDiagram checks the JSON against the diagram schema first.
enum class SchemaCheck {
  kValidate,  ///< always, for a diagram as read (the default)
  /// For a diagram that passed the schema before and since had only numbers replaced by numbers (a refit's trial
  /// values, SetParameterValues): the schema's answer cannot have changed. The builder's own checks (each block's
  /// parameter ranges, connections, loops) still run. Never for JSON from a file or a user.
  kSkipRevalidation,
};

/// Validates and builds a diagram from JSON. `base_directory` resolves relative file parameters;
/// `source` names the file in messages. @throws DiagramError (all problems at once; a diagram of more than
/// kMaxDiagramElements elements alone, at once) or AlgebraicLoopError.
Diagram BuildDiagram(const nlohmann::json& diagram, const std::filesystem::path& base_directory,
                     const std::string& source, SchemaCheck schema = SchemaCheck::kValidate);

/// A diagram built to be looked at (drawn), not run: everything BuildDiagram checks, except that a cycle of direct
/// feedthrough is returned with it rather than thrown.
struct InspectedDiagram {
  Diagram diagram;  ///< blocks, connections and connectors; no execution order when `algebraic_loop` is set
  std::optional<AlgebraicLoopError> algebraic_loop;  ///< the loader's refusal (its message and the cycle's blocks)
};

/// As BuildDiagram, but an algebraic loop does not throw (InspectedDiagram::algebraic_loop): `motionblocks draw`
/// draws a diagram whose only fault is such a loop, with the loop highlighted. Never simulate a diagram that has
/// one. @throws DiagramError (all other problems at once).
InspectedDiagram InspectDiagram(const nlohmann::json& diagram, const std::filesystem::path& base_directory,
                                const std::string& source);

/// ReadDiagramJson + ApplyOverrides + BuildDiagram.
Diagram LoadDiagram(const std::filesystem::path& path, const std::vector<ParameterOverride>& overrides = {});

}  // namespace mb

#pragma once
// DiagramDocument: the one typed way to read and edit a diagram's JSON (schema: diagrams/schema.json; names from
// SSP, DESIGN.md) — find an element, add one, connect ports, sum a signal into a driven input, insert an element
// before an input, set `element.parameter`, the free-parameter list, the experiment section — each operation
// checked against the block registry (types, parameter specs, ports), so that no tool walks or writes raw
// diagram JSON. Building and running stay with BuildDiagram (engine/diagram_loader.h) on `json()`.
//
// Ports are learned by asking the block type: the element is instantiated through its registered factory with
// its validated parameters (a `subsystem` element's ports are its inner diagram's connectors). Nothing here
// names a block type or a port: summing uses the type that declares `BlockType::sum_of_two` (blocks/sum.cc).

#include <filesystem>
#include <memory>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/experiment_mode.h"
#include "engine/parameters.h"
#include "engine/units.h"

namespace mb {

class Block;

/// One end of a connection: port `port` of element `element`, or — `element` empty — the diagram's connector
/// named `port` (an input connector as a start, an output connector as an end). SSP's startElement /
/// startConnector and endElement / endConnector. As a start, an element's port may be left empty when the element
/// has exactly one output: the document writes that output's name.
struct Endpoint {
  std::string element;
  std::string port;
  bool is_connector() const { return element.empty(); }
  /// "element.port", or the connector's name.
  std::string ToString() const { return element.empty() ? port : element + "." + port; }
  bool operator==(const Endpoint&) const = default;
};

/// A connection start → end as written in the diagram.
struct Connection {
  Endpoint start;
  Endpoint end;
};

/// A connector of the diagram (SSP `connectors`): "input" or "output", its unit, its measured column.
struct DocumentConnector {
  std::string name;
  std::string kind;         ///< "input" or "output"
  std::string unit;
  std::string measurement;  ///< the measured column's name (default: the connector's name)
  std::string quantity;     ///< declared "quantity" ("position", … units.h kQuantityNames); empty: the unit says it
  /// What it carries: the declared quantity, else its unit's (units.h ConnectorQuantity).
  MotionQuantity Quantity() const { return ConnectorQuantity(unit, quantity); }
};

/// An element to add: `name` is a wish (a taken name gets a suffix, see DiagramDocument::Add), `type` a
/// registered block type, `parameters` as in a diagram file (a value or {"value": …, "unit": "…"}),
/// `sample_time` [Ts, offset] in seconds for discrete blocks.
struct ElementSpec {
  std::string name;
  std::string type;
  nlohmann::json parameters = nlohmann::json::object();
  std::optional<std::pair<double, double>> sample_time;
  std::string description;
};

class DiagramDocument {
 public:
  /// Holds `diagram` (a JSON object; "elements" and "connections" arrays if present). `base_directory` resolves
  /// a subsystem's diagram file; `source` names the diagram in messages.
  /// @throws std::invalid_argument if `diagram` is not an object or "elements"/"connections" are not arrays.
  explicit DiagramDocument(nlohmann::json diagram, std::filesystem::path base_directory = {},
                           std::string source = "diagram");
  /// Reads a diagram file (ReadDiagramJson: syntax errors with line and column).
  static DiagramDocument Load(const std::filesystem::path& path);

  /// The diagram as JSON, to write out or to build (BuildDiagram).
  const nlohmann::json& json() const { return json_; }
  const std::filesystem::path& base_directory() const { return base_; }
  const std::string& source() const { return source_; }

  // ---- Elements ----------------------------------------------------------------------------------------
  bool Has(const std::string& element) const;
  std::vector<std::string> ElementNames() const;
  /// The element's "type". @throws std::invalid_argument for an unknown element ("did you mean").
  std::string TypeOf(const std::string& element) const;
  /// The elements of one type, in file order.
  std::vector<std::string> ElementsOfType(const std::string& type) const;
  /// `base` if no element has that name, else the first free of base_2, base_3, …
  std::string UniqueName(const std::string& base) const;
  /// Appends an element; returns its name: `spec.name`, or UniqueName(spec.name) when that is taken (adding never
  /// fails on a name clash, so a suggestion can be applied twice). @throws std::invalid_argument for an empty
  /// name or one with '.', an unknown type ("did you mean"), a sampleTime the type does not take / lacks, and
  /// every parameter problem at once (unknown parameter, missing required one, wrong type, unit or bound).
  /// A quantity given in a parameter's linear unit (a suggested block's {"value": 0.5, "unit": "N·s/m"}) is written
  /// in its unit on this diagram's axis, the value unchanged ({"value": 0.5, "unit": "N·m·s/rad"}; ParameterSpec).
  std::string Add(const ElementSpec& spec);

  // ---- Connections -------------------------------------------------------------------------------------
  std::vector<Connection> Connections() const;
  /// What drives `end` (an element's input or an output connector), if anything.
  std::optional<Endpoint> DriverOf(const Endpoint& end) const;
  /// Connects `start` (an element's output or an input connector) to `end` (an element's input or an output
  /// connector). @throws std::invalid_argument naming the element/connector/port that does not exist (listing the
  /// ports there are), or an end already driven ("use SumInto to add a signal").
  void Connect(const Endpoint& start, const Endpoint& end);
  /// Adds `addend` into the signal that already drives `end`: a new two-input sum (the type declaring
  /// BlockType::sum_of_two, named UniqueName(sum_name)) takes the old driver on its first input and `addend` on
  /// its second, and drives `end` in place of the old driver. Returns the sum's name. @throws
  /// std::invalid_argument if nothing drives `end` (connect it instead) or as Connect for `addend`.
  std::string SumInto(const Endpoint& end, const Endpoint& addend, const std::string& sum_name);
  /// The same with a two-input difference (the type declaring BlockType::difference_of_two): the old driver minus
  /// `subtrahend` drives `end` (a load on a plant's force input). @throws as SumInto.
  std::string SubtractInto(const Endpoint& end, const Endpoint& subtrahend, const std::string& name);
  /// Puts `element` (already added; exactly one input and one output port) between `end` and what drives it.
  /// @throws std::invalid_argument if nothing drives `end` or the element has not one input and one output.
  void InsertBefore(const Endpoint& end, const std::string& element);
  /// Puts `element` (already added; one input and one output port) after the element output `start`: every element
  /// input that `start` drove reads the element's output instead, and `start` drives the element; output connectors
  /// keep reading `start`. @throws std::invalid_argument if `start` drives no element input or the element has not
  /// one input and one output.
  void InsertAfter(const Endpoint& start, const std::string& element);
  /// Every element input that `start` drives reads `replacement` (an element output or an input connector) instead;
  /// output connectors keep reading `start`: the loop opened at `start` (a controller fed the measured position in
  /// place of the plant's). Returns how many inputs now read `replacement` (0: `start` drove none, nothing changed).
  /// Nothing is checked here and nothing thrown: BuildDiagram checks the ports and units of the result.
  std::size_t ReadInstead(const Endpoint& start, const Endpoint& replacement);
  /// Adds a two-input difference (the type declaring BlockType::difference_of_two, named UniqueName(name)) of
  /// `minuend` − `subtrahend` (element outputs or input connectors). Returns its name; OutputOf gives its output.
  /// @throws std::invalid_argument as Connect.
  std::string AddDifference(const Endpoint& minuend, const Endpoint& subtrahend, const std::string& name);
  /// The first output port of `element`. @throws std::invalid_argument for an unknown element or one without outputs.
  Endpoint OutputOf(const std::string& element) const;

  // ---- Connectors --------------------------------------------------------------------------------------
  /// The connectors of kind "input" or "output", in file order.
  std::vector<DocumentConnector> Connectors(const std::string& kind) const;
  /// Appends a connector (name, kind "input" or "output", unit, measured column; the column is left out when it is the
  /// name). @throws std::invalid_argument for an empty name, another kind, or a name a connector already has.
  void AddConnector(const DocumentConnector& connector);
  /// `base` if no connector has that name, else the first free of base_2, base_3, … (UniqueName's rule).
  std::string UniqueConnectorName(const std::string& base) const;
  /// Removes the connector named `name` and every connection at it (an output connector's driver keeps its other
  /// readers). Returns whether there was one.
  bool RemoveConnector(const std::string& name);

  // ---- Parameters --------------------------------------------------------------------------------------
  /// The value of `element.parameter` in its SI unit (a quantity {"value", "unit"} converted:
  /// ParameterValueInSi), else the type's default, else null (a required parameter not given). @throws std::invalid_argument for an unknown element or a parameter the
  /// type does not declare ("did you mean").
  nlohmann::json Parameter(const std::string& element, const std::string& parameter) const;
  /// The spec of `element.parameter` on this diagram's axis (OnAxis, Axis()): its unit as this diagram reads it
  /// (N·m·s/rad for a friction's viscous coefficient on a rotary diagram in rad and N·m, N·s/m on a linear one).
  /// @throws std::invalid_argument as Parameter.
  ParamSpec ParameterSpec(const std::string& element, const std::string& parameter) const;
  /// The axis this diagram's motion is in, from its connectors (engine/parameters.h DiagramAxis): m and N, or rad
  /// and N·m, rev and A, …
  MotionAxis Axis() const;
  /// Sets `element.parameter` to `value`: a number (or array) in the parameter's SI unit, written in the unit the
  /// diagram used if it wrote a quantity {"value", "unit"}; or a quantity object, written as given
  /// (ReplacedParameterSlot). @throws
  /// std::invalid_argument as Parameter; DiagramError if the value does not fit the parameter's spec (type,
  /// bounds) — the same error BuildDiagram would give.
  void SetParameter(const std::string& element, const std::string& parameter, const nlohmann::json& value);
  /// SetParameter, then the element built through its block type's factory as BuildDiagram will build it, so that a
  /// value right for the parameter alone but not with the element's others (three gains on a gain of width 1) is
  /// refused at once rather than when the diagram is built (Python's Diagram.set; issue 41). The element is left as
  /// it was when the value is refused. @throws as SetParameter; DiagramError
  /// "/elements/<element>/parameters/<parameter>: <element>.<parameter> = <value> does not fit element '…' (type):
  /// <the block's reason>".
  void SetParameterChecked(const std::string& element, const std::string& parameter, const nlohmann::json& value);
  /// Every parameter of the element validated against its type's specs, defaults filled in, units stripped.
  /// @throws std::invalid_argument for an unknown element or an unregistered type; DiagramError for bad values.
  Parameters ElementParameters(const std::string& element) const;

  // ---- Free parameters ("free": what compare and fit refit) ---------------------------------------------
  std::vector<std::string> FreeParameters() const;
  /// Appends "element.parameter" (if not listed yet). @throws std::invalid_argument as Parameter, or for a name
  /// without '.'.
  void AddFreeParameter(const std::string& name);
  /// Removes `name` from the free parameters (no-op when it is not one).
  void RemoveFreeParameter(const std::string& name);

  // ---- Experiment and solver ----------------------------------------------------------------------------
  /// Sets defaultExperiment to startTime `start`, stopTime `stop`, stepSize `step` [s].
  void SetExperiment(double start, double stop, double step);
  /// Keeps defaultExperiment's startTime (default 0) and stepSize, sets stopTime = startTime + `duration` [s].
  void SetExperimentDuration(double duration);
  /// Gives this document `other`'s defaultExperiment (or none, if it has none).
  void CopyExperimentFrom(const DiagramDocument& other);
  /// Sets `section`.`key` = `value`, `section` being "defaultExperiment" or "solver" (a sweep's
  /// "defaultExperiment.stopTime" or "solver.step"); the section is created if absent. The key is not checked here:
  /// the diagram's JSON Schema names the known ones (engine/diagram_schema.h). @throws std::invalid_argument for
  /// another section (naming the two), or an empty key.
  void SetSectionSetting(const std::string& section, const std::string& key, const nlohmann::json& value);
  /// Whether SetSectionSetting takes `section`: "defaultExperiment" or "solver".
  static bool IsSettingSection(const std::string& section);
  /// experiment.mode (simulation when absent). @throws std::invalid_argument for a name that is not a mode.
  ExperimentMode Mode() const;
  /// solver.step and defaultExperiment.stepSize when given and > 0 [s].
  std::optional<double> SolverStep() const;
  std::optional<double> ExperimentStepSize() const;

  // ---- Logging, subsystems, text ------------------------------------------------------------------------
  std::vector<std::string> LoggedSignals() const;
  void SetLoggedSignals(const std::vector<std::string>& signals);
  /// Removes every metric (a diagram run open-ended has nothing to score).
  void ClearMetrics();
  /// Points subsystem `element` at `file` and drops its parameter overrides (they belonged to the old inner
  /// diagram); returns the dropped overrides as "element.param = value". @throws std::invalid_argument if the
  /// element is unknown or not a subsystem.
  std::vector<std::string> SetSubsystemDiagram(const std::string& element, const std::filesystem::path& file);
  /// Rewrites the file names the diagram reads (file parameters, ParamSpec::file: from_file.file, gpr.model; a
  /// subsystem's "diagram" file; inside inline subsystems too) for a copy of it written into `folder`: each names
  /// the same file as before, relative to `folder` (an absolute name stays absolute unless it lies in `folder`).
  /// Relative names are read against base_directory() (empty: the current directory). Returns the rewritten names
  /// that lie outside `folder`, as "element.parameter: name": the copy reads those only with --allow-path
  /// (engine/file_access.h).
  std::vector<std::string> RelocateFiles(const std::filesystem::path& folder);
  /// Appends `text` to the diagram's "notes" / "description".
  void AppendNote(const std::string& text);
  void AppendDescription(const std::string& text);

 private:
  // SumInto and SubtractInto: `join` (two inputs, one output) takes the old driver of `end` on its first input and
  // `addend` on its second, and drives `end`.
  std::string JoinInto(const Endpoint& end, const Endpoint& addend, const ElementSpec& join);
  nlohmann::json* FindElement(const std::string& element);
  const nlohmann::json& Element(const std::string& element) const;
  /// The element's input or output port names (instantiating its block, or reading a subsystem's connectors).
  std::vector<std::string> Ports(const std::string& element, bool inputs) const;
  /// The one input and the one output port of an element inserted into a signal path (InsertBefore, InsertAfter).
  /// @throws std::invalid_argument naming the element when it has not exactly one of each.
  std::pair<std::string, std::string> PathPorts(const std::string& element) const;
  /// The element's block built through its registered type's factory (its parameters validated, defaults filled
  /// in, its sampleTime read). @throws std::invalid_argument for an unregistered type; whatever the factory throws.
  std::unique_ptr<Block> Instantiate(const std::string& element) const;
  /// `start` with an empty port of an element with one output resolved to that output.
  Endpoint ResolveStart(const Endpoint& start) const;
  /// @throws std::invalid_argument unless `endpoint` exists as a start (an output or input connector) or an end.
  void CheckEndpoint(const Endpoint& endpoint, bool is_start) const;
  /// Index of the connection into `end`. @throws std::invalid_argument if none.
  std::size_t FeedOf(const Endpoint& end) const;

  nlohmann::json json_;
  std::filesystem::path base_;
  std::string source_;
};

}  // namespace mb

// The diagram builder (diagram_loader.h: BuildDiagram, InspectDiagram): an expanded diagram's JSON checked against
// the schema and read section by section — experiment, solver, connectors, elements (blocks created through the
// registry), connections, logged signals, metrics, roles — each step appending its problems so that the user sees
// them all at once; then the execution order (sorted by direct feedthrough; an algebraic loop refused, or kept for
// drawing).
#include "engine/diagram_loader.h"

#include <algorithm>
#include <map>
#include <optional>
#include <set>
#include <sstream>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "engine/closest_names.h"
#include "engine/diagram_document.h"
#include "engine/diagram_schema.h"
#include "engine/diagram_values.h"
#include "engine/execution_order.h"
#include "engine/file_access.h"
#include "engine/json_schema.h"
#include "engine/registry.h"
#include "engine/solver_type.h"
#include "engine/subsystem_expansion.h"
#include "engine/text_excerpt.h"
#include "engine/units.h"

namespace mb {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// The block type that adds two signals (BlockType::sum_of_two, declared in its own file), for messages.
std::string SummingTypeName() {
  try {
    return BlockRegistry::Global().SumOfTwo().type_name;
  } catch (const std::logic_error&) {
    return "summing";
  }
}

// A block's ports by name, "a, b" ("(none)" without any), for messages.
std::string PortList(const std::vector<PortSpec>& ports) {
  std::string names;
  for (const auto& p : ports) names += (names.empty() ? "" : ", ") + p.name;
  return names.empty() ? "(none)" : names;
}

}  // namespace

/// Builds a Diagram step by step; each step appends problems instead of throwing so that the user sees them
/// all at once.
class DiagramBuilder {
 public:
  /// `origins`: where each element, connection and logged signal was written (ExpandSubsystemsImpl);
  /// `schema_problems`: the diagram's problems against the schema, reported with the builder's own (which win
  /// at the same pointer); blocks are not created when there are any.
  DiagramBuilder(const json& j, fs::path base, std::string source,
                 std::map<std::string, std::vector<std::string>> origins, std::vector<SchemaProblem> schema_problems)
      : j_(j),
        base_(std::move(base)),
        source_(std::move(source)),
        origins_(std::move(origins)),
        schema_problems_(std::move(schema_problems)) {}

  /// Builds the diagram; with `algebraic_loop` non-null, a cycle of direct feedthrough is stored there (the diagram
  /// then has no execution order) instead of thrown.
  Diagram Build(std::optional<AlgebraicLoopError>* algebraic_loop = nullptr) {
    if (!j_.is_object()) throw DiagramError(source_, {"/: a diagram is a JSON object"});
    CheckVersion();
    d_.name_ = j_.value("name", fs::path(source_).stem().string());
    ReadExperiment();
    ReadSolver();
    ReadInputConnectors();
    ReadElements();
    ThrowIfProblems();  // connections need valid blocks
    ReadConnections();
    ReadOutputConnectors();
    ReadLog();
    ReadMetrics();
    ReadRoles();
    ReadFree();
    ThrowIfProblems();
    try {
      Sort();
    } catch (const AlgebraicLoopError& e) {
      if (algebraic_loop == nullptr) throw;
      algebraic_loop->emplace(e);
    }
    return std::move(d_);
  }

 private:
  void Problem(std::string p) { problems_.push_back(std::move(p)); }

  /// Throws the builder's problems and the schema's, a schema problem only where the builder has none.
  void ThrowIfProblems() const {
    auto all = MergeProblems(problems_, schema_problems_, /*own_covers_descendants=*/false);
    if (!all.empty()) throw DiagramError(source_, all);
  }

  /// Where the user wrote entry `index` of `section` (after subsystem expansion).
  std::string At(const std::string& section, std::size_t index) const {
    const auto it = origins_.find(section);
    if (it != origins_.end() && index < it->second.size()) return it->second[index];
    return fmt::format("/{}/{}", section, index);
  }

  void CheckVersion() {
    if (!j_.contains("schemaVersion")) {
      Problem(fmt::format("/schemaVersion: missing; add \"schemaVersion\": \"{}\"", kDiagramSchemaVersion));
    } else if (j_["schemaVersion"] != kDiagramSchemaVersion) {
      Problem(fmt::format("/schemaVersion: this build reads version \"{}\", the file says {}", kDiagramSchemaVersion,
                          j_["schemaVersion"].dump()));
    }
  }

  void ReadExperiment() {
    const json e = j_.value("defaultExperiment", json::object());
    auto& x = d_.experiment_;
    x.start_time = NumberOr(e, "startTime", 0.0, "/defaultExperiment", &problems_);
    x.stop_time = NumberOr(e, "stopTime", 1.0, "/defaultExperiment", &problems_);
    x.step_size = NumberOr(e, "stepSize", 0.0, "/defaultExperiment", &problems_);
    if (!(x.stop_time > x.start_time)) {
      Problem(fmt::format("/defaultExperiment: stopTime ({}) must be greater than startTime ({})", x.stop_time,
                          x.start_time));
    }
    // Absent = automatic (the fastest discrete period, else the solver's steps); a number given must be a log
    // interval: 0 would log at no interval at all (issue 41: it was taken for "automatic" without a word).
    if (e.is_object() && e.contains("stepSize") && !(x.step_size > 0.0)) {
      Problem(fmt::format("/defaultExperiment/stepSize: must be > 0 s (the log interval), got {}; leave stepSize out "
                          "to log at the fastest discrete period (or every solver step)",
                          x.step_size));
    }
  }

  void ReadSolver() {
    const json s = j_.value("solver", json::object());
    auto& x = d_.solver_;
    x.type = s.value("type", "rk4");
    x.method = s.value("method", "bdf");
    x.step = NumberOr(s, "step", 1e-4, "/solver", &problems_);
    x.rtol = NumberOr(s, "rtol", 1e-6, "/solver", &problems_);
    x.atol = NumberOr(s, "atol", 1e-9, "/solver", &problems_);
    x.max_step = NumberOr(s, "maxStep", 0.0, "/solver", &problems_);
    if (!SolverTypeNamed(x.type)) {
      Problem(fmt::format("/solver/type: '{}' is not a solver; use \"{}\"", x.type, fmt::join(kSolverTypeNames, "\", \"")));
    }
    if (std::find(kCvodeMethodNames.begin(), kCvodeMethodNames.end(), x.method) == kCvodeMethodNames.end()) {
      Problem(fmt::format("/solver/method: '{}': CVODE's methods are \"bdf\" (stiff) and \"adams\"", x.method));
    }
    if (!(x.step > 0.0)) Problem("/solver/step: must be > 0 s");
    if (!(x.rtol > 0.0) || !(x.atol > 0.0)) Problem("/solver: rtol and atol must be > 0");
  }

  void ReadInputConnectors() {
    const json cs = j_.value("connectors", json::array());
    std::map<std::string, std::size_t> connector_index;  // name → where first declared
    for (std::size_t i = 0; i < cs.size(); ++i) {
      const std::string ptr = fmt::format("/connectors/{}", i);
      const json& c = cs[i];
      const std::string kind = c.value("kind", "");
      if (kind != "input" && kind != "output") {
        Problem(fmt::format("{}/kind: must be \"input\" or \"output\"", ptr));
        continue;
      }
      if (!c.contains("name") || !c["name"].is_string()) {
        Problem(fmt::format("{}/name: a connector needs a name", ptr));
        continue;
      }
      // Signals, measured columns and --input name a connector: one name, one connector, of either kind.
      const auto [first, unique] = connector_index.emplace(c["name"].get<std::string>(), i);
      if (!unique) {
        Problem(fmt::format("{}/name: connector '{}' is declared twice (also /connectors/{}); connector names must be "
                            "unique: rename or remove one",
                            ptr, Excerpt(first->first), first->second));
        continue;
      }
      if (kind != "input") continue;
      ExternalInput in;
      in.name = c["name"];
      in.unit = c.value("unit", "");
      in.measurement = c.value("measurement", in.name);
      in.quantity = DeclaredQuantity(c, ptr);
      in.optional = c.value("optional", false);
      in.default_value = NumberOr(c, "default", 0.0, ptr, &problems_);
      if (const std::string how = c.value("interpolation", "linear"); how == "cubic") {
        in.interpolation = InputInterpolation::kCubic;
      } else if (how != "linear") {
        Problem(fmt::format("{}/interpolation: '{}' is not an interpolation; use \"linear\" or \"cubic\"", ptr,
                            Excerpt(how)));
      }
      d_.inputs_.push_back(in);
    }
  }

  void ReadElements() {
    if (!j_.contains("elements") || !j_["elements"].is_array() || j_["elements"].empty()) {
      Problem("/elements: a diagram needs a non-empty array of elements");
      return;
    }
    std::set<std::string> names;
    const auto& registry = BlockRegistry::Global();
    const MotionAxis axis = DiagramAxis(j_);  // a rotary diagram's parameters in rotary units (N·m·s/rad …)
    d_.axis_ = axis;
    for (std::size_t i = 0; i < j_["elements"].size(); ++i) {
      const json& e = j_["elements"][i];
      const std::string ptr = At("elements", i);
      const std::string name = e.value("name", "");
      const std::string type = e.value("type", "");
      if (name.empty() || name.find('.') != std::string::npos) {
        Problem(fmt::format("{}/name: each element needs a name without '.'", ptr));
        continue;
      }
      if (!names.insert(name).second) {
        Problem(fmt::format("{}/name: the name '{}' is used twice; element names must be unique", ptr, name));
      }
      const BlockType* bt = registry.Find(type);
      if (!bt) {
        std::string hint;
        for (const auto& s : registry.Suggest(type)) hint += (hint.empty() ? "" : ", ") + s;
        Problem(fmt::format("{}/type: unknown block type '{}' in element '{}'{}; `motionblocks blocks` lists them",
                            ptr, type, name, hint.empty() ? "" : "; did you mean: " + hint));
        continue;
      }
      std::vector<std::string> param_problems;
      auto values = ValidateParameters(OnAxis(bt->parameters, axis), e.value("parameters", json::object()),
                                       ptr + "/parameters", &param_problems);
      for (auto& p : param_problems) Problem(fmt::format("{} (element '{}', {})", p, name, type));
      std::optional<SampleTime> st;
      if (e.contains("sampleTime")) {
        if (bt->sample_time_rule == SampleTimeRule::kNone) {
          Problem(fmt::format("{}/sampleTime: block type '{}' is not sampled (it is continuous or inherits its rate); "
                              "remove sampleTime or use the discrete variant",
                              ptr, type));
        } else {
          st = ParseSampleTime(e["sampleTime"], ptr + "/sampleTime", &problems_);
        }
      } else if (bt->sample_time_rule == SampleTimeRule::kRequired) {
        Problem(fmt::format("{}: element '{}' ({}) is discrete: add \"sampleTime\": [Ts, offset] in seconds", ptr,
                            name, type));
      }
      if (!param_problems.empty() || !schema_problems_.empty()) continue;
      try {
        BlockConfig config{name, Parameters(name, std::move(values)), st, base_};
        d_.blocks_.push_back(bt->factory(config));
        d_.block_index_.emplace(d_.blocks_.back()->name(), static_cast<int>(d_.blocks_.size() - 1));
        d_.block_types_.push_back(type);
        d_.block_parameters_.push_back(config.parameters);
        element_pointer_.push_back(ptr);
      } catch (const std::exception& ex) {
        Problem(fmt::format("{}: element '{}' ({}): {}", ptr, name, type, ex.what()));
      }
    }
  }

  // Resolves the start of a connection to a signal; "" element = an input connector of the diagram.
  std::optional<SignalRef> ResolveStart(const json& c, const std::string& ptr) {
    const std::string element = c.value("startElement", "");
    const std::string connector = c.value("startConnector", "");
    if (element.empty()) {
      for (std::size_t k = 0; k < d_.inputs_.size(); ++k) {
        if (d_.inputs_[k].name == connector) return SignalRef{-1, static_cast<int>(k)};
      }
      Problem(fmt::format("{}/startConnector: the diagram has no input connector '{}'", ptr, connector));
      return std::nullopt;
    }
    const int b = d_.FindBlock(element);
    if (b < 0) {
      Problem(fmt::format("{}/startElement: no element named '{}'", ptr, element));
      return std::nullopt;
    }
    const Block& block = *d_.blocks_[static_cast<std::size_t>(b)];
    if (connector.empty()) {  // issue 41: no port is guessed, even for a block of one output
      Problem(fmt::format("{}/startConnector: missing; name the output of element '{}' that the connection starts "
                          "from (its outputs: {})",
                          ptr, element, PortList(block.output_ports())));
      return std::nullopt;
    }
    const int port = block.FindOutputPort(connector);
    if (port < 0) {
      std::string ports;
      for (const auto& p : block.output_ports()) ports += (ports.empty() ? "" : ", ") + p.name;
      Problem(fmt::format("{}/startConnector: element '{}' has no output '{}'; its outputs: {}", ptr, element,
                          connector, ports.empty() ? "(none)" : ports));
      return std::nullopt;
    }
    return SignalRef{b, port};
  }

  void ReadConnections() {
    d_.sources_.resize(d_.blocks_.size());
    for (std::size_t b = 0; b < d_.blocks_.size(); ++b) {
      d_.sources_[b].assign(d_.blocks_[b]->input_ports().size(), SignalRef{-2, 0});  // -2: unconnected
    }
    const json cs = j_.value("connections", json::array());
    for (std::size_t i = 0; i < cs.size(); ++i) {
      const std::string ptr = At("connections", i);
      const json& c = cs[i];
      const std::string end_element = c.value("endElement", "");
      if (end_element.empty()) continue;  // to an output connector: handled by ReadOutputConnectors
      auto start = ResolveStart(c, ptr);
      const int b = d_.FindBlock(end_element);
      if (b < 0) {
        Problem(fmt::format("{}/endElement: no element named '{}'", ptr, end_element));
        continue;
      }
      const Block& block = *d_.blocks_[static_cast<std::size_t>(b)];
      const std::string connector = c.value("endConnector", "");
      if (connector.empty()) {  // issue 41: no port is guessed, even for a block of one input
        Problem(fmt::format("{}/endConnector: missing; name the input of element '{}' that the connection feeds "
                            "(its inputs: {})",
                            ptr, end_element, PortList(block.input_ports())));
        continue;
      }
      const int port = block.FindInputPort(connector);
      if (port < 0) {
        std::string ports;
        for (const auto& p : block.input_ports()) ports += (ports.empty() ? "" : ", ") + p.name;
        Problem(fmt::format("{}/endConnector: element '{}' has no input '{}'; its inputs: {}", ptr, end_element,
                            connector, ports.empty() ? "(none)" : ports));
        continue;
      }
      if (!start) continue;
      auto& slot = d_.sources_[static_cast<std::size_t>(b)][static_cast<std::size_t>(port)];
      if (slot.block != -2) {
        Problem(fmt::format("{}: input '{}.{}' is already connected; an input takes exactly one signal (use a sum "
                            "block to add signals)",
                            ptr, end_element, block.input_ports()[static_cast<std::size_t>(port)].name));
        continue;
      }
      const PortSpec& in = block.input_ports()[static_cast<std::size_t>(port)];
      const int width = d_.SignalWidth(*start);
      if (width != in.width) {
        Problem(fmt::format("{}: width mismatch: {} has width {}, input {}.{} expects {}", ptr,
                            d_.SignalName(*start), width, end_element, in.name, in.width));
        continue;
      }
      const std::string unit = SignalUnit(*start);
      const MotionQuantity declared =
          start->is_external() ? d_.inputs_[static_cast<std::size_t>(start->port)].quantity : MotionQuantity::kOther;
      if (!unit.empty() && !in.unit.empty() && !PortAcceptsSignal(in.unit, unit, declared)) {
        Problem(fmt::format("{}: unit mismatch: {} is in '{}', input {}.{} expects '{}' (insert a gain to convert)",
                            ptr, d_.SignalName(*start), unit, end_element, in.name, in.unit));
        continue;
      }
      slot = *start;
    }
    for (std::size_t b = 0; b < d_.blocks_.size(); ++b) {
      for (std::size_t p = 0; p < d_.sources_[b].size(); ++p) {
        if (d_.sources_[b][p].block == -2) {
          Problem(fmt::format("{}: input '{}.{}' is not connected; connect it (a constant block gives a fixed value)",
                              element_pointer_[b], d_.blocks_[b]->name(), d_.blocks_[b]->input_ports()[p].name));
        }
      }
    }
  }

  // The connector's declared "quantity" (units.h QuantityNamed; the schema holds the names); a problem when it
  // contradicts the connector's unit (a connector in m declared a force).
  MotionQuantity DeclaredQuantity(const json& c, const std::string& ptr) {
    if (!c.contains("quantity") || !c["quantity"].is_string()) return MotionQuantity::kOther;
    const std::string name = c["quantity"];
    const MotionQuantity declared = QuantityNamed(name);
    const std::string unit = c.contains("unit") && c["unit"].is_string() ? c["unit"].get<std::string>() : "";
    const MotionQuantity of_unit = QuantityOfUnit(unit);
    if (of_unit != MotionQuantity::kOther && of_unit != declared) {
      Problem(fmt::format("{}/quantity: \"{}\" contradicts the unit '{}', which measures a {}; leave \"quantity\" "
                          "out (the unit says it) or fix the unit",
                          ptr, Excerpt(name), Excerpt(unit),
                          kQuantityNames[static_cast<std::size_t>(of_unit) - 1]));
    }
    return declared;
  }

  std::string SignalUnit(const SignalRef& ref) const {
    if (ref.is_external()) return d_.inputs_[static_cast<std::size_t>(ref.port)].unit;
    return d_.blocks_[static_cast<std::size_t>(ref.block)]->output_ports()[static_cast<std::size_t>(ref.port)].unit;
  }

  void ReadOutputConnectors() {
    const json cs = j_.value("connectors", json::array());
    std::vector<std::string> names;  // the output connectors, in the order written
    for (const auto& c : cs) {
      if (c.value("kind", "") == "output" && c.contains("name") && c["name"].is_string()) names.push_back(c["name"]);
    }
    const auto feeding = ConnectionsIntoOutputs(names);
    for (std::size_t i = 0; i < cs.size(); ++i) {
      const json& c = cs[i];
      if (c.value("kind", "") != "output" || !c.contains("name")) continue;
      ExternalOutput out;
      out.name = c["name"];
      out.unit = c.value("unit", "");
      out.measurement = c.value("measurement", out.name);
      out.quantity = DeclaredQuantity(c, fmt::format("/connectors/{}", i));
      const auto it = feeding.find(out.name);
      std::optional<SignalRef> start;
      if (it != feeding.end()) start = ResolveStart(j_["connections"][it->second], At("connections", it->second));
      if (!start) {
        if (it == feeding.end()) {
          Problem(fmt::format("/connectors/{}: output connector '{}' is connected to nothing", i, out.name));
        }
        continue;
      }
      // The connector declares what it carries, as an input port does: a unit of another quantity (kg for a signal
      // in m) would label the logged and compared values wrongly. A linear signal may leave through a rotary
      // connector of its quantity and back (units.h PortAcceptsUnit: the blocks' linear units stand for both).
      const std::string unit = SignalUnit(*start);
      if (!unit.empty() && !out.unit.empty() && !PortAcceptsUnit(out.unit, unit) &&
          !PortAcceptsSignal(unit, out.unit, out.quantity)) {
        Problem(fmt::format("/connectors/{}/unit: unit mismatch: output connector '{}' is in '{}', but the signal "
                            "wired to it, {}, is in '{}' (write the signal's unit, or insert a gain to convert)",
                            i, Excerpt(out.name), Excerpt(out.unit), d_.SignalName(*start), unit));
        continue;
      }
      out.source = *start;
      d_.outputs_.push_back(out);
    }
  }

  /// The connection feeding each output connector (by index in "connections"). A connection without
  /// endElement must end at an output connector, and an output connector takes one connection.
  std::map<std::string, std::size_t> ConnectionsIntoOutputs(const std::vector<std::string>& outputs) {
    std::map<std::string, std::size_t> feeding;
    const json conns = j_.value("connections", json::array());
    for (std::size_t k = 0; k < conns.size(); ++k) {
      if (conns[k].value("endElement", "") != "") continue;
      const std::string name = conns[k].value("endConnector", "");
      const std::string ptr = At("connections", k);
      if (std::find(outputs.begin(), outputs.end(), name) == outputs.end()) {
        const auto close = ClosestNames(name, outputs, 1);
        Problem(fmt::format("{}/endConnector: the diagram has no output connector '{}'{}; a connection without "
                            "endElement ends at one of the diagram's output connectors: {}",
                            ptr, name, close.empty() ? "" : fmt::format(" (did you mean '{}'?)", close.front()),
                            outputs.empty() ? "(none)" : fmt::format("{}", fmt::join(outputs, ", "))));
        continue;
      }
      const auto [it, inserted] = feeding.emplace(name, k);
      if (!inserted) {
        Problem(fmt::format("{}: output connector '{}' is already connected ({}); an output takes exactly one "
                            "signal (use a {} block to add signals)",
                            ptr, name, At("connections", it->second), SummingTypeName()));
      }
    }
    return feeding;
  }

  void ReadLog() {
    std::set<std::string> seen;
    auto add = [&](const std::string& signal, const std::string& ptr) {
      if (!seen.insert(signal).second) return;
      try {
        const SignalRef ref = d_.ResolveSignal(signal);
        d_.logged_.push_back(LoggedSignal{signal, ref, d_.SignalWidth(ref)});
      } catch (const std::exception& e) {
        Problem(fmt::format("{}: {}", ptr, e.what()));
      }
    };
    const json log = j_.value("log", json::array());
    for (std::size_t i = 0; i < log.size(); ++i) {
      if (!log[i].is_string()) {
        Problem(fmt::format("{}: a logged signal is a string \"block.port\"", At("log", i)));
        continue;
      }
      add(log[i].get<std::string>(), At("log", i));
    }
    // Diagram inputs and outputs are always logged (compare needs them).
    for (const auto& in : d_.inputs_) add(in.name, "/connectors");
    for (const auto& out : d_.outputs_) add(out.name, "/connectors");
  }

  void ReadMetrics() {
    const json ms = j_.value("metrics", json::array());
    std::map<std::string, std::size_t> first_of_name;  // a result holds one value per metric name
    for (std::size_t i = 0; i < ms.size(); ++i) {
      const std::string ptr = fmt::format("/metrics/{}", i);
      const json& m = ms[i];
      MetricSpec spec;
      spec.name = m.value("name", "");
      const std::string type = m.value("type", "rmse");
      spec.signal = m.value("signal", "");
      spec.reference = m.value("reference", "");
      spec.unit = m.value("unit", "");
      spec.from = NumberOr(m, "from", -1e300, ptr, &problems_);
      spec.to = NumberOr(m, "to", 1e300, ptr, &problems_);
      if (spec.name.empty()) Problem(fmt::format("{}/name: a metric needs a name", ptr));
      if (const auto [at, inserted] = first_of_name.emplace(spec.name, i); !inserted && !spec.name.empty()) {
        Problem(fmt::format("{}/name: the metric name '{}' is used by /metrics/{} too; each metric needs a name of "
                            "its own (results hold one value per name)",
                            ptr, Excerpt(spec.name), at->second));
      }
      if (const auto known = MetricTypeNamed(type)) {
        spec.type = *known;
      } else {
        Problem(fmt::format("{}/type: '{}' is not a metric; use {}", ptr, Excerpt(type),
                            fmt::join(kMetricTypeNames, ", ")));
      }
      for (const auto* sig : {&spec.signal, &spec.reference}) {
        if (sig->empty()) continue;
        try {
          d_.ResolveSignal(*sig);
        } catch (const std::exception& e) {
          Problem(fmt::format("{}: {}", ptr, e.what()));
        }
      }
      if (spec.signal.empty()) Problem(fmt::format("{}/signal: a metric needs a signal", ptr));
      if (spec.type == MetricType::kRmsDifference && spec.reference.empty()) {
        Problem(fmt::format("{}/reference: rms_difference needs a reference signal", ptr));
      }
      d_.metrics_.push_back(spec);
    }
  }

  // "roles": {"role": "element", …}; the meaning of a role is the reader's (tools/workflow/loop_from_diagram.h).
  void ReadRoles() {
    if (!j_.contains("roles")) return;
    if (!j_["roles"].is_object()) {
      Problem("/roles: must be an object {\"role\": \"element name\"}");
      return;
    }
    for (const auto& [role, element] : j_["roles"].items()) {
      if (!element.is_string()) {
        Problem(fmt::format("/roles/{}: must be an element's name (a string), got {}", role, element.dump()));
      } else if (d_.FindBlock(element.get<std::string>()) < 0) {
        Problem(fmt::format("/roles/{}: no element named '{}'", role, element.get<std::string>()));
      } else {
        d_.roles_[role] = element.get<std::string>();
      }
    }
  }

  // "free": ["element.parameter", …], what compare and fit refit by default: each entry names an element of the
  // diagram and one of its type's parameters (issue 41: a misspelt entry was ignored by run and failed fit later).
  void ReadFree() {
    if (!j_.contains("free") || !j_["free"].is_array()) return;  // the schema says what a non-array is
    const json& free = j_["free"];
    for (std::size_t i = 0; i < free.size(); ++i) {
      if (!free[i].is_string()) continue;  // the schema's problem
      const std::string entry = free[i].get<std::string>();
      const std::string ptr = fmt::format("/free/{}", i);
      const auto dot = entry.find('.');
      if (dot == std::string::npos || dot == 0 || dot + 1 == entry.size()) {
        Problem(fmt::format("{}: '{}': write element.parameter, e.g. \"friction.viscous\"", ptr, Excerpt(entry)));
        continue;
      }
      const std::string element = entry.substr(0, dot), parameter = entry.substr(dot + 1);
      const int b = d_.FindBlock(element);
      if (b < 0) {
        std::vector<std::string> names;
        for (const auto& block : d_.blocks_) names.push_back(block->name());
        const auto closest = ClosestNames(element, names);
        Problem(fmt::format("{}: '{}': no element named '{}'{}", ptr, Excerpt(entry), Excerpt(element),
                            closest.empty() ? "" : fmt::format(" (did you mean '{}'?)", closest.front())));
        continue;
      }
      const std::string& type = d_.block_types_[static_cast<std::size_t>(b)];
      std::vector<std::string> names;
      for (const auto& spec : BlockRegistry::Global().Get(type).parameters) names.push_back(spec.name);
      if (std::find(names.begin(), names.end(), parameter) == names.end()) {
        const auto closest = ClosestNames(parameter, names);
        Problem(fmt::format("{}: '{}': element '{}' ({}) has no parameter '{}'{}; it takes: {}", ptr, Excerpt(entry),
                            element, type, Excerpt(parameter),
                            closest.empty() ? "" : fmt::format(" (did you mean '{}'?)", closest.front()),
                            fmt::join(names, ", ")));
      }
    }
  }

  void Sort() {
    std::vector<FeedthroughEdge> edges;
    std::vector<std::string> names;
    for (const auto& b : d_.blocks_) names.push_back(b->name());
    for (std::size_t b = 0; b < d_.blocks_.size(); ++b) {
      const auto& ports = d_.blocks_[b]->input_ports();
      for (std::size_t p = 0; p < ports.size(); ++p) {
        const SignalRef src = d_.sources_[b][p];
        if (!ports[p].direct_feedthrough || src.is_external()) continue;
        edges.push_back(FeedthroughEdge{src.block, static_cast<int>(b),
                                        fmt::format("{} → {}.{} (direct feedthrough)", d_.SignalName(src),
                                                    names[b], ports[p].name)});
      }
    }
    try {
      d_.execution_order_ = SortBlocks(static_cast<int>(d_.blocks_.size()), edges, names);
    } catch (const AlgebraicLoopError& e) {
      throw AlgebraicLoopError(fmt::format("{}: {}", source_, e.what()), e.cycle());
    }
  }

  const json& j_;
  fs::path base_;
  std::string source_;
  Diagram d_;
  std::vector<std::string> problems_;
  std::vector<std::string> element_pointer_;
  std::map<std::string, std::vector<std::string>> origins_;
  std::vector<SchemaProblem> schema_problems_;
};

std::string TooManyElementsProblem(std::size_t count, bool or_more, bool expanded) {
  return fmt::format("/elements: {} elements{}{}, more than the {} a diagram may hold (each is a block built, sorted "
                     "and stepped: a run would take minutes before its first step); simulate a part of the model, or "
                     "merge blocks (a gain or state_space of width n for n scalar ones)",
                     count, or_more ? " or more" : "", expanded ? " once its subsystems are expanded" : "",
                     kMaxDiagramElements);
}

namespace {

// Refuses a diagram of more than kMaxDiagramElements elements (`expanded`: counted after its subsystems' expansion).
void RequireAtMostMaxElements(const json& diagram, const std::string& source, bool expanded) {
  if (!diagram.is_object() || !diagram.contains("elements") || !diagram["elements"].is_array()) return;
  const std::size_t count = diagram["elements"].size();
  if (count <= kMaxDiagramElements) return;
  throw DiagramError(source, {TooManyElementsProblem(count, /*or_more=*/false, expanded)});
}

Diagram BuildDiagramImpl(const json& diagram, const fs::path& base_directory, const std::string& source,
                         std::optional<AlgebraicLoopError>* algebraic_loop,
                         SchemaCheck schema = SchemaCheck::kValidate) {
  // The diagram as the user wrote it against the schema first; a value of the wrong JSON type stops here (the
  // builder would not know what to make of it), other schema problems are reported with the builder's.
  RequireAtMostMaxElements(diagram, source, /*expanded=*/false);  // before any work that grows with the size
  std::vector<SchemaProblem> schema_problems;
  if (schema == SchemaCheck::kValidate) schema_problems = DiagramSchemaProblems(diagram);
  std::vector<std::string> problems;
  for (const auto& p : schema_problems) problems.push_back(p.Text());
  const bool wrong_type = std::any_of(schema_problems.begin(), schema_problems.end(),
                                      [](const SchemaProblem& p) { return p.wrong_type; });
  if (wrong_type || !diagram.is_object()) throw DiagramError(source, problems);
  const std::size_t schema_count = problems.size();
  SubsystemExpansion expanded = ExpandSubsystemsWithOrigins(diagram, base_directory, source, &problems);
  if (problems.size() > schema_count) throw DiagramError(source, problems);
  RequireAtMostMaxElements(expanded.diagram, source, /*expanded=*/true);
  return DiagramBuilder(expanded.diagram, base_directory, source, std::move(expanded.origins),
                        std::move(schema_problems))
      .Build(algebraic_loop);
}

}  // namespace

Diagram BuildDiagram(const json& diagram, const fs::path& base_directory, const std::string& source,
                     SchemaCheck schema) {
  return BuildDiagramImpl(diagram, base_directory, source, nullptr, schema);
}

InspectedDiagram InspectDiagram(const json& diagram, const fs::path& base_directory, const std::string& source) {
  std::optional<AlgebraicLoopError> algebraic_loop;
  Diagram built = BuildDiagramImpl(diagram, base_directory, source, &algebraic_loop);
  return InspectedDiagram{std::move(built), std::move(algebraic_loop)};
}

}  // namespace mb

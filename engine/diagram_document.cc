#include "engine/diagram_document.h"

#include <algorithm>
#include <stdexcept>

#include <fmt/format.h>

#include "engine/closest_names.h"
#include "engine/diagram_loader.h"
#include "engine/registry.h"
#include "engine/text_excerpt.h"

namespace mb {

namespace fs = std::filesystem;
using Json = nlohmann::json;

namespace {

std::string List(const std::vector<std::string>& names) {
  std::string out;
  for (const auto& n : names) out += (out.empty() ? "" : ", ") + n;
  return out.empty() ? "(none)" : out;
}

std::string DidYouMean(const std::string& name, const std::vector<std::string>& candidates) {
  const auto close = ClosestNames(name, candidates);
  return close.empty() ? "" : "; did you mean: " + List(close);
}

// The name `written` (read against `base`) as a diagram in `folder` names the same file; `outside` is set when that
// file is not inside `folder`. Absolute names outside `folder` stay absolute.
std::string RelocatedFileName(const std::string& written, const fs::path& base, const fs::path& folder,
                              bool* outside) {
  const fs::path as_written(written);
  const fs::path file = (as_written.is_absolute() ? as_written : fs::absolute(base) / as_written).lexically_normal();
  const fs::path relative = file.lexically_relative(fs::absolute(folder).lexically_normal());
  *outside = relative.empty() || *relative.begin() == "..";
  if (relative.empty() || (*outside && as_written.is_absolute())) return file.string();
  return relative.string();
}

// RelocateFiles on the "elements" of `diagram` (recursing into inline subsystems); `where` prefixes element names.
void RelocateElementFiles(Json* diagram, const fs::path& base, const fs::path& folder, const std::string& where,
                          std::vector<std::string>* outside_names) {
  if (!diagram->contains("elements") || !(*diagram)["elements"].is_array()) return;
  auto relocate = [&](Json* slot, const std::string& name) {
    Json* value = slot->is_object() && slot->contains("value") ? &(*slot)["value"] : slot;
    if (!value->is_string() || value->get<std::string>().empty()) return;
    bool outside = false;
    *value = RelocatedFileName(value->get<std::string>(), base, folder, &outside);
    if (outside) outside_names->push_back(fmt::format("{}: {}", name, value->get<std::string>()));
  };
  for (auto& element : (*diagram)["elements"]) {
    const std::string name = where + element.value("name", "?");
    const std::string type = element.value("type", "");
    if (type == kSubsystemType && element.contains("diagram")) {
      if (element["diagram"].is_object()) {
        RelocateElementFiles(&element["diagram"], base, folder, name + "/", outside_names);
      } else {
        relocate(&element["diagram"], name + ".diagram");
      }
      continue;
    }
    const BlockType* block_type = BlockRegistry::Global().Find(type);
    if (!block_type || !element.contains("parameters") || !element["parameters"].is_object()) continue;
    for (const auto& spec : block_type->parameters) {
      if (spec.file && element["parameters"].contains(spec.name)) {
        relocate(&element["parameters"][spec.name], name + "." + spec.name);
      }
    }
  }
}

const BlockType& RegisteredType(const std::string& type, const std::string& what) {
  const BlockType* bt = BlockRegistry::Global().Find(type);
  if (!bt) {
    throw std::invalid_argument(fmt::format("{}: unknown block type '{}'{}; `motionblocks blocks` lists them", what,
                                            type, DidYouMean(type, BlockRegistry::Global().TypeNames())));
  }
  return *bt;
}

const ParamSpec* FindSpec(const BlockType& type, const std::string& parameter) {
  for (const auto& spec : type.parameters) {
    if (spec.name == parameter) return &spec;
  }
  return nullptr;
}

std::vector<std::string> SpecNames(const BlockType& type) {
  std::vector<std::string> names;
  for (const auto& spec : type.parameters) names.push_back(spec.name);
  return names;
}

Endpoint Start(const Json& c) { return {c.value("startElement", ""), c.value("startConnector", "")}; }
Endpoint End(const Json& c) { return {c.value("endElement", ""), c.value("endConnector", "")}; }

Json ConnectionJson(const Endpoint& start, const Endpoint& end) {
  return {{"startElement", start.element}, {"startConnector", start.port}, {"endElement", end.element},
          {"endConnector", end.port}};
}

}  // namespace

DiagramDocument::DiagramDocument(Json diagram, fs::path base_directory, std::string source)
    : json_(std::move(diagram)), base_(std::move(base_directory)), source_(std::move(source)) {
  if (!json_.is_object()) throw std::invalid_argument(fmt::format("{}: a diagram is a JSON object", source_));
  for (const char* key : {"elements", "connections"}) {
    if (json_.contains(key) && !json_[key].is_array()) {
      throw std::invalid_argument(fmt::format("{}: /{} must be an array", source_, key));
    }
  }
}

DiagramDocument DiagramDocument::Load(const fs::path& path) {
  return DiagramDocument(ReadDiagramJson(path), path.parent_path(), path.string());
}

// ---- Elements ------------------------------------------------------------------------------------------

Json* DiagramDocument::FindElement(const std::string& element) {
  if (!json_.contains("elements")) return nullptr;
  for (auto& e : json_["elements"]) {
    if (e.value("name", "") == element) return &e;
  }
  return nullptr;
}

const Json& DiagramDocument::Element(const std::string& element) const {
  if (json_.contains("elements")) {
    for (const auto& e : json_["elements"]) {
      if (e.value("name", "") == element) return e;
    }
  }
  throw std::invalid_argument(fmt::format("{}: no element named '{}'{}", source_, element,
                                          DidYouMean(element, ElementNames())));
}

bool DiagramDocument::Has(const std::string& element) const {
  const auto names = ElementNames();
  return std::find(names.begin(), names.end(), element) != names.end();
}

std::vector<std::string> DiagramDocument::ElementNames() const {
  std::vector<std::string> names;
  for (const auto& e : json_.value("elements", Json::array())) names.push_back(e.value("name", ""));
  return names;
}

std::string DiagramDocument::TypeOf(const std::string& element) const { return Element(element).value("type", ""); }

std::vector<std::string> DiagramDocument::ElementsOfType(const std::string& type) const {
  std::vector<std::string> names;
  for (const auto& e : json_.value("elements", Json::array())) {
    if (e.value("type", "") == type) names.push_back(e.value("name", ""));
  }
  return names;
}

std::string DiagramDocument::UniqueName(const std::string& base) const {
  std::string name = base;
  for (int k = 2; Has(name); ++k) name = fmt::format("{}_{}", base, k);
  return name;
}

std::string DiagramDocument::Add(const ElementSpec& spec) {
  const std::string what = fmt::format("{}: adding element '{}'", source_, spec.name);
  if (spec.name.empty() || spec.name.find('.') != std::string::npos) {
    throw std::invalid_argument(fmt::format("{}: an element needs a name without '.'", what));
  }
  const BlockType& type = RegisteredType(spec.type, what);
  if (spec.sample_time && type.sample_time_rule == SampleTimeRule::kNone) {
    throw std::invalid_argument(fmt::format("{}: block type '{}' is not sampled; give no sample time", what, spec.type));
  }
  if (!spec.sample_time && type.sample_time_rule == SampleTimeRule::kRequired) {
    throw std::invalid_argument(
        fmt::format("{}: block type '{}' is discrete; give its sample time [Ts, offset]", what, spec.type));
  }
  const std::string name = UniqueName(spec.name);
  std::vector<std::string> problems;
  const std::vector<ParamSpec> specs = OnAxis(type.parameters, Axis());
  ValidateParameters(specs, spec.parameters, fmt::format("/elements/{}/parameters", name), &problems);
  if (!problems.empty()) throw std::invalid_argument(fmt::format("{} ({}): {}", what, spec.type, List(problems)));
  Json element = {{"name", name}, {"type", spec.type}};
  if (!spec.description.empty()) element["description"] = spec.description;
  if (spec.sample_time) element["sampleTime"] = {spec.sample_time->first, spec.sample_time->second};
  element["parameters"] = spec.parameters;
  for (const auto& s : specs) {  // a suggested block's {"value", "unit": "N·s/m"} reads N·m·s/rad on a rotary axis
    if (element["parameters"].is_object() && element["parameters"].contains(s.name)) {
      element["parameters"][s.name] = ParameterSlotOnAxis(s, element["parameters"][s.name]);
    }
  }
  json_["elements"].push_back(std::move(element));
  return name;
}

// ---- Ports and connections -----------------------------------------------------------------------------

std::vector<std::string> DiagramDocument::Ports(const std::string& element, bool inputs) const {
  const Json& e = Element(element);
  const std::string type = e.value("type", "");
  std::vector<std::string> names;
  if (type == kSubsystemType) {
    const Json& inner = e.value("diagram", Json());
    const Json connectors = inner.is_string() ? ReadDiagramJson(base_ / inner.get<std::string>()).value("connectors", Json::array())
                                              : inner.value("connectors", Json::array());
    for (const auto& c : connectors) {
      if (c.value("kind", "") == (inputs ? "input" : "output")) names.push_back(c.value("name", ""));
    }
    return names;
  }
  const std::string what = fmt::format("{}: element '{}'", source_, element);
  (void)RegisteredType(type, what);
  std::unique_ptr<Block> block;
  try {
    block = Instantiate(element);
  } catch (const std::exception& ex) {
    throw std::invalid_argument(fmt::format("{} ({}): cannot list its ports: {}", what, type, ex.what()));
  }
  for (const auto& p : inputs ? block->input_ports() : block->output_ports()) names.push_back(p.name);
  return names;
}

std::unique_ptr<Block> DiagramDocument::Instantiate(const std::string& element) const {
  const Json& e = Element(element);
  const std::string type = e.value("type", "");
  const BlockType& bt = RegisteredType(type, fmt::format("{}: element '{}'", source_, element));
  std::optional<SampleTime> st;
  if (e.contains("sampleTime")) {
    const Json& s = e["sampleTime"];
    st = s.is_array() ? SampleTime::Discrete(s.at(0).get<double>(), s.size() > 1 ? s[1].get<double>() : 0.0)
                      : SampleTime::Discrete(s.get<double>(), 0.0);
  }
  return bt.factory(BlockConfig{element, ElementParameters(element), st, base_});
}

Endpoint DiagramDocument::ResolveStart(const Endpoint& start) const {
  if (start.is_connector() || !start.port.empty()) return start;
  const auto ports = Ports(start.element, false);
  if (ports.size() != 1) {
    throw std::invalid_argument(fmt::format("{}: element '{}' ({}) has {} outputs; name one: {}", source_,
                                            start.element, TypeOf(start.element), ports.size(), List(ports)));
  }
  return {start.element, ports.front()};
}

void DiagramDocument::CheckEndpoint(const Endpoint& endpoint, bool is_start) const {
  // A start is an element's output or an input connector; an end an element's input or an output connector.
  const char* side = is_start ? "output" : "input";
  std::vector<std::string> names;
  if (endpoint.is_connector()) {
    const char* kind = is_start ? "input" : "output";
    for (const auto& c : Connectors(kind)) names.push_back(c.name);
    if (std::find(names.begin(), names.end(), endpoint.port) != names.end()) return;
    throw std::invalid_argument(fmt::format("{}: no {} connector '{}'; the {}s: {}", source_, kind, endpoint.port,
                                            kind, List(names)));
  }
  names = Ports(endpoint.element, !is_start);
  if (std::find(names.begin(), names.end(), endpoint.port) == names.end()) {
    throw std::invalid_argument(fmt::format("{}: element '{}' ({}) has no {} '{}'; its {}s: {}", source_,
                                            endpoint.element, TypeOf(endpoint.element), side, endpoint.port, side,
                                            List(names)));
  }
}

std::vector<Connection> DiagramDocument::Connections() const {
  std::vector<Connection> out;
  for (const auto& c : json_.value("connections", Json::array())) out.push_back({Start(c), End(c)});
  return out;
}

std::optional<Endpoint> DiagramDocument::DriverOf(const Endpoint& end) const {
  std::optional<Endpoint> driver;
  for (const auto& c : Connections()) {
    if (c.end == end) driver = c.start;
  }
  return driver;
}

std::size_t DiagramDocument::FeedOf(const Endpoint& end) const {
  std::optional<std::size_t> feed;
  const auto connections = Connections();
  for (std::size_t k = 0; k < connections.size(); ++k) {
    if (connections[k].end == end) feed = k;
  }
  if (!feed) {
    throw std::invalid_argument(fmt::format("{}: nothing drives {} '{}'; connect it instead", source_,
                                            end.is_connector() ? "output" : "input", end.ToString()));
  }
  return *feed;
}

void DiagramDocument::Connect(const Endpoint& given_start, const Endpoint& end) {
  const Endpoint start = ResolveStart(given_start);
  CheckEndpoint(start, true);
  CheckEndpoint(end, false);
  if (const auto driver = DriverOf(end)) {
    throw std::invalid_argument(fmt::format("{}: {} '{}' is already driven by '{}'; an input takes one signal (use "
                                            "SumInto to add a signal)",
                                            source_, end.is_connector() ? "output" : "input", end.ToString(),
                                            driver->ToString()));
  }
  json_["connections"].push_back(ConnectionJson(start, end));
}

std::string DiagramDocument::SumInto(const Endpoint& end, const Endpoint& addend, const std::string& sum_name) {
  const BlockType& sum = BlockRegistry::Global().SumOfTwo();
  return JoinInto(end, addend, {sum_name, sum.type_name, *sum.sum_of_two, std::nullopt, ""});
}

std::string DiagramDocument::SubtractInto(const Endpoint& end, const Endpoint& subtrahend, const std::string& name) {
  const BlockType& difference = BlockRegistry::Global().DifferenceOfTwo();
  return JoinInto(end, subtrahend, {name, difference.type_name, *difference.difference_of_two, std::nullopt, ""});
}

std::string DiagramDocument::JoinInto(const Endpoint& end, const Endpoint& given_addend, const ElementSpec& join) {
  const std::size_t feed = FeedOf(end);
  const Endpoint addend = ResolveStart(given_addend);
  CheckEndpoint(addend, true);
  const std::string name = Add(join);
  const auto inputs = Ports(name, true);
  const auto outputs = Ports(name, false);
  const Endpoint previous = Start(json_["connections"][feed]);
  json_["connections"].push_back(ConnectionJson(previous, {name, inputs.at(0)}));
  json_["connections"].push_back(ConnectionJson(addend, {name, inputs.at(1)}));
  json_["connections"][feed]["startElement"] = name;
  json_["connections"][feed]["startConnector"] = outputs.at(0);
  return name;
}

std::string DiagramDocument::AddDifference(const Endpoint& minuend, const Endpoint& subtrahend,
                                           const std::string& name) {
  const BlockType& difference = BlockRegistry::Global().DifferenceOfTwo();
  const std::string added = Add({name, difference.type_name, *difference.difference_of_two, std::nullopt, ""});
  const auto inputs = Ports(added, true);
  Connect(minuend, {added, inputs.at(0)});
  Connect(subtrahend, {added, inputs.at(1)});
  return added;
}

Endpoint DiagramDocument::OutputOf(const std::string& element) const {
  const auto outputs = Ports(element, false);
  if (outputs.empty()) {
    throw std::invalid_argument(fmt::format("{}: element '{}' has no output port", source_, element));
  }
  return {element, outputs.front()};
}

std::pair<std::string, std::string> DiagramDocument::PathPorts(const std::string& element) const {
  const auto inputs = Ports(element, true);
  const auto outputs = Ports(element, false);
  if (inputs.size() != 1 || outputs.size() != 1) {
    throw std::invalid_argument(fmt::format("{}: element '{}' ({}) has {} inputs and {} outputs; only an element with "
                                            "one of each can be inserted into a signal path",
                                            source_, element, TypeOf(element), inputs.size(), outputs.size()));
  }
  return {inputs.front(), outputs.front()};
}

void DiagramDocument::InsertBefore(const Endpoint& end, const std::string& element) {
  const std::size_t feed = FeedOf(end);
  const auto [input, output] = PathPorts(element);
  const Endpoint previous = Start(json_["connections"][feed]);
  json_["connections"].push_back(ConnectionJson(previous, {element, input}));
  json_["connections"][feed]["startElement"] = element;
  json_["connections"][feed]["startConnector"] = output;
}

void DiagramDocument::InsertAfter(const Endpoint& start, const std::string& element) {
  const auto [input, output] = PathPorts(element);
  std::size_t moved = 0;
  for (auto& c : json_["connections"]) {
    if (Start(c) != start || End(c).is_connector() || End(c).element == element) continue;
    c["startElement"] = element;
    c["startConnector"] = output;
    ++moved;
  }
  if (moved == 0) {
    throw std::invalid_argument(
        fmt::format("{}: '{}' drives no element's input; nothing to insert '{}' before", source_, start.ToString(),
                    element));
  }
  json_["connections"].push_back(ConnectionJson(start, {element, input}));
}

std::size_t DiagramDocument::ReadInstead(const Endpoint& start, const Endpoint& replacement) {
  std::size_t moved = 0;
  for (auto& c : json_["connections"]) {
    if (Start(c) != start || End(c).is_connector()) continue;
    c = ConnectionJson(replacement, End(c));
    ++moved;
  }
  return moved;
}

std::vector<DocumentConnector> DiagramDocument::Connectors(const std::string& kind) const {
  std::vector<DocumentConnector> out;
  for (const auto& c : json_.value("connectors", Json::array())) {
    if (c.value("kind", "") != kind) continue;
    const std::string name = c.value("name", "");
    out.push_back({name, kind, c.value("unit", ""), c.value("measurement", name), c.value("quantity", "")});
  }
  return out;
}

void DiagramDocument::AddConnector(const DocumentConnector& connector) {
  if (connector.name.empty() || (connector.kind != "input" && connector.kind != "output")) {
    throw std::invalid_argument(fmt::format("{}: a connector needs a name and the kind \"input\" or \"output\"",
                                            source_));
  }
  for (const auto& c : json_.value("connectors", Json::array())) {
    if (c.value("name", "") == connector.name) {
      throw std::invalid_argument(
          fmt::format("{}: a connector named '{}' exists already; choose another name", source_, connector.name));
    }
  }
  Json c = {{"name", connector.name}, {"kind", connector.kind}};
  if (!connector.unit.empty()) c["unit"] = connector.unit;
  if (!connector.quantity.empty()) c["quantity"] = connector.quantity;
  if (!connector.measurement.empty() && connector.measurement != connector.name) {
    c["measurement"] = connector.measurement;
  }
  json_["connectors"].push_back(std::move(c));
}

std::string DiagramDocument::UniqueConnectorName(const std::string& base) const {
  const auto taken = [&](const std::string& name) {
    const Json& connectors = json_.value("connectors", Json::array());
    return std::any_of(connectors.begin(), connectors.end(),
                       [&](const Json& c) { return c.value("name", "") == name; });
  };
  std::string name = base;
  for (int k = 2; taken(name); ++k) name = fmt::format("{}_{}", base, k);
  return name;
}

bool DiagramDocument::RemoveConnector(const std::string& name) {
  Json& connectors = json_["connectors"];
  if (!connectors.is_array()) return false;
  const auto named = std::find_if(connectors.begin(), connectors.end(),
                                  [&](const Json& c) { return c.value("name", "") == name; });
  if (named == connectors.end()) return false;
  connectors.erase(named);
  const Endpoint connector{"", name};
  Json kept = Json::array();
  for (const auto& c : json_["connections"]) {
    if (Start(c) != connector && End(c) != connector) kept.push_back(c);
  }
  json_["connections"] = std::move(kept);
  return true;
}

// ---- Parameters ----------------------------------------------------------------------------------------

Json DiagramDocument::Parameter(const std::string& element, const std::string& parameter) const {
  const Json& e = Element(element);
  const ParamSpec spec = ParameterSpec(element, parameter);
  const Json params = e.value("parameters", Json::object());
  if (params.contains(parameter)) return ParameterValueInSi(spec, params[parameter]);
  return spec.default_value ? *spec.default_value : Json();
}

ParamSpec DiagramDocument::ParameterSpec(const std::string& element, const std::string& parameter) const {
  const Json& e = Element(element);
  const std::string type = e.value("type", "");
  const BlockType& bt = RegisteredType(type, fmt::format("{}: element '{}'", source_, element));
  const ParamSpec* spec = FindSpec(bt, parameter);
  if (!spec) {
    throw std::invalid_argument(fmt::format("{}: element '{}' ({}) has no parameter '{}'{}; it takes: {}", source_,
                                            element, type, parameter, DidYouMean(parameter, SpecNames(bt)),
                                            List(SpecNames(bt))));
  }
  return OnAxis(*spec, Axis());
}

MotionAxis DiagramDocument::Axis() const { return DiagramAxis(json_); }

void DiagramDocument::SetParameter(const std::string& element, const std::string& parameter, const Json& value) {
  const ParamSpec spec = ParameterSpec(element, parameter);  // checks the element and the parameter's name
  std::vector<std::string> problems;
  ValidateParameters({spec}, Json{{parameter, value}}, fmt::format("/elements/{}/parameters", element), &problems);
  if (!problems.empty()) throw DiagramError(source_, problems);
  Json& slot = (*FindElement(element))["parameters"][parameter];
  slot = ParameterSlotOnAxis(spec, ReplacedParameterSlot(&spec, slot, value));
}

void DiagramDocument::SetParameterChecked(const std::string& element, const std::string& parameter,
                                          const Json& value) {
  Parameter(element, parameter);  // an unknown element or parameter: std::invalid_argument, nothing changed
  const Json before = FindElement(element)->value("parameters", Json());
  SetParameter(element, parameter, value);  // the value against the parameter's spec: nothing changed if refused
  try {
    (void)Instantiate(element);
  } catch (const std::exception& ex) {
    Json& e = *FindElement(element);
    if (before.is_null()) {
      e.erase("parameters");
    } else {
      e["parameters"] = before;
    }
    throw DiagramError(source_, {fmt::format("/elements/{}/parameters/{}: {}.{} = {} does not fit element '{}' ({}): {}",
                                             element, parameter, element, parameter, Excerpt(value.dump(), 80),
                                             element, TypeOf(element), ex.what())});
  }
}

Parameters DiagramDocument::ElementParameters(const std::string& element) const {
  const Json& e = Element(element);
  const BlockType& bt = RegisteredType(e.value("type", ""), fmt::format("{}: element '{}'", source_, element));
  std::vector<std::string> problems;
  auto values = ValidateParameters(OnAxis(bt.parameters, Axis()), e.value("parameters", Json::object()),
                                   fmt::format("/elements/{}/parameters", element), &problems);
  if (!problems.empty()) throw DiagramError(source_, problems);
  return Parameters(element, std::move(values));
}

std::vector<std::string> DiagramDocument::FreeParameters() const {
  std::vector<std::string> names;
  for (const auto& f : json_.value("free", Json::array())) names.push_back(f.get<std::string>());
  return names;
}

void DiagramDocument::AddFreeParameter(const std::string& name) {
  const auto dot = name.find('.');
  if (dot == std::string::npos) {
    throw std::invalid_argument(
        fmt::format("{}: free parameter '{}': write element.parameter, e.g. mass.gain", source_, name));
  }
  Parameter(name.substr(0, dot), name.substr(dot + 1));
  const auto names = FreeParameters();
  if (std::find(names.begin(), names.end(), name) == names.end()) json_["free"].push_back(name);
}

void DiagramDocument::RemoveFreeParameter(const std::string& name) {
  if (!json_.contains("free")) return;
  Json& free = json_["free"];
  for (auto it = free.begin(); it != free.end(); ++it) {
    if (it->is_string() && it->get<std::string>() == name) {
      free.erase(it);
      return;
    }
  }
}

// ---- Experiment, solver, logging, text ----------------------------------------------------------------

void DiagramDocument::SetExperiment(double start, double stop, double step) {
  json_["defaultExperiment"] = {{"startTime", start}, {"stopTime", stop}, {"stepSize", step}};
}

void DiagramDocument::SetExperimentDuration(double duration) {
  const double start = json_.value("defaultExperiment", Json::object()).value("startTime", 0.0);
  json_["defaultExperiment"]["startTime"] = start;
  json_["defaultExperiment"]["stopTime"] = start + duration;
}

bool DiagramDocument::IsSettingSection(const std::string& section) {
  return section == "defaultExperiment" || section == "solver";
}

void DiagramDocument::SetSectionSetting(const std::string& section, const std::string& key, const Json& value) {
  if (!IsSettingSection(section)) {
    throw std::invalid_argument(fmt::format("{}: '{}.{}': only defaultExperiment.<key> and solver.<key> are settings",
                                            source_, section, key));
  }
  if (key.empty()) {
    throw std::invalid_argument(fmt::format("{}: '{}.': name the setting after the dot", source_, section));
  }
  json_[section][key] = value;
}

std::vector<std::string> DiagramDocument::RelocateFiles(const fs::path& folder) {
  std::vector<std::string> outside;
  RelocateElementFiles(&json_, base_.empty() ? fs::current_path() : base_, folder, "", &outside);
  base_ = folder;
  return outside;
}

void DiagramDocument::CopyExperimentFrom(const DiagramDocument& other) {
  json_.erase("defaultExperiment");
  if (other.json_.contains("defaultExperiment")) json_["defaultExperiment"] = other.json_["defaultExperiment"];
}

ExperimentMode DiagramDocument::Mode() const {
  return ExperimentModeNamed(json_.value("experiment", Json::object()).value("mode", "simulation"));
}

std::optional<double> DiagramDocument::SolverStep() const {
  const double step = json_.value("solver", Json::object()).value("step", 0.0);
  return step > 0.0 ? std::optional<double>(step) : std::nullopt;
}

std::optional<double> DiagramDocument::ExperimentStepSize() const {
  const double step = json_.value("defaultExperiment", Json::object()).value("stepSize", 0.0);
  return step > 0.0 ? std::optional<double>(step) : std::nullopt;
}

std::vector<std::string> DiagramDocument::LoggedSignals() const {
  std::vector<std::string> out;
  for (const auto& s : json_.value("log", Json::array())) {
    if (s.is_string()) out.push_back(s.get<std::string>());
  }
  return out;
}

void DiagramDocument::SetLoggedSignals(const std::vector<std::string>& signals) { json_["log"] = signals; }

void DiagramDocument::ClearMetrics() { json_["metrics"] = Json::array(); }

std::vector<std::string> DiagramDocument::SetSubsystemDiagram(const std::string& element, const fs::path& file) {
  const std::string type = TypeOf(element);
  if (type != kSubsystemType) {
    throw std::invalid_argument(fmt::format(
        "{}: element '{}' is a '{}', not a subsystem; put it in its own file and use it as {{\"name\": \"{}\", "
        "\"type\": \"subsystem\", \"diagram\": \"plant.Json\"}} so that it can be swapped",
        source_, element, type, element));
  }
  Json& e = *FindElement(element);
  e["diagram"] = file.string();
  std::vector<std::string> dropped;
  const Json overrides = e.value("parameters", Json::object());
  for (const auto& [key, value] : overrides.items()) {
    dropped.push_back(fmt::format("{}.{} = {}", element, key, value.dump()));
  }
  e.erase("parameters");
  return dropped;
}

void DiagramDocument::AppendNote(const std::string& text) {
  json_["notes"] = json_.value("notes", std::string()) + text;
}

void DiagramDocument::AppendDescription(const std::string& text) {
  json_["description"] = json_.value("description", std::string()) + text;
}

}  // namespace mb

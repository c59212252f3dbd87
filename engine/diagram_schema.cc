#include "engine/diagram_schema.h"

#include <cmath>
#include <set>
#include <string>
#include <vector>

#include <fmt/format.h>

#include "engine/diagram_loader.h"
#include "engine/experiment_mode.h"
#include "engine/metric_type.h"
#include "engine/solver_type.h"
#include "engine/units.h"

namespace mb {

using nlohmann::json;

namespace {

// ---- Block types ---------------------------------------------------------------------------------------

json ValueSchema(const ParamSpec& p) {
  json number = {{"type", "number"}};
  if (p.min && std::isfinite(*p.min)) number["minimum"] = *p.min;
  if (p.max && std::isfinite(*p.max)) number["maximum"] = *p.max;
  switch (p.type) {
    case ParamType::kNumber: return number;
    case ParamType::kInteger: number["type"] = "integer"; return number;
    case ParamType::kBool: return {{"type", "boolean"}};
    case ParamType::kString: {
      json s = {{"type", "string"}};
      if (!p.choices.empty()) s["enum"] = p.choices;
      return s;
    }
    case ParamType::kVector: {
      json v = number;
      v["type"] = json::array({"number", "array"});
      v["items"] = number;
      return v;
    }
  }
  return json::object();
}

json ParameterSchema(const ParamSpec& p) {
  const json value = ValueSchema(p);
  // {"value": …, "unit": …}: a unit of the parameter's quantity is converted by the loader (engine/units.h), which
  // then checks the bounds in the declared unit; the schema checks only the value's type there.
  json converted = value;
  if (!p.unit.empty()) {
    for (json* v : {&converted, converted.contains("items") ? &converted["items"] : nullptr}) {
      if (v != nullptr) {
        v->erase("minimum");
        v->erase("maximum");
      }
    }
  }
  const json unit = p.unit.empty() ? json{{"type", "string"}}
                                   : json{{"type", "string"},
                                          {"description", fmt::format("{} or a unit of the same quantity (converted)",
                                                                      p.unit)}};
  json out = {{"description", p.unit.empty() ? p.description : fmt::format("{} [{}]", p.description, p.unit)},
              {"anyOf", json::array({value, {{"type", "object"},
                                             {"required", json::array({"value"})},
                                             {"additionalProperties", false},
                                             {"properties", {{"value", converted}, {"unit", unit}}}}})}};
  if (p.default_value) out["default"] = *p.default_value;
  return out;
}

// "Ports: inputs …; outputs …." or "Ports depend on parameters (…)." (engine/registry.h PortsSummary).
std::string PortsSentence(const BlockTypePorts& ports) {
  std::string summary = PortsSummary(ports);
  if (ports.known) return "Ports: " + summary + ".";
  summary[0] = 'P';  // "ports depend on …", "ports not listed: …"
  return summary + ".";
}

json BlockSchema(const BlockType& bt) {
  json params = {{"type", "object"}, {"additionalProperties", false}, {"properties", json::object()}};
  json required = json::array();
  for (const auto& p : bt.parameters) {
    params["properties"][p.name] = ParameterSchema(p);
    if (!p.default_value) required.push_back(p.name);
  }
  if (!required.empty()) params["required"] = required;
  // The ports in the description, for an editor's hover and completion (a connection's ports cannot be tied to its
  // element's type in a schema: each element's name is the user's).
  json block = {{"description", fmt::format("{} {}", bt.description, PortsSentence(DefaultPorts(bt)))},
                {"properties", {{"parameters", params}, {"diagram", false}}}};
  switch (bt.sample_time_rule) {
    case SampleTimeRule::kNone: block["properties"]["sampleTime"] = false; break;
    case SampleTimeRule::kRequired: block["required"] = json::array({"sampleTime"}); break;
    case SampleTimeRule::kOptional: break;
  }
  return block;
}

json SubsystemSchema() {
  return {{"description",
           "A nested diagram (a file relative to this one, or inline); its parameters override inner ones as "
           "\"inner_element.parameter\": value."},
          {"required", json::array({"diagram"})},
          {"properties",
           {{"sampleTime", false},
            // "inner_element.parameter": a '.' searched for, not an anchored "^[^.]+\\..+$": valijson matches
            // with std::regex, whose recursion per character overflowed the stack on a key a megabyte long.
            {"parameters", {{"type", "object"}, {"propertyNames", {{"pattern", "\\."}}}}}}}};
}

json ElementSchema(const BlockRegistry& registry) {
  json types = registry.TypeNames();
  types.push_back(kSubsystemType);
  json element = {
      {"type", "object"},
      {"required", {"name", "type"}},
      {"additionalProperties", false},
      {"properties",
       // No "pattern" for the '.': the loader refuses a dotted name with its own message, and valijson's std::regex
       // recursed once per character (a name a megabyte long overflowed the stack; tests/hostile found it).
       {{"name", {{"type", "string"}, {"minLength", 1}, {"description", "unique in the diagram, no '.'"}}},
        {"type", {{"type", "string"}, {"enum", types}, {"description", "a block type (motionblocks blocks)"}}},
        {"description", {{"type", "string"}}},
        {"parameters", {{"type", "object"}}},
        {"sampleTime",
         {{"description", "Ts or [Ts, offset] in seconds (Simulink's convention); discrete blocks only"},
          {"anyOf", json::array({{{"type", "number"}, {"exclusiveMinimum", 0}},
                                 {{"type", "array"},
                                  {"items", {{"type", "number"}}},
                                  {"minItems", 1},
                                  {"maxItems", 2}}})}}},
        {"diagram",
         {{"description", "subsystem only: a diagram file relative to this one, or an inline diagram"},
          {"anyOf", json::array({{{"type", "string"}}, {{"$ref", "#"}}})}}},
        {"ui", {{"type", "object"}}}}},
      {"allOf", json::array()}};
  for (const std::string type : types) {
    element["allOf"].push_back({{"if", {{"properties", {{"type", {{"const", type}}}}}, {"required", json::array({"type"})}}},
                                {"then", {{"$ref", "#/definitions/blocks/" + type}}}});
  }
  return element;
}

// ---- Sections ------------------------------------------------------------------------------------------

json StrictObject(json properties) {
  return {{"type", "object"}, {"additionalProperties", false}, {"properties", std::move(properties)}};
}

json ArrayOf(json items) { return {{"type", "array"}, {"items", std::move(items)}}; }

json Described(json schema, const std::string& description) {
  schema["description"] = description;
  return schema;
}

// The port names of every block type (outputs or inputs), sorted and unique: completion suggestions ("examples") for a
// connection's startConnector / endConnector.
json PortNames(const BlockRegistry& registry, bool inputs) {
  std::set<std::string> names;
  for (const auto& name : registry.TypeNames()) {
    const BlockTypePorts ports = DefaultPorts(*registry.Find(name));
    for (const auto& p : inputs ? ports.inputs : ports.outputs) names.insert(p.name);
  }
  return json(std::vector<std::string>(names.begin(), names.end()));
}

// A name table (engine/experiment_mode.h, metric_type.h, units.h) as a schema enum.
template <std::size_t N>
json Names(const std::array<std::string_view, N>& table) {
  json names = json::array();
  for (const auto name : table) names.push_back(std::string(name));
  return names;
}

json Sections(const BlockRegistry& registry) {
  const json string = {{"type", "string"}};
  const json number = {{"type", "number"}};
  json connector = StrictObject({{"name", string},
                                 {"kind", {{"enum", {"input", "output"}}}},
                                 {"unit", Described(string, "SI unit of the signal")},
                                 {"description", string},
                                 {"measurement", Described(string, "column in a measurement log (default: name)")},
                                 {"quantity", Described({{"enum", Names(kQuantityNames)}},
                                                        "what a signal in a unit of no motion quantity (V, none) "
                                                        "stands for; blocks take it on ports of that quantity")},
                                 {"optional", Described({{"type", "boolean"}}, "input only: may be absent")},
                                 {"default", Described(number, "input only: value when absent")},
                                 {"interpolation",
                                  Described({{"enum", {"linear", "cubic"}}},
                                            "input only: between the log's samples, linear (default) or cubic "
                                            "Hermite (Catmull-Rom), for a smooth signal logged slower than the "
                                            "diagram runs")}});
  connector["required"] = {"name", "kind"};
  json metric = StrictObject({{"name", string},
                              {"type", {{"enum", Names(kMetricTypeNames)}}},
                              {"signal", Described(string, "element.port or a connector name")},
                              {"reference", Described(string, "rms_difference: the signal to compare with")},
                              {"unit", string},
                              {"from", Described(number, "start of the window [s]")},
                              {"to", Described(number, "end of the window [s]")}});
  metric["required"] = {"name", "signal"};
  return {
      {"$schema", string},
      {"schemaVersion", {{"const", kDiagramSchemaVersion}}},
      {"name", string},
      {"description", string},
      {"notes", string},
      {"experiment",
       Described(StrictObject({{"mode", Described({{"enum", Names(kExperimentModeNames)}},
                                                  "how compare/fit run the model against a measurement")}}),
                 "how the diagram is compared with measurements")},
      {"defaultExperiment",
       StrictObject({{"startTime", Described(number, "[s]")},
                     {"stopTime", Described(number, "[s]")},
                     {"stepSize", Described({{"type", "number"}, {"exclusiveMinimum", 0}},
                                            "log interval [s] > 0; leave it out to log at the fastest discrete "
                                            "period (or every solver step)")}})},
      {"solver",
       StrictObject({{"type", {{"enum", Names(kSolverTypeNames)}}},
                     {"method", Described({{"enum", Names(kCvodeMethodNames)}}, "CVODE only")},
                     {"step", Described({{"type", "number"}, {"exclusiveMinimum", 0}}, "fixed-step solvers [s]")},
                     {"rtol", {{"type", "number"}, {"exclusiveMinimum", 0}}},
                     {"atol", {{"type", "number"}, {"exclusiveMinimum", 0}}},
                     {"maxStep", Described({{"type", "number"}, {"minimum", 0}}, "CVODE maximum step [s], 0 = none")}})},
      {"connectors", ArrayOf(connector)},
      {"elements", {{"type", "array"}, {"minItems", 1}, {"items", {{"$ref", "#/definitions/element"}}}}},
      {"connections",
       ArrayOf(StrictObject(
           {{"startElement", Described(string, "omit or \"\" for an input connector of the diagram")},
            {"startConnector",
             {{"type", "string"},
              {"description", "an output port of startElement (its type's ports: motionblocks blocks TYPE) or an "
                              "input connector's name; always given, even for a block of one output"},
              {"examples", PortNames(registry, false)}}},
            {"endElement", Described(string, "omit or \"\" for an output connector of the diagram")},
            {"endConnector",
             {{"type", "string"},
              {"description", "an input port of endElement (its type's ports: motionblocks blocks TYPE) or an "
                              "output connector's name; always given, even for a block of one input"},
              {"examples", PortNames(registry, true)}}}}))},
      {"log", ArrayOf(Described(string, "element.port or a connector name"))},
      {"metrics", ArrayOf(metric)},
      {"free", Described({{"type", "array"}, {"items", string}, {"uniqueItems", true}},
                         "element.parameter names that compare and fit refit by default (each an element of the "
                         "diagram and one of its type's parameters)")},
      {"roles", Described({{"type", "object"}, {"additionalProperties", string}},
                          "role → element name, for analyses that find parts of the loop by role "
                          "(docs/engine.md)")},
      {"ui", {{"type", "object"}}}};
}

}  // namespace

json DiagramSchema(const BlockRegistry& registry) {
  json blocks = json::object();
  for (const auto& name : registry.TypeNames()) blocks[name] = BlockSchema(*registry.Find(name));
  blocks[kSubsystemType] = SubsystemSchema();
  return {{"$schema", "http://json-schema.org/draft-07/schema#"},
          {"title", "motionblocks diagram"},
          {"description",
           "Generated by `motionblocks schema` from the block registry. A block diagram in SSP's words (elements, "
           "connectors, connections, defaultExperiment) plus what SSP lacks: schemaVersion, per-element "
           "sampleTime, solver, log, metrics, experiment, free (docs/engine.md)."},
          {"type", "object"},
          {"required", {"schemaVersion", "elements"}},
          {"additionalProperties", false},
          {"properties", Sections(registry)},
          {"definitions", {{"element", ElementSchema(registry)}, {"blocks", blocks}}}};
}

}  // namespace mb

namespace mb {

namespace {

const JsonSchemaValidator& DiagramValidator() {
  static const JsonSchemaValidator validator(DiagramSchema(BlockRegistry::Global()));
  return validator;
}

/// Whether `pointer` lies in the parameters, sampleTime or type of an element whose "type" is a string (a
/// registered block's, or an unknown one): the loader checks those itself, with better words.
bool LeftToLoader(const json& diagram, const std::string& pointer) {
  const std::vector<std::string> tokens = PointerTokens(pointer);
  json::json_pointer element;
  for (std::size_t i = 0; i < tokens.size(); ++i) {
    if (i >= 2 && tokens[i - 2] == "elements" && (tokens[i] == "parameters" || tokens[i] == "sampleTime" ||
                                                  tokens[i] == "type")) {
      const json& e = diagram.at(element);
      if (e.is_object() && e.contains("type") && e["type"].is_string() && e["type"] != kSubsystemType) return true;
    }
    element /= tokens[i];
  }
  return false;
}

}  // namespace

std::vector<SchemaProblem> DiagramSchemaProblems(const json& diagram) {
  std::vector<SchemaProblem> out;
  for (auto& p : DiagramValidator().Validate(diagram)) {
    if (!LeftToLoader(diagram, p.pointer)) out.push_back(std::move(p));
  }
  return out;
}

}  // namespace mb

#include "tools/suggest.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

#include <fmt/format.h>

#include "models/diagnosis/effect_registry.h"

namespace mb {

using nlohmann::json;

bool HasEffectBlock(const std::string& effect) {
  const EffectType* type = EffectRegistry::Global().Find(effect);
  return type && type->block;
}

namespace {

std::string InputConnectorWithUnit(const json& diagram, const std::vector<std::string>& units) {
  for (const auto& c : diagram.value("connectors", json::array())) {
    if (c.value("kind", "") != "input") continue;
    const std::string unit = c.value("unit", "");
    if (std::find(units.begin(), units.end(), unit) != units.end()) return c.value("name", "");
  }
  return {};
}

// The input connector carrying position ("m"), velocity ("m/s") or acceleration ("m/s^2"); throws naming what to add.
std::string NeedInput(const json& diagram, MotionInput input, const std::string& effect) {
  std::string quantity;
  std::vector<std::string> units;
  switch (input) {
    case MotionInput::kPosition: quantity = "position"; units = {"m"}; break;
    case MotionInput::kVelocity: quantity = "velocity"; units = {"m/s"}; break;
    case MotionInput::kAcceleration: quantity = "acceleration"; units = {"m/s^2", "m/s²", "m/s2"}; break;
  }
  const std::string name = InputConnectorWithUnit(diagram, units);
  if (name.empty()) {
    throw std::invalid_argument(fmt::format("effect '{}' needs the {}: add an input connector with unit \"{}\"",
                                            effect, quantity, units.front()));
  }
  return name;
}

std::string UniqueName(const json& diagram, const std::string& base) {
  std::string name = base;
  for (int k = 2;; ++k) {
    bool taken = false;
    for (const auto& e : diagram["elements"]) taken = taken || e.value("name", "") == name;
    if (!taken) return name;
    name = fmt::format("{}_{}", base, k);
  }
}

// Index of the connection that feeds the output connector `output`.
std::size_t FeedOf(const json& diagram, const std::string& output) {
  std::optional<std::size_t> feed;
  for (std::size_t k = 0; k < diagram["connections"].size(); ++k) {
    const json& c = diagram["connections"][k];
    if (c.value("endElement", "") == "" && c.value("endConnector", "") == output) feed = k;
  }
  if (!feed) throw std::invalid_argument(fmt::format("the diagram has no connection into output '{}'", output));
  return *feed;
}

// Adds `element` (output port `port`) to the signal feeding output connector `output`, through a new sum.
void AddToOutput(json* out, const json& element, const std::string& output, const std::string& port = "y") {
  const std::size_t feed = FeedOf(*out, output);
  const std::string name = element.at("name");
  const std::string sum_name = UniqueName(*out, "with_" + name);
  out->at("elements").push_back(element);
  (*out)["elements"].push_back({{"name", sum_name}, {"type", "sum"}, {"parameters", {{"signs", "++"}}}});
  const json previous = (*out)["connections"][feed];
  (*out)["connections"].push_back({{"startElement", previous.value("startElement", "")},
                                   {"startConnector", previous.value("startConnector", "")},
                                   {"endElement", sum_name},
                                   {"endConnector", "u1"}});
  (*out)["connections"].push_back(
      {{"startElement", name}, {"startConnector", port}, {"endElement", sum_name}, {"endConnector", "u2"}});
  (*out)["connections"][feed]["startElement"] = sum_name;
  (*out)["connections"][feed]["startConnector"] = "y";
}

// Puts `element` (ports "u" → "y") between the signal feeding output connector `output` and the connector.
void InsertBeforeOutput(json* out, const json& element, const std::string& output) {
  const std::size_t feed = FeedOf(*out, output);
  const std::string name = element.at("name");
  out->at("elements").push_back(element);
  const json previous = (*out)["connections"][feed];
  (*out)["connections"].push_back({{"startElement", previous.value("startElement", "")},
                                   {"startConnector", previous.value("startConnector", "")},
                                   {"endElement", name},
                                   {"endConnector", "u"}});
  (*out)["connections"][feed]["startElement"] = name;
  (*out)["connections"][feed]["startConnector"] = "y";
}

void Wire(json* out, const std::string& connector, const std::string& element, const std::string& port) {
  (*out)["connections"].push_back(
      {{"startElement", ""}, {"startConnector", connector}, {"endElement", element}, {"endConnector", port}});
}

// The diagram's time step: the solver's fixed step, else the default experiment's step size.
double DiagramStep(const json& diagram, const std::string& effect, const std::string& block) {
  const double solver = diagram.value("solver", json::object()).value("step", 0.0);
  if (solver > 0.0) return solver;
  const double experiment = diagram.value("defaultExperiment", json::object()).value("stepSize", 0.0);
  if (experiment > 0.0) return experiment;
  throw std::invalid_argument(fmt::format(
      "effect '{}' needs the diagram's sample period for its {} block: set solver.step or "
      "defaultExperiment.stepSize",
      effect, block));
}

}  // namespace

json SuggestAmendedDiagram(const json& diagram, const DiagnosedEffect& effect, const std::string& output) {
  const EffectType& type = LookupEffect(effect.effect);
  if (!type.block) {
    throw std::invalid_argument(
        fmt::format("no block for effect '{}' yet: add it by hand (docs/diagnosis.md)", effect.effect));
  }
  const EffectBlockTemplate& block = *type.block;
  json out = diagram;
  std::vector<std::string> inputs;
  for (const auto& [input, port] : block.inputs) inputs.push_back(NeedInput(out, input, effect.effect));
  json element = {{"name", UniqueName(out, block.element_name)},
                  {"type", block.block_type},
                  {"description", effect.description},
                  {"parameters", block.parameters(effect)}};
  if (block.discrete) element["sampleTime"] = {DiagramStep(out, effect.effect, block.element_name), 0.0};
  const std::string name = element["name"];
  if (block.placement == BlockPlacement::kInsertBeforeOutput) {
    InsertBeforeOutput(&out, element, output);
  } else {
    AddToOutput(&out, element, output, block.output_port);
  }
  for (std::size_t k = 0; k < inputs.size(); ++k) Wire(&out, inputs[k], name, block.inputs[k].second);
  for (const auto& f : block.free) out["free"].push_back(name + "." + f);
  out["notes"] = out.value("notes", std::string()) +
                 fmt::format(" Amended by motionblocks compare --suggest: added '{}' ({}).", name, effect.effect);
  return out;
}

json SuggestGprFallbackBlock(const json& diagram, const std::string& model_path, const std::string& output) {
  json out = diagram;
  const std::string position = NeedInput(out, MotionInput::kPosition, "nonparametric_fallback");
  const std::string velocity = NeedInput(out, MotionInput::kVelocity, "nonparametric_fallback");
  const std::string name = UniqueName(out, "residual_gp");
  AddToOutput(&out,
              {{"name", name},
               {"type", "gpr"},
               {"description", "TISO-GPR on (x, v) learned from what the catalogue's effects leave of the residual"},
               {"parameters", {{"model", model_path}}}},
              output, "mean");
  Wire(&out, position, name, "x");
  Wire(&out, velocity, name, "xdot");
  out["description"] = out.value("description", std::string()) +
                       fmt::format(" Amended by motionblocks compare --suggest: added '{}' (non-parametric fallback).",
                                   name);
  return out;
}

}  // namespace mb

#include "tools/suggest.h"

#include <cmath>
#include <optional>
#include <stdexcept>

#include <fmt/format.h>

namespace mb {

using nlohmann::json;

// A velocity-dependent ripple gets the plain position_periodic block at its period for now (constant
// amplitude, harmonics refit): the |v| scaling is not a block yet.
bool HasEffectBlock(const std::string& effect) {
  return effect == "position_periodic" || effect == "velocity_dependent_ripple";
}

namespace {

std::string InputConnectorWithUnit(const json& diagram, const std::string& unit) {
  for (const auto& c : diagram.value("connectors", json::array())) {
    if (c.value("kind", "") == "input" && c.value("unit", "") == unit) return c.value("name", "");
  }
  return {};
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

}  // namespace

json SuggestAmendedDiagram(const json& diagram, const DiagnosedEffect& effect, const std::string& output) {
  if (!HasEffectBlock(effect.effect)) {
    throw std::invalid_argument(fmt::format("no block for effect '{}' yet: add it by hand (docs/diagnosis.md)",
                                            effect.effect));
  }
  json out = diagram;
  const std::string position = InputConnectorWithUnit(out, "m");
  if (position.empty()) {
    throw std::invalid_argument(fmt::format("effect '{}' needs the position: add an input connector with unit \"m\"",
                                            effect.effect));
  }
  // Find the connection that feeds the output connector; route it through a sum with the effect.
  // An index, not a pointer: the connections array grows below.
  std::optional<std::size_t> feed;
  for (std::size_t k = 0; k < out["connections"].size(); ++k) {
    const json& c = out["connections"][k];
    if (c.value("endElement", "") == "" && c.value("endConnector", "") == output) feed = k;
  }
  if (!feed) throw std::invalid_argument(fmt::format("the diagram has no connection into output '{}'", output));

  const std::string effect_name = UniqueName(out, "ripple");
  const std::string sum_name = UniqueName(out, "with_" + effect_name);
  const double period = effect.parameters.count("period") ? effect.parameters.at("period") : 0.0;
  const int harmonics = effect.parameters.count("harmonics") ? static_cast<int>(effect.parameters.at("harmonics")) : 3;
  const bool same_columns = effect.effect == "position_periodic";  // else start the coefficients at zero
  if (!(period > 0.0)) throw std::invalid_argument("position_periodic without a period: cannot suggest a block");
  // Initial coefficients from the diagnosis' joint fit (columns cos1, sin1, cos2, …).
  json cos_c = json::array(), sin_c = json::array();
  for (int h = 1; h <= harmonics; ++h) {
    double a = 0.0, b = 0.0;
    for (std::size_t k = 0; k < effect.column_names.size(); ++k) {
      const auto& name = effect.column_names[k];
      const double value = same_columns ? effect.coefficients(static_cast<Eigen::Index>(k)) : 0.0;
      if (name.ends_with(fmt::format(".cos{}", h))) a = value;
      if (name.ends_with(fmt::format(".sin{}", h))) b = value;
    }
    cos_c.push_back(a);
    sin_c.push_back(b);
  }
  out["elements"].push_back({{"name", effect_name},
                             {"type", "position_periodic"},
                             {"description", effect.description},
                             {"parameters",
                              {{"period", {{"value", period}, {"unit", "m"}}},
                               {"harmonics", harmonics},
                               {"cos_coefficients", cos_c},
                               {"sin_coefficients", sin_c}}}});
  out["elements"].push_back({{"name", sum_name}, {"type", "sum"}, {"parameters", {{"signs", "++"}}}});
  const json previous = out["connections"][*feed];
  out["connections"].push_back({{"startElement", previous.value("startElement", "")},
                                {"startConnector", previous.value("startConnector", "")},
                                {"endElement", sum_name},
                                {"endConnector", "u1"}});
  out["connections"].push_back(
      {{"startElement", effect_name}, {"startConnector", "y"}, {"endElement", sum_name}, {"endConnector", "u2"}});
  out["connections"].push_back(
      {{"startElement", ""}, {"startConnector", position}, {"endElement", effect_name}, {"endConnector", "x"}});
  out["connections"][*feed]["startElement"] = sum_name;
  out["connections"][*feed]["startConnector"] = "y";
  out["free"].push_back(effect_name + ".cos_coefficients");
  out["free"].push_back(effect_name + ".sin_coefficients");
  out["notes"] = out.value("notes", std::string()) +
                 fmt::format(" Amended by motionblocks compare --suggest: added '{}' ({}).", effect_name, effect.effect);
  return out;
}

}  // namespace mb

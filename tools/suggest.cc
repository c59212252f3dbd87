#include "tools/suggest.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

#include <fmt/format.h>

namespace mb {

using nlohmann::json;

// asymmetric_friction has no block on purpose: with a free offset and Coulomb friction it is the same regressor
// (1[v > 0] = (1 + sign v)/2 wherever the axis moves), so refitting those is the fix.
bool HasEffectBlock(const std::string& effect) {
  static const std::vector<std::string> kWithBlock{
      "position_periodic", "velocity_dependent_ripple", "time_periodic",    "time_delay",      "mass_mismatch",
      "stribeck_friction", "viscous_friction",          "coulomb_friction", "constant_offset", "resonance",
      "quantization"};
  return std::find(kWithBlock.begin(), kWithBlock.end(), effect) != kWithBlock.end();
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
std::string NeedInput(const json& diagram, const std::string& quantity, const std::string& effect) {
  std::vector<std::string> units;
  if (quantity == "position") units = {"m"};
  if (quantity == "velocity") units = {"m/s"};
  if (quantity == "acceleration") units = {"m/s^2", "m/s²", "m/s2"};
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

// The diagnosis' coefficient of column "<effect>.<suffix>" (0 if absent).
double Coefficient(const DiagnosedEffect& effect, const std::string& suffix) {
  for (std::size_t k = 0; k < effect.column_names.size(); ++k) {
    const auto& name = effect.column_names[k];
    if (name == effect.effect ? suffix.empty() : name.ends_with("." + suffix)) {
      return effect.coefficients(static_cast<Eigen::Index>(k));
    }
  }
  return 0.0;
}

double Parameter(const DiagnosedEffect& effect, const std::string& name) {
  const auto it = effect.parameters.find(name);
  if (it == effect.parameters.end() || !std::isfinite(it->second)) {
    throw std::invalid_argument(fmt::format("effect '{}' without a '{}': cannot suggest a block", effect.effect, name));
  }
  return it->second;
}

// Harmonic coefficients a_h (cos) and b_h (sin), h = 1..harmonics, from the diagnosis' columns.
void HarmonicCoefficients(const DiagnosedEffect& effect, int harmonics, json* cos_c, json* sin_c) {
  *cos_c = json::array();
  *sin_c = json::array();
  for (int h = 1; h <= harmonics; ++h) {
    cos_c->push_back(Coefficient(effect, fmt::format("cos{}", h)));
    sin_c->push_back(Coefficient(effect, fmt::format("sin{}", h)));
  }
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
double DiagramStep(const json& diagram) {
  const double solver = diagram.value("solver", json::object()).value("step", 0.0);
  if (solver > 0.0) return solver;
  const double experiment = diagram.value("defaultExperiment", json::object()).value("stepSize", 0.0);
  if (experiment > 0.0) return experiment;
  throw std::invalid_argument(
      "effect 'time_delay' needs the diagram's sample period for its delay block: set solver.step or "
      "defaultExperiment.stepSize");
}

}  // namespace

json SuggestAmendedDiagram(const json& diagram, const DiagnosedEffect& effect, const std::string& output) {
  const std::string& kind = effect.effect;
  if (!HasEffectBlock(kind)) {
    throw std::invalid_argument(fmt::format("no block for effect '{}' yet: add it by hand (docs/diagnosis.md)", kind));
  }
  json out = diagram;
  std::vector<std::string> free;
  std::string name;
  if (kind == "position_periodic" || kind == "velocity_dependent_ripple") {
    const std::string position = NeedInput(out, "position", kind);
    const double period = Parameter(effect, "period");
    if (!(period > 0.0)) throw std::invalid_argument(fmt::format("{} without a period: cannot suggest a block", kind));
    const bool scaled = kind == "velocity_dependent_ripple";
    const int harmonics = effect.parameters.count("harmonics") ? static_cast<int>(effect.parameters.at("harmonics"))
                                                               : (scaled ? 1 : 3);
    json cos_c, sin_c;
    HarmonicCoefficients(effect, harmonics, &cos_c, &sin_c);
    name = UniqueName(out, "ripple");
    AddToOutput(&out,
                {{"name", name},
                 {"type", kind},
                 {"description", effect.description},
                 {"parameters",
                  {{"period", {{"value", period}, {"unit", "m"}}},
                   {"harmonics", harmonics},
                   {"cos_coefficients", cos_c},
                   {"sin_coefficients", sin_c}}}},
                output);
    Wire(&out, position, name, "x");
    if (scaled) Wire(&out, NeedInput(out, "velocity", kind), name, "v");
    free = {name + ".cos_coefficients", name + ".sin_coefficients"};
  } else if (kind == "time_periodic") {
    const int harmonics = effect.parameters.count("harmonics") ? static_cast<int>(effect.parameters.at("harmonics")) : 1;
    json cos_c, sin_c;
    HarmonicCoefficients(effect, harmonics, &cos_c, &sin_c);
    name = UniqueName(out, "vibration");
    AddToOutput(&out,
                {{"name", name},
                 {"type", "time_periodic"},
                 {"description", effect.description},
                 {"parameters",
                  {{"frequency_hz", {{"value", Parameter(effect, "frequency_hz")}, {"unit", "Hz"}}},
                   {"harmonics", harmonics},
                   {"cos_coefficients", cos_c},
                   {"sin_coefficients", sin_c}}}},
                output);
    // The frequency too: over a long record a small frequency error turns into a large phase error.
    free = {name + ".frequency_hz", name + ".cos_coefficients", name + ".sin_coefficients"};
  } else if (kind == "time_delay") {
    const double delay = Parameter(effect, "delay");
    if (delay < 0.0) {
      throw std::invalid_argument(fmt::format(
          "time_delay of {:.4g} ms is negative: the model lags the measurement (check the time stamps, or delay the "
          "measured inputs instead); a transport_delay block cannot advance the output",
          delay * 1e3));
    }
    const double ts = DiagramStep(out);
    name = UniqueName(out, "delay");
    InsertBeforeOutput(&out,
                       {{"name", name},
                        {"type", "transport_delay"},
                        {"description", effect.description},
                        {"sampleTime", {ts, 0.0}},
                        {"parameters", {{"delay", {{"value", delay}, {"unit", "s"}}}}}},
                       output);
    free = {name + ".delay"};
  } else if (kind == "mass_mismatch" || kind == "viscous_friction") {
    const bool mass = kind == "mass_mismatch";
    name = UniqueName(out, mass ? "payload" : "viscous_extra");
    AddToOutput(&out,
                {{"name", name},
                 {"type", "gain"},
                 {"description", effect.description},
                 {"parameters", {{"gain", Coefficient(effect, "")}}}},
                output);
    Wire(&out, NeedInput(out, mass ? "acceleration" : "velocity", kind), name, "u");
    free = {name + ".gain"};
  } else if (kind == "stribeck_friction" || kind == "coulomb_friction") {
    // A friction element of its own (slip model: the measured velocity drives it); the friction block needs
    // non-negative forces, so a negative coefficient starts from 1 mN (not 0: the fit's central differences
    // would step below the bound) and the fit moves it.
    const bool stribeck = kind == "stribeck_friction";
    const double level = std::max(1e-3, Coefficient(effect, ""));
    json parameters = {{"viscous", 0.0}, {"coulomb", stribeck ? 0.0 : level}, {"stick_model", "none"}};
    if (stribeck) {
      parameters["static"] = {{"value", level}, {"unit", "N"}};
      parameters["stribeck_velocity"] = {{"value", Parameter(effect, "stribeck_velocity")}, {"unit", "m/s"}};
    }
    name = UniqueName(out, stribeck ? "stribeck" : "coulomb_extra");
    AddToOutput(&out, {{"name", name}, {"type", "friction"}, {"description", effect.description}, {"parameters", parameters}},
                output, "f");
    Wire(&out, NeedInput(out, "velocity", kind), name, "v");
    free = stribeck ? std::vector<std::string>{name + ".static", name + ".stribeck_velocity"}
                    : std::vector<std::string>{name + ".coulomb"};
  } else if (kind == "resonance") {
    // The two-mass model seen from the motor (blocks/flexible_load.h): the diagnosis' regressors g and ġ/ω_r
    // are its terms, the coefficient of g its load mass. Mass, frequency and damping are refit: the
    // frequency from the spectrum is good to a fraction of a Welch bin, not of the mode's bandwidth.
    const double frequency = Parameter(effect, "frequency_hz");
    const double damping = Parameter(effect, "damping_ratio");
    if (!(frequency > 0.0) || !(damping > 0.0)) {
      throw std::invalid_argument(fmt::format(
          "resonance with frequency_hz = {} and damping_ratio = {}: both must be > 0 to suggest a block", frequency,
          damping));
    }
    const std::string acceleration = NeedInput(out, "acceleration", kind);
    name = UniqueName(out, "flexible_load");
    AddToOutput(&out,
                {{"name", name},
                 {"type", "flexible_load"},
                 {"description", effect.description},
                 {"parameters",
                  {{"mass", {{"value", Coefficient(effect, "response")}, {"unit", "kg"}}},
                   {"frequency_hz", {{"value", frequency}, {"unit", "Hz"}}},
                   {"damping_ratio", damping}}}},
                output, "f");
    Wire(&out, acceleration, name, "a");
    free = {name + ".mass", name + ".frequency_hz", name + ".damping_ratio"};
  } else if (kind == "quantization") {
    // The quantizer goes last, on the signal the output connector reads. Its step stays fixed (not free): the
    // least-squares cost is piecewise constant in q, so a Jacobian by finite differences carries no information
    // about it; the diagnosis finds q from the levels or the residual's periodicity in ŷ instead.
    const double step = Parameter(effect, "step");
    if (!(step > 0.0)) {
      throw std::invalid_argument(fmt::format("quantization with step {}: must be > 0 to suggest a block", step));
    }
    name = UniqueName(out, "output_quantizer");
    InsertBeforeOutput(&out,
                       {{"name", name},
                        {"type", "quantizer"},
                        {"description", effect.description},
                        {"parameters", {{"interval", step}}}},
                       output);
  } else {  // constant_offset
    name = UniqueName(out, "offset_extra");
    AddToOutput(&out,
                {{"name", name},
                 {"type", "constant"},
                 {"description", effect.description},
                 {"parameters", {{"value", Coefficient(effect, "")}}}},
                output);
    free = {name + ".value"};
  }
  for (const auto& f : free) out["free"].push_back(f);
  out["notes"] = out.value("notes", std::string()) +
                 fmt::format(" Amended by motionblocks compare --suggest: added '{}' ({}).", name, kind);
  return out;
}

json SuggestGprFallbackBlock(const json& diagram, const std::string& model_path, const std::string& output) {
  json out = diagram;
  const std::string position = NeedInput(out, "position", "nonparametric_fallback");
  const std::string velocity = NeedInput(out, "velocity", "nonparametric_fallback");
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

#include "tools/suggest.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>

#include <fmt/format.h>

#include "engine/diagram_document.h"

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

std::string InputConnectorWithUnit(const DiagramDocument& diagram, const std::vector<std::string>& units) {
  for (const auto& c : diagram.Connectors("input")) {
    if (std::find(units.begin(), units.end(), c.unit) != units.end()) return c.name;
  }
  return {};
}

// The input connector carrying position ("m"), velocity ("m/s") or acceleration ("m/s^2"); throws naming what to add.
std::string NeedInput(const DiagramDocument& diagram, const std::string& quantity, const std::string& effect) {
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

// A Fourier-series element: `parameters` (its period or frequency) plus the diagnosis' harmonic coefficients.
ElementSpec FourierElement(const std::string& name, const std::string& type, json parameters, int harmonics,
                           const DiagnosedEffect& effect) {
  json cos_c, sin_c;
  HarmonicCoefficients(effect, harmonics, &cos_c, &sin_c);
  parameters["harmonics"] = harmonics;
  parameters["cos_coefficients"] = cos_c;
  parameters["sin_coefficients"] = sin_c;
  return {name, type, parameters, std::nullopt, effect.description};
}

// Adds `element` (its one output) to the signal feeding output connector `output`, through a new sum named
// "with_<element>". Returns the element's name.
std::string AddToOutput(DiagramDocument* out, const ElementSpec& element, const std::string& output) {
  const std::string name = out->Add(element);
  out->SumInto({"", output}, {name, ""}, "with_" + name);
  return name;
}

// Puts `element` (one input, one output) between the signal feeding output connector `output` and the connector.
std::string InsertBeforeOutput(DiagramDocument* out, const ElementSpec& element, const std::string& output) {
  const std::string name = out->Add(element);
  out->InsertBefore({"", output}, name);
  return name;
}

void Wire(DiagramDocument* out, const std::string& connector, const std::string& element, const std::string& port) {
  out->Connect({"", connector}, {element, port});
}

// The diagram's time step: the solver's fixed step, else the default experiment's step size.
double DiagramStep(const DiagramDocument& diagram) {
  if (const auto step = diagram.SolverStep()) return *step;
  if (const auto step = diagram.ExperimentStepSize()) return *step;
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
  DiagramDocument out(diagram);
  std::vector<std::string> free;
  std::string name;
  if (kind == "position_periodic" || kind == "velocity_dependent_ripple") {
    const std::string position = NeedInput(out, "position", kind);
    const double period = Parameter(effect, "period");
    if (!(period > 0.0)) throw std::invalid_argument(fmt::format("{} without a period: cannot suggest a block", kind));
    const bool scaled = kind == "velocity_dependent_ripple";
    const int harmonics = effect.parameters.count("harmonics") ? static_cast<int>(effect.parameters.at("harmonics"))
                                                               : (scaled ? 1 : 3);
    name = AddToOutput(
        &out, FourierElement("ripple", kind, {{"period", {{"value", period}, {"unit", "m"}}}}, harmonics, effect),
        output);
    Wire(&out, position, name, "x");
    if (scaled) Wire(&out, NeedInput(out, "velocity", kind), name, "v");
    free = {name + ".cos_coefficients", name + ".sin_coefficients"};
  } else if (kind == "time_periodic") {
    const int harmonics = effect.parameters.count("harmonics") ? static_cast<int>(effect.parameters.at("harmonics")) : 1;
    name = AddToOutput(&out,
                       FourierElement("vibration", "time_periodic",
                                      {{"frequency_hz", {{"value", Parameter(effect, "frequency_hz")}, {"unit", "Hz"}}}},
                                      harmonics, effect),
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
    name = InsertBeforeOutput(&out,
                              {"delay",
                               "transport_delay",
                               {{"delay", {{"value", delay}, {"unit", "s"}}}},
                               std::pair{ts, 0.0},
                               effect.description},
                              output);
    free = {name + ".delay"};
  } else if (kind == "mass_mismatch" || kind == "viscous_friction") {
    const bool mass = kind == "mass_mismatch";
    name = AddToOutput(&out,
                       {mass ? "payload" : "viscous_extra",
                        "gain",
                        {{"gain", Coefficient(effect, "")}},
                        std::nullopt,
                        effect.description},
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
    name = AddToOutput(&out,
                       {stribeck ? "stribeck" : "coulomb_extra", "friction", parameters, std::nullopt,
                        effect.description},
                       output);
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
    name = AddToOutput(&out,
                       {"flexible_load",
                        "flexible_load",
                        {{"mass", {{"value", Coefficient(effect, "response")}, {"unit", "kg"}}},
                         {"frequency_hz", {{"value", frequency}, {"unit", "Hz"}}},
                         {"damping_ratio", damping}},
                        std::nullopt,
                        effect.description},
                       output);
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
    name = InsertBeforeOutput(
        &out, {"output_quantizer", "quantizer", {{"interval", step}}, std::nullopt, effect.description}, output);
  } else {  // constant_offset
    name = AddToOutput(
        &out, {"offset_extra", "constant", {{"value", Coefficient(effect, "")}}, std::nullopt, effect.description},
        output);
    free = {name + ".value"};
  }
  for (const auto& f : free) out.AddFreeParameter(f);
  out.AppendNote(fmt::format(" Amended by motionblocks compare --suggest: added '{}' ({}).", name, kind));
  return out.json();
}

json SuggestGprFallbackBlock(const json& diagram, const std::string& model_path, const std::string& output) {
  DiagramDocument out(diagram);
  const std::string position = NeedInput(out, "position", "nonparametric_fallback");
  const std::string velocity = NeedInput(out, "velocity", "nonparametric_fallback");
  const std::string name = AddToOutput(
      &out,
      {"residual_gp", "gpr", {{"model", model_path}}, std::nullopt,
       "TISO-GPR on (x, v) learned from what the catalogue's effects leave of the residual"},
      output);
  Wire(&out, position, name, "x");
  Wire(&out, velocity, name, "xdot");
  out.AppendDescription(
      fmt::format(" Amended by motionblocks compare --suggest: added '{}' (non-parametric fallback).", name));
  return out.json();
}

}  // namespace mb

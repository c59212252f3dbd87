#include "tools/workflow/suggest.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <memory>
#include <optional>
#include <stdexcept>
#include <tuple>
#include <utility>

#include <fmt/format.h>

#include "engine/block_roles.h"
#include "engine/diagram_document.h"
#include "engine/registry.h"
#include "engine/units.h"
#include "models/diagnosis/amplitude_factor.h"
#include "models/diagnosis/effect_block.h"
#include "models/diagnosis/effect_registry.h"
#include "tools/workflow/loop_probe.h"

namespace mb {

using nlohmann::json;

bool HasEffectBlock(const std::string& effect) {
  const EffectType* type = EffectRegistry::Global().Find(effect);
  return type && BlockFor(*type);
}

bool IsFrictionLawReplacement(const DiagnosisResult& diagnosis, const std::string& effect) {
  return std::find(diagnosis.friction_law.begin(), diagnosis.friction_law.end(), effect) !=
         diagnosis.friction_law.end();
}

std::vector<const DiagnosedEffect*> EffectsInApplicationOrder(const DiagnosisResult& diagnosis) {
  std::vector<const DiagnosedEffect*> order;
  for (const auto& law : diagnosis.friction_law) {
    for (const auto& e : diagnosis.effects) {
      if (e.effect == law) order.push_back(&e);
    }
  }
  const std::size_t laws = order.size();
  for (const auto& e : diagnosis.effects) {
    if (!IsFrictionLawReplacement(diagnosis, e.effect)) order.push_back(&e);
  }
  std::stable_sort(order.begin() + static_cast<std::ptrdiff_t>(laws), order.end(),
                   [](const DiagnosedEffect* a, const DiagnosedEffect* b) {
                     return a->selection_order < b->selection_order;
                   });
  return order;
}

namespace {

// The input connector carrying position, velocity or acceleration (linear or rotary units, engine/units.h); throws
// naming what to add.
std::string NeedInput(const DiagramDocument& diagram, MotionInput input, const std::string& effect) {
  const auto [quantity, wanted, example] = [&]() -> std::tuple<std::string, MotionQuantity, std::string> {
    switch (input) {
      case MotionInput::kPosition: return {"position", MotionQuantity::kPosition, "m"};
      case MotionInput::kVelocity: return {"velocity", MotionQuantity::kVelocity, "m/s"};
      case MotionInput::kAcceleration: break;
    }
    return {"acceleration", MotionQuantity::kAcceleration, "m/s^2"};
  }();
  for (const auto& c : diagram.Connectors("input")) {
    if (c.Quantity() == wanted) return c.name;
  }
  throw std::invalid_argument(fmt::format(
      "effect '{}' needs the {}: add an input connector with unit \"{}\" (or rad, rev, deg), or one in another unit "
      "that declares \"quantity\": \"{}\"",
      effect, quantity, example, quantity));
}

// Where an effect's block reads the motion: the input connector carrying it (equation-error mode: the measured
// motion), or in simulation mode the plant's own output "x" or "v" (the simulated motion; tools/workflow/loop_probe.h's
// PlantElement). A block of the acceleration in simulation mode would close an algebraic loop through the plant: throws,
// saying what to do instead.
Endpoint MotionSource(const DiagramDocument& diagram, MotionInput input, const std::string& effect) {
  if (diagram.Mode() == ExperimentMode::kEquationError) return {"", NeedInput(diagram, input, effect)};
  std::string why;
  const std::optional<std::string> plant = PlantElement(diagram, &why);
  if (!plant) throw std::invalid_argument(fmt::format("effect '{}' in simulation mode: {}", effect, why));
  switch (input) {
    case MotionInput::kPosition: return {*plant, "x"};
    case MotionInput::kVelocity: return {*plant, "v"};
    case MotionInput::kAcceleration: break;
  }
  throw std::invalid_argument(fmt::format(
      "effect '{}' multiplies the acceleration: in simulation mode a block of the plant's acceleration would feed the "
      "force that sets it (an algebraic loop); a mass goes to the plant's mass input (rigid_body's mass_input)",
      effect));
}

// Whether blocks of `type` are what effects insert between the model and its output (placement kInsertBeforeOutput:
// the measurement chain — a logger's delay, a quantizer), as the registry's block templates say.
bool IsMeasurementChainBlock(const std::string& type) {
  for (const auto& name : EffectNames()) {
    const EffectType& t = LookupEffect(name);
    if (t.block && t.block->placement == BlockPlacement::kInsertBeforeOutput && t.block->block_type == type) {
      return true;
    }
  }
  return false;
}

// Where a force is added: the output connector, or, when a measurement chain was inserted before it, that chain's
// input — a force found after a delay is logged through the same delay as the rest of the model's force (on the
// independent delay log a Coulomb law summed after the delay block left 1.1 N against a 0.45 N floor).
Endpoint ForceEnd(const DiagramDocument& d, const std::string& output) {
  if (d.Mode() != ExperimentMode::kEquationError) {  // the output is the motion: the force acts on the plant
    std::string why;
    if (const std::optional<Endpoint> port = PlantForcePort(d, &why)) return *port;
    throw std::invalid_argument(fmt::format("in simulation mode an effect's force acts on the plant, but {}", why));
  }
  Endpoint end{"", output};
  for (std::size_t guard = 0; guard < d.ElementNames().size(); ++guard) {
    const auto driver = d.DriverOf(end);
    if (!driver || driver->is_connector() || !IsMeasurementChainBlock(d.TypeOf(driver->element))) break;
    std::optional<Endpoint> input;
    for (const auto& c : d.Connections()) {
      if (c.end.element == driver->element) input = c.end;
    }
    if (!input) break;
    end = *input;
  }
  return end;
}

// Adds `element` (its output port `port`) to the model's force feeding output connector `output` (ForceEnd), through
// a new sum named "with_<element>". Returns the element's name.
std::string AddToOutput(DiagramDocument* out, const ElementSpec& element, const std::string& output,
                        const std::string& port) {
  const std::string name = out->Add(element);
  if (out->Mode() == ExperimentMode::kEquationError) {
    out->SumInto(ForceEnd(*out, output), {name, port}, "with_" + name);
  } else {
    // The effect's force is a load (what the drive must supply beyond the model's: its equation-error sign), and the
    // plant's input is the force that drives it.
    out->SubtractInto(ForceEnd(*out, output), {name, port}, "with_" + name);
  }
  return name;
}

// Puts `element` (one input, one output) between the signal feeding output connector `output` and the connector.
std::string InsertBeforeOutput(DiagramDocument* out, const ElementSpec& element, const std::string& output) {
  const std::string name = out->Add(element);
  out->InsertBefore({"", output}, name);
  return name;
}

// The input connector that reads the logged command compared at output connector `output` (the same measured column),
// added as "logged_<output>" when the diagram has none.
std::string CommandInput(DiagramDocument* out, const std::string& output) {
  std::optional<DocumentConnector> compared;
  for (const auto& c : out->Connectors("output")) {
    if (c.name == output) compared = c;
  }
  if (!compared) throw std::invalid_argument(fmt::format("the diagram has no output connector '{}'", output));
  for (const auto& c : out->Connectors("input")) {
    if (c.measurement == compared->measurement) return c.name;
  }
  const DocumentConnector command{out->UniqueConnectorName("logged_" + output), "input", compared->unit,
                                  compared->measurement, compared->quantity};
  out->AddConnector(command);
  return command.name;
}

// The input connector that reads log column `column` (an effect's DiagnosedEffect::log_column), added when the diagram
// has none: named after the column (characters other than letters, digits and '_' as '_'), in the column's own unit.
std::string ColumnInput(DiagramDocument* out, const std::string& column, const std::string& effect) {
  if (column.empty()) {
    throw std::invalid_argument(fmt::format("effect '{}' names no log column: cannot suggest its block", effect));
  }
  for (const auto& c : out->Connectors("input")) {
    if (c.measurement == column) return c.name;
  }
  std::string wish = column;
  for (char& ch : wish) {
    if (!std::isalnum(static_cast<unsigned char>(ch)) && ch != '_') ch = '_';
  }
  const DocumentConnector connector{out->UniqueConnectorName(wish), "input", "", column, ""};
  out->AddConnector(connector);
  return connector.name;
}

// Puts `element` (ports u → y) on the command path (BlockPlacement::kOnCommand). Equation-error mode: fed by the logged
// command, and what the log holds beyond what the element passes on, u − y, summed into the model's force (ForceEnd).
// Simulation mode: after the drive's force `drive_force` (DiagnosedComparison::drive_force_source), so that every block
// it fed reads what the element passes on (DiagramDocument::InsertAfter; a compared output keeps the command).
std::string AddOnCommand(DiagramDocument* out, const ElementSpec& element, const std::string& output,
                         const std::string& effect, const std::optional<Endpoint>& drive_force) {
  if (out->Mode() != ExperimentMode::kEquationError) {
    if (!drive_force || !out->Has(drive_force->element)) {
      throw std::invalid_argument(fmt::format(
          "effect '{}' acts on the command path, but this closed loop does not show the drive's force: compare the "
          "drive's force as an output in N (an output connector fed by the controller's force), or log its command "
          "in N, or put a {} block between the controller and the plant by hand",
          effect, element.type));
    }
    const std::string name = out->Add(element);
    out->InsertAfter(*drive_force, name);
    return name;
  }
  const std::string command = CommandInput(out, output);
  const std::string name = out->Add(element);
  out->Connect({"", command}, {name, "u"});
  const std::string excess = out->AddDifference({"", command}, {name, "y"}, "beyond_" + name);
  out->SumInto(ForceEnd(*out, output), out->OutputOf(excess), "with_" + name);
  return name;
}

void Wire(DiagramDocument* out, const std::string& connector, const std::string& element, const std::string& port) {
  out->Connect({"", connector}, {element, port});
}

// The model's force (the factor of_model_force multiplies by): in equation-error mode the force feeding output
// connector `output`, in simulation mode the drive's force `drive_force` (DiagnosedComparison::drive_force_source);
// throws naming the effect when there is none.
Endpoint ModelForceEnd(const DiagramDocument& out, const std::string& output, const DiagnosedEffect& effect,
                       const std::optional<Endpoint>& drive_force) {
  if (out.Mode() != ExperimentMode::kEquationError) {
    if (drive_force && out.Has(drive_force->element)) return *drive_force;
    throw std::invalid_argument(fmt::format(
        "effect '{}' multiplies the model's drive force, which this closed loop does not show: compare the drive's "
        "force as an output in N (an output connector fed by the controller's force), or log its command in N",
        effect.effect));
  }
  const auto force = out.DriverOf(ForceEnd(out, output));
  if (!force) {
    throw std::invalid_argument(fmt::format("effect '{}' multiplies the model's force, but nothing feeds output '{}'",
                                            effect.effect, output));
  }
  return *force;
}

// The factor that multiplies element `name` (EffectBlockTemplate::multiplier): its source — the input connector, or the
// model's force `force` (taken before the element was summed in) — itself or through a new element "<name>_<block
// type>" reading it, times its second factor through a product element "<name>_factor" when it has one. `factor_name`
// gets what the product's description calls it.
Endpoint Factor(DiagramDocument* out, const MotionMultiplier& multiplier, const DiagnosedEffect& effect,
                const std::string& name, const std::optional<Endpoint>& force, std::string* factor_name) {
  if (multiplier.one) {
    const std::string one = out->Add({name + "_one", "constant", {{"value", 1.0}}, std::nullopt,
                                      fmt::format("the factor 1 that '{}' schedules in time", name)});
    *factor_name = "one";
    return out->OutputOf(one);
  }
  Endpoint source;
  if (multiplier.clock || multiplier.amplitude_column) {  // a third factor's source less its origin z₀
    if (multiplier.clock) {
      source = out->OutputOf(out->Add({name + "_clock", "clock", json::object(), std::nullopt,
                                       fmt::format("the time that the amplitude of '{}' drifts with", name)}));
      *factor_name = "time";
    } else {
      source = {"", ColumnInput(out, effect.amplitude_column, effect.effect)};
      *factor_name = source.port;
    }
    const auto origin = effect.parameters.find(kAmplitudeOrigin);
    if (origin == effect.parameters.end()) {
      throw std::invalid_argument(fmt::format("effect '{}': its third factor has no origin", effect.effect));
    }
    const std::string z0 = out->Add({name + "_origin", "constant", {{"value", origin->second}}, std::nullopt,
                                     fmt::format("where the amplitude of '{}' is as diagnosed", name)});
    source = out->OutputOf(out->AddDifference(source, out->OutputOf(z0), name + "_" + *factor_name + "_from_origin"));
  } else if (multiplier.of_model_force) {
    source = *force;
    *factor_name = "force";
  } else {
    source = MotionSource(*out, multiplier.input, effect.effect);
    *factor_name = source.is_connector() ? source.port : source.element + "_" + source.port;
  }
  Endpoint factor = source;
  if (!multiplier.block_type.empty()) {
    const std::string element = out->Add({name + "_" + multiplier.block_type, multiplier.block_type,
                                          multiplier.parameters(effect), std::nullopt,
                                          fmt::format("a factor of the motion that multiplies '{}'", name)});
    out->Connect(source, {element, "u"});
    for (const std::string& parameter : multiplier.free) out->AddFreeParameter(element + "." + parameter);
    *factor_name = multiplier.block_type;
    factor = out->OutputOf(element);
  }
  if (!multiplier.times) return factor;
  std::string second_name;
  const Endpoint second = Factor(out, *multiplier.times, effect, name, force, &second_name);
  const std::string product = out->Add({name + "_factor", "product", json::object(), std::nullopt,
                                        fmt::format("the factor that multiplies '{}': {} × {}", name, *factor_name,
                                                    second_name)});
  out->Connect(factor, {product, "u1"});
  out->Connect(second, {product, "u2"});
  *factor_name += "_" + second_name;
  return out->OutputOf(product);
}

// Adds `element` times a factor (EffectBlockTemplate::multiplier) to the model's force feeding output connector
// `output`: a product element "<element>_times_<factor>" multiplies the element's output and the factor (Factor) and
// is summed in. Returns the element's name.
std::string AddProductToOutput(DiagramDocument* out, const ElementSpec& element, const MotionMultiplier& multiplier,
                               const DiagnosedEffect& effect, const std::string& output, const std::string& port,
                               const std::optional<Endpoint>& force) {
  const std::string name = out->Add(element);
  std::string factor_name;
  const Endpoint factor = Factor(out, multiplier, effect, name, force, &factor_name);
  const std::string product = AddToOutput(
      out, {name + "_times_" + factor_name, "product", json::object(), std::nullopt,
            fmt::format("'{}' × {} ({})", name,
                        factor_name == "force" ? std::string("the model's force") : "'" + factor_name + "'",
                        effect.effect)},
      output, "y");
  out->Connect({name, port}, {product, "u1"});
  out->Connect(factor, {product, "u2"});
  return name;
}

// Whether `multiplier` scales the drive's force in this diagram: its first factor is the model's force ŷ itself (a
// force constant k(z)·ŷ, its saturation k(z)·ŷ·|ŷ|, a friction growing with the transmitted force
// ŷ·sign(ŷ)·tanh(v/v_s)) and the diagram is compared in equation-error mode, where the output is the drive's force that
// the log holds rather than the force that moves the body.
bool ScalesTheDriveForce(const DiagramDocument& out, const MotionMultiplier& multiplier) {
  return out.Mode() == ExperimentMode::kEquationError && multiplier.of_model_force && multiplier.block_type.empty();
}

// How many times `multiplier` reads the model's force's size: ŷ and |ŷ| count 1, sign(ŷ) 0 (|ŷ|·tanh(v/v_s) as
// ŷ × sign(ŷ)·tanh(v/v_s) is ŷ times a factor of degree 0).
int ForceDegree(const MotionMultiplier& multiplier) {
  return (multiplier.of_model_force && multiplier.block_type != "sign" ? 1 : 0) +
         (multiplier.times ? ForceDegree(*multiplier.times) : 0);
}

// The share r of the drive's force u where it grows with the force's size, r = ρ·|u| (the iron saturating), from the
// share read on the model's force, r̂ = ρ·|ŷ|: u·(1 − ρ·|u|) = ŷ is a quadratic in |u| whose root gives
// r = (1 − √(1 − 4r̂))/2 exactly (the Catalan series r̂ + r̂² + 2r̂³ + …). Read on ŷ as it is, r̂ leaves O(r̂²) of ŷ, which
// kept grammar seeds 27 and 29 at 2.4 and 1.3 × their floor. Beyond r̂ = 1/4 the quadratic has no root: ŷ = 1/(4ρ) is
// the most force such a motor gives, and r stays at its 1/2 (blocks/sqrt.h holds √ at 0 there).
Endpoint ShareAtTheDriveForce(DiagramDocument* out, const Endpoint& share_on_model_force, const std::string& unity,
                              const std::string& name) {
  const std::string four = out->Add({name + "_share_times_4", "gain", {{"gain", 4.0}}, std::nullopt,
                                     fmt::format("4 × the share of the model's force that '{}' is", name)});
  out->Connect(share_on_model_force, {four, "u"});
  const std::string discriminant =
      out->AddDifference(out->OutputOf(unity), out->OutputOf(four), name + "_share_discriminant");
  const std::string root = out->Add({name + "_share_root", "sqrt", json::object(), std::nullopt,
                                     fmt::format("√(1 − 4 r̂), r̂ the share of the model's force that '{}' is", name)});
  out->Connect(out->OutputOf(discriminant), {root, "u"});
  const std::string twice =
      out->AddDifference(out->OutputOf(unity), out->OutputOf(root), name + "_twice_share_at_drive_force");
  const std::string half = out->Add({name + "_share_at_drive_force", "gain", {{"gain", 0.5}}, std::nullopt,
                                     fmt::format("the share of the drive's force that '{}' is: (1 − √(1 − 4 r̂))/2",
                                                 name)});
  out->Connect(out->OutputOf(twice), {half, "u"});
  return out->OutputOf(half);
}

// Adds `element` as a share r of the drive's force (ScalesTheDriveForce): r is the element's output (fed 1 on
// `factor_port`, a gain scheduled in time) times the multiplier's other factors, read on ŷ. The drive's force u moves
// the body by u·(1 − r) = ŷ, so the log holds u = ŷ/(1 − r): ŷ·r/(1 − r) is summed into the output through a product
// "<element>_of_drive_force" (ops "**/"). The diagnosis' regressor ŷ·r is its first order; summed in as it is, a force
// constant 30 % off leaves 0.3² = 9 % of ŷ, many times a record's noise floor. Where r reads the force's size (the iron
// saturating, r = ρ·|u|), r̂ read on ŷ is taken to the share at u in closed form (ShareAtTheDriveForce; a second
// fixed-point step, r read on ŷ/(1 − r̂), had let a joint refit run into 1 − r = 0 on grammar seed 40). r is limited to
// ±90 %. Returns the element's name.
std::string AddDriveForceShare(DiagramDocument* out, const ElementSpec& element, const MotionMultiplier& multiplier,
                               const DiagnosedEffect& effect, const std::string& output, const std::string& port,
                               const std::string& factor_port, const Endpoint& force) {
  const std::string name = out->Add(element);
  std::string rest_name;
  if (!factor_port.empty()) out->Connect(Factor(out, One(), effect, name, force, &rest_name), {name, factor_port});
  Endpoint share{name, port};
  if (multiplier.times) {
    const Endpoint rest = Factor(out, *multiplier.times, effect, name, force, &rest_name);
    const std::string product = out->Add({name + "_share", "product", json::object(), std::nullopt,
                                          fmt::format("the share of the drive's force that '{}' is: '{}' × {}", name,
                                                      name, rest_name)});
    out->Connect(share, {product, "u1"});
    out->Connect(rest, {product, "u2"});
    share = out->OutputOf(product);
  }
  const std::string unity = out->Add({name + "_unity", "constant", {{"value", 1.0}}, std::nullopt,
                                      fmt::format("1, less the share of the drive's force that '{}' is", name)});
  if (multiplier.times && ForceDegree(*multiplier.times) == 1) share = ShareAtTheDriveForce(out, share, unity, name);
  // A force constant 90 % below or above its nominal is no motor's. The limit keeps a refit, or a record on which the
  // model's force or a column goes further than on the training record, away from 1 − r = 0 (grammar seed 4, named
  // ŷ·|ŷ| × a temperature: held-out RMSE 8.3 → 882 N without it). At ±50 % it cut a warm-up of ŷ·|ŷ| that a ramp was
  // named (seed 40) off the floor.
  constexpr double kLargestShare = 0.9;
  const std::string limit = out->Add({name + "_share_limit", "saturation",
                                      {{"lower", -kLargestShare}, {"upper", kLargestShare}}, std::nullopt,
                                      fmt::format("the share of the drive's force that '{}' is, within ±{:g} %", name,
                                                  100.0 * kLargestShare)});
  out->Connect(share, {limit, "u"});
  share = out->OutputOf(limit);
  const Endpoint rest_of_force =
      out->OutputOf(out->AddDifference(out->OutputOf(unity), share, name + "_rest_of_force"));
  const std::string addend = AddToOutput(
      out, {name + "_of_drive_force", "product", {{"ops", "**/"}}, std::nullopt,
            fmt::format("the model's force × r/(1 − r), r the share of the drive's force that '{}' is ({})", name,
                        effect.effect)},
      output, "y");
  out->Connect(force, {addend, "u1"});
  out->Connect(share, {addend, "u2"});
  out->Connect(rest_of_force, {addend, "u3"});
  return name;
}

// Adds `element`, whose port `factor_port` multiplies its input itself (a gain scheduled in time), summed into the
// output, its input the factor (EffectBlockTemplate::multiplier_port). Returns the element's name.
std::string AddWithFactorInput(DiagramDocument* out, const ElementSpec& element, const MotionMultiplier& multiplier,
                               const DiagnosedEffect& effect, const std::string& output, const std::string& port,
                               const std::string& factor_port, const std::optional<Endpoint>& force) {
  const std::string name = AddToOutput(out, element, output, port);
  std::string factor_name;
  out->Connect(Factor(out, multiplier, effect, name, force, &factor_name), {name, factor_port});
  return name;
}

// The diagram's time step: the solver's fixed step, else the default experiment's step size.
double DiagramStep(const DiagramDocument& diagram, const std::string& effect, const std::string& block) {
  if (const auto step = diagram.SolverStep()) return *step;
  if (const auto step = diagram.ExperimentStepSize()) return *step;
  throw std::invalid_argument(fmt::format(
      "effect '{}' needs the diagram's sample period for its {} block: set solver.step or "
      "defaultExperiment.stepSize",
      effect, block));
}

// The model's parameter `replaced` (element.parameter) taken over by the new element: set to 0 and no longer refit,
// with a note. A diagram that no longer has it (edited since the diagnosis) is left as it is.
void TakeOver(DiagramDocument* out, const std::string& replaced, const std::string& by) {
  const auto dot = replaced.find('.');
  if (dot == std::string::npos || !out->Has(replaced.substr(0, dot))) return;
  out->SetParameter(replaced.substr(0, dot), replaced.substr(dot + 1), 0.0);
  out->RemoveFreeParameter(replaced);
  out->AppendNote(fmt::format(" '{}' takes over {} (now 0, no longer refit).", by, replaced));
}

// The level a pair carries as a column of its own (EffectTraits::nests_constant_pair, MultiplierRow::own_level): its
// multiplier × 1, a pair with a block of its own, with the level's coefficient; nullopt when the effect has none (a
// pair without a level, or a diagnosis made before the pairs carried it).
std::optional<DiagnosedEffect> LevelOf(const DiagnosedEffect& effect) {
  const EffectType& type = LookupEffect(effect.effect);
  if (!type.traits.nests_constant_pair) return std::nullopt;
  const EffectType* constant = EffectRegistry::Global().FindPair(type.multiplier, "constant");
  const auto column = std::find(effect.column_names.begin(), effect.column_names.end(), effect.effect + ".level");
  if (constant == nullptr || column == effect.column_names.end()) return std::nullopt;  // a diagnosis made before
  DiagnosedEffect level = effect;
  level.effect = constant->name;
  level.modulator = "constant";
  level.column_names = {constant->name};
  level.coefficients = Eigen::VectorXd::Constant(1, BlockCoefficient(effect, "level"));
  level.coefficient_std.resize(0);
  level.replaced_parameter.clear();
  level.description = fmt::format("the level of {}: {} × 1", effect.effect, type.multiplier);
  return level;
}

// `factor` times `extra` at the end of its chain of factors (MotionMultiplier::times): v·|v| times the time is
// v × (|v| × t).
MotionMultiplier TimesAtEnd(MotionMultiplier factor, MotionMultiplier extra) {
  if (!factor.times) return Times(std::move(factor), std::move(extra));
  factor.times = std::make_shared<const MotionMultiplier>(TimesAtEnd(*factor.times, std::move(extra)));
  return factor;
}

// A mass over the whole record found in simulation mode (acceleration × 1: a payload, a wrong moving mass) is the
// plant's own: a block would read the acceleration that the plant computes from the force the block feeds (an algebraic
// loop). The plant's first parameter in kg (kg·m² on a rotary axis) takes the diagnosed mass on top and is
// refit with the diagram's free parameters. False when the effect is not such a mass or the diagram is compared in
// equation-error mode; throws naming what is missing when the plant has no such parameter.
bool PlantMassTakesIt(DiagramDocument* out, const DiagnosedEffect& effect) {
  const EffectType& type = LookupEffect(effect.effect);
  if (out->Mode() == ExperimentMode::kEquationError || type.multiplier != "acceleration" ||
      type.modulator != "constant") {
    return false;
  }
  std::string why;
  const std::optional<std::string> plant = PlantElement(*out, &why);
  if (!plant) throw std::invalid_argument(fmt::format("effect '{}' in simulation mode: {}", effect.effect, why));
  const BlockType* block = BlockRegistry::Global().Find(out->TypeOf(*plant));
  // Its first parameter in kg, the moving mass (linear_motor's payload_mass comes after it); on a rotary axis the
  // diagram reads it in kg·m² (DiagramDocument::ParameterSpec).
  std::string mass;
  if (block != nullptr) {
    const auto kg = std::find_if(block->parameters.begin(), block->parameters.end(),
                                 [](const ParamSpec& p) { return p.unit == "kg"; });
    if (kg != block->parameters.end()) mass = kg->name;
  }
  if (mass.empty()) {
    throw std::invalid_argument(fmt::format(
        "effect '{}' is a mass, which in simulation mode is the plant's own, but plant '{}' ({}) has no parameter in "
        "kg: change its mass by hand",
        effect.effect, *plant, out->TypeOf(*plant)));
  }
  const double before = out->Parameter(*plant, mass).get<double>(), after = before + BlockCoefficient(effect, "");
  out->SetParameter(*plant, mass, after);
  out->AddFreeParameter(*plant + "." + mass);
  out->AppendNote(fmt::format(" Amended by motionblocks compare --suggest: {} is the plant's mass, {}.{} {:.6g} → "
                              "{:.6g} kg, refit.",
                              effect.effect, *plant, mass, before, after));
  return true;
}

// Whether blocks of `type` declare the parameter `parameter` (a plant's mass_input, an inertia's acceleration_input).
bool Declares(const std::string& type, const std::string& parameter) {
  const BlockType* block = BlockRegistry::Global().Find(type);
  return block != nullptr && std::any_of(block->parameters.begin(), block->parameters.end(),
                                         [&](const ParamSpec& p) { return p.name == parameter; });
}

// The plant's input that schedules its mass (blocks/rigid_body.h: "added_mass", with mass_input true), set up; throws
// naming what to do when the plant's type has none.
Endpoint PlantMassInput(DiagramDocument* out, const std::string& effect) {
  std::string why;
  const std::optional<std::string> plant = PlantElement(*out, &why);
  if (!plant) throw std::invalid_argument(fmt::format("effect '{}' in simulation mode: {}", effect, why));
  if (!Declares(out->TypeOf(*plant), "mass_input")) {
    throw std::invalid_argument(fmt::format(
        "effect '{}' is a mass that varies, which in simulation mode is the plant's own, but plant '{}' ({}) has no "
        "mass input: use a rigid_body plant (its mass_input) or change the mass by hand",
        effect, *plant, out->TypeOf(*plant)));
  }
  out->SetParameter(*plant, "mass_input", true);
  return {*plant, "added_mass"};
}

// A mass that varies (a payload picked up, a mass along the travel or following a column) in simulation mode: a block
// of the plant's acceleration would feed the force that sets it (an algebraic loop), so the mass goes where it acts,
// on the plant's mass input (PlantMassInput): (M + ΔM)·ẍ = f is M·ẍ = f − ΔM·ẍ, the diagnosis' regressor. The block
// reads the acceleration as 1 — a switched gain's output is then its mass — or, a block with a "mass" output and an
// acceleration_input switch (blocks/inertia_table_1d.h, blocks/position_dependent_inertia.h), gives its M(x) there and
// adds its ½M′(x)·v² to the plant's force (ForceEnd of `output`). A third factor `extra` multiplies the mass.
void AddToPlantMass(DiagramDocument* out, const EffectBlockTemplate& block, ElementSpec element,
                    const DiagnosedEffect& effect, const std::string& output,
                    const std::optional<MotionMultiplier>& extra) {
  const Endpoint mass_input = PlantMassInput(out, effect.effect);
  const bool kinetic = Declares(block.block_type, "acceleration_input");
  if (kinetic) element.parameters["acceleration_input"] = false;
  const std::string name = out->Add(element);
  std::string unused;
  const auto one = [&] { return Factor(out, One(), effect, name, std::nullopt, &unused); };
  for (const auto& [input, port] : block.inputs) {
    if (input != MotionInput::kAcceleration) {
      out->Connect(MotionSource(*out, input, effect.effect), {name, port});
    } else if (!kinetic) {
      out->Connect(one(), {name, port});
    }
  }
  Endpoint mass{name, kinetic ? "mass" : block.output_port};
  // The multiplier is the acceleration, read as 1: what is left of it is the third factor.
  std::optional<MotionMultiplier> factor = extra;
  if (block.multiplier) {
    const MotionMultiplier& m = *block.multiplier;
    if (!(m.input == MotionInput::kAcceleration && m.block_type.empty() && !m.of_model_force && !m.one && !m.clock &&
          !m.amplitude_column && !m.times)) {
      throw std::invalid_argument(fmt::format("effect '{}': a mass whose factor is not the acceleration alone has no "
                                              "block in simulation mode yet; add it by hand",
                                              effect.effect));
    }
    if (!block.multiplier_port.empty()) {
      out->Connect(extra ? Factor(out, *extra, effect, name, std::nullopt, &unused) : one(),
                   {name, block.multiplier_port});
      factor.reset();
    }
  }
  if (factor) {
    std::string factor_name;
    const Endpoint source = Factor(out, *factor, effect, name, std::nullopt, &factor_name);
    const std::string product = out->Add({name + "_times_" + factor_name, "product", json::object(), std::nullopt,
                                          fmt::format("the mass of '{}' × '{}' ({})", name, factor_name,
                                                      effect.effect)});
    out->Connect(mass, {product, "u1"});
    out->Connect(source, {product, "u2"});
    mass = out->OutputOf(product);
  }
  if (out->DriverOf(mass_input)) {
    out->SumInto(mass_input, mass, "with_" + name);
  } else {
    out->Connect(mass, mass_input);
  }
  if (kinetic) out->SubtractInto(ForceEnd(*out, output), {name, "y"}, "with_" + name);  // ½M′(x)·v², a load
  out->AppendNote(fmt::format(" Amended by motionblocks compare --suggest: {} is a mass, the plant's: '{}' schedules "
                              "{}.",
                              effect.effect, name, mass_input.ToString()));
}

// Adds `effect`'s block to `out` (its template, or the grammar's composed one: BlockFor), and its level (LevelOf); with
// `extra`, the block's output is multiplied by it too (the part of a pair proportional to its third factor's source).
void AddEffectBlock(DiagramDocument* out, const DiagnosedEffect& effect, const std::string& output,
                    const std::optional<MotionMultiplier>& extra, const std::optional<Endpoint>& drive_force) {
  if (!extra && PlantMassTakesIt(out, effect)) return;
  const std::optional<EffectBlockTemplate> composed = BlockFor(LookupEffect(effect.effect));
  if (!composed) {
    throw std::invalid_argument(
        fmt::format("no block for effect '{}' yet: add it by hand (docs/diagnosis.md)", effect.effect));
  }
  const EffectBlockTemplate& block = *composed;
  if (extra && block.placement != BlockPlacement::kAddToOutput) {
    throw std::invalid_argument(fmt::format("effect '{}': its amplitude's third factor has no block where its block "
                                            "is not summed into the output; add it by hand",
                                            effect.effect));
  }
  std::optional<MotionMultiplier> multiplier = block.multiplier;
  if (extra) multiplier = multiplier ? TimesAtEnd(*multiplier, *extra) : *extra;
  std::optional<Endpoint> force;  // taken before the element is summed in
  if (multiplier && multiplier->NeedsModelForce()) force = ModelForceEnd(*out, output, effect, drive_force);
  ElementSpec element{block.element_name, block.block_type, block.parameters(effect), std::nullopt, effect.description};
  if (block.discrete) element.sample_time = std::make_pair(DiagramStep(*out, effect.effect, block.element_name), 0.0);
  if (out->Mode() != ExperimentMode::kEquationError && LookupEffect(effect.effect).multiplier == "acceleration") {
    AddToPlantMass(out, block, element, effect, output, extra);
    if (const std::optional<DiagnosedEffect> level = LevelOf(effect)) {
      AddEffectBlock(out, *level, output, extra, drive_force);
    }
    return;
  }
  std::vector<Endpoint> inputs;
  for (const auto& [input, port] : block.inputs) inputs.push_back(MotionSource(*out, input, effect.effect));
  std::string name;
  switch (block.placement) {
    case BlockPlacement::kInsertBeforeOutput: name = InsertBeforeOutput(out, element, output); break;
    case BlockPlacement::kOnCommand: name = AddOnCommand(out, element, output, effect.effect, drive_force); break;
    case BlockPlacement::kAddToOutput:
      if (!multiplier) {
        name = AddToOutput(out, element, output, block.output_port);
      } else if (ScalesTheDriveForce(*out, *multiplier)) {
        name = AddDriveForceShare(out, element, *multiplier, effect, output, block.output_port,
                                  block.multiplier_port, *force);
      } else if (block.multiplier_port.empty()) {
        name = AddProductToOutput(out, element, *multiplier, effect, output, block.output_port, force);
      } else {
        name = AddWithFactorInput(out, element, *multiplier, effect, output, block.output_port,
                                  block.multiplier_port, force);
      }
      break;
  }
  for (std::size_t k = 0; k < inputs.size(); ++k) out->Connect(inputs[k], {name, block.inputs[k].second});
  if (!block.log_column_port.empty()) {
    Wire(out, ColumnInput(out, effect.log_column, effect.effect), name, block.log_column_port);
  }
  for (const auto& f : block.free) out->AddFreeParameter(name + "." + f);
  if (!effect.replaced_parameter.empty()) TakeOver(out, effect.replaced_parameter, name);
  out->AppendNote(fmt::format(" Amended by motionblocks compare --suggest: added '{}' ({}).", name,
                              extra ? effect.description : effect.effect));
  if (const std::optional<DiagnosedEffect> level = LevelOf(effect)) {
    AddEffectBlock(out, *level, output, extra, drive_force);
  }
}

}  // namespace

json SuggestAmendedDiagram(const json& diagram, const DiagnosedEffect& effect, const std::string& output,
                           const std::optional<Endpoint>& drive_force) {
  DiagramDocument out(diagram);
  // A third factor (models/diagnosis/amplitude_factor.h): the pair as diagnosed at z₀, and its part times z − z₀.
  const AmplitudeParts parts = SplitAmplitudeFactor(effect);
  AddEffectBlock(&out, parts.main, output, std::nullopt, drive_force);
  if (parts.part) {
    AddEffectBlock(&out, *parts.part, output, AmplitudeSourceFactor(effect.parameters.at(kAmplitudeWith) < 0.0),
                   drive_force);
  }
  return out.json();
}

namespace {

// The block type of the GP disturbance model: the one declaring the loop role "gp" in its own file (blocks/gpr.cc).
std::string GpBlockType() {
  const std::vector<std::string> types = BlockRoleRegistry::Global().TypesWithLoopRole("gp");
  if (types.empty()) {
    throw std::logic_error("no registered block type has the loop role \"gp\" (the GP model): link mb_blocks");
  }
  return types.front();
}

}  // namespace

json SuggestGprFallbackBlock(const json& diagram, const std::string& model_path, const std::string& output,
                             const std::filesystem::path& base_directory) {
  DiagramDocument out(diagram, base_directory);
  const Endpoint position = MotionSource(out, MotionInput::kPosition, "nonparametric_fallback");
  const Endpoint velocity = MotionSource(out, MotionInput::kVelocity, "nonparametric_fallback");
  const std::string name = AddToOutput(
      &out,
      {"residual_gp", GpBlockType(), {{"model", model_path}}, std::nullopt,
       "TISO-GPR on (x, v) learned from what the catalogue's effects leave of the residual"},
      output, "mean");
  out.Connect(position, {name, "x"});
  out.Connect(velocity, {name, "xdot"});
  out.AppendDescription(
      fmt::format(" Amended by motionblocks compare --suggest: added '{}' (non-parametric fallback).", name));
  return out.json();
}

}  // namespace mb

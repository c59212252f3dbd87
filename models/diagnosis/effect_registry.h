#pragma once
// The catalogue of candidate missing physical effects as a registry, mirroring the block registry
// (engine/registry.h): each effect is one file in models/diagnosis/effects/ that fills in an EffectType — its
// name, physics, regressors, proposal rule and traits — and registers it with MB_REGISTER_EFFECT. The block that
// adds an effect to a diagram is registered beside that block, in its own file (blocks/<type>.cc), with
// MB_REGISTER_EFFECT_BLOCK: the effect files name no block, the block files know their parameters. The diagnosis (diagnosis.cc), the loop (tools/workflow/: suggest.cc, improve.cc) and the
// non-parametric fallback (models/gpr/residual_gpr.cc) ask the registry for an effect's traits and block
// instead of comparing its name (docs/diagnosis.md, "Adding an effect").

#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "models/diagnosis/effect_catalogue.h"

namespace mb {

struct DiagnosedEffect;  // models/diagnosis/diagnosis.h
class ProposalContext;   // models/diagnosis/effect_proposal.h

/// What an effect's regressors are periodic in (Lomb–Scargle searches; DIAGNOSIS.md step 2).
enum class Periodicity {
  kNone,
  kPosition,  ///< periodic in x with a parameter "period" [m] (cogging, screw-lead ripple): a pitch of the machine
  kTime,      ///< periodic in t with a parameter "frequency_hz" (a vibration)
};

/// What the diagnosis and the loop ask of an effect instead of its name.
struct EffectTraits {
  /// Periodic effects' first two regressor columns are the cosine and sine of the fundamental: the diagnosis
  /// reports their amplitude; at one speed a position period cannot be told from a time period.
  Periodicity periodicity = Periodicity::kNone;
  /// The regressor is the error itself (ŷ quantized, or delayed, minus ŷ): the effect must enter the joint fit
  /// with a coefficient near 1, else the column is only a nonlinear function of ŷ that happens to correlate
  /// with the residual and the effect is dropped.
  bool regressor_is_error = false;
  /// The effect's one coefficient has a physical sign: positive (a drag dissipates energy, c·v·|v| with c > 0). A fit
  /// with c ≤ 0 is another curve of the speed standing in for the friction law's shape (−850 N·s²/m² beside a Stribeck
  /// hump where a viscosity followed the oil temperature), and the effect is dropped with a note.
  bool positive_coefficient = false;
  /// Why the coefficient is positive, for the note that drops the effect ("it dissipates energy", "it is a mass").
  std::string positive_because = "it dissipates energy";
  /// The regressor is built from the model output ŷ alone, which is in the output filter's band already: it is
  /// not low-passed with the motion's regressors (DiagnosisOptions::regressor_filter_hz).
  bool regressor_in_output_band = false;
  /// The effect acts on the command path, between the controller's command and the force that acts (an actuator lag,
  /// the drive's saturation or voltage limit). Its regressor is built from the command (CommandOf): in equation-error
  /// mode the logged one, or ŷ, in the output's band; in simulation mode the model's drive force
  /// (DiagnosisSignals::drive_force), and the force it gives reaches the output through the closed loop
  /// (ThroughTheLoop) — or, where the diagram is at hand (DiagnosisSignals::simulate_effect), its regressor is that
  /// simulation's output change itself (EffectSimulatedInTheDiagram), which every such effect must then return.
  bool command_path = false;
  /// A friction-law replacement: the effect replaces the model's friction law near zero velocity (regularised
  /// Coulomb, pre-sliding, Stribeck) rather than adding a force the model lacks. The diagnosis tries these first,
  /// reports them as "the friction law near zero velocity is wrong", and searches for the other effects in what they
  /// leave (DIAGNOSIS.md, "When the base model is wrong elsewhere"). Their catalogue names end in "_friction".
  bool friction_law_replacement = false;
  /// The effect's regressor is the whole Coulomb law, level and shape (F_c·tanh(v/v_c)), not a correction to the
  /// model's: its block takes over the model's Coulomb parameter, which the amended diagram sets to 0 and no longer
  /// refits (DiagnosedEffect::replaced_parameter). Left in, the two levels trade against each other in the refit.
  bool replaces_coulomb_law = false;
  /// A nonlinear parameter that the ranking re-estimates once every effect is chosen (DiagnoseMissingEffects, step
  /// 3c): a scan of the joint fit with the base and every other chosen effect in, over [value/range, value·range]
  /// (log grid, golden section), coordinate-wise, the friction-law replacements first. Its first estimate was made in
  /// what the effects chosen before it left, without those found after it: a law replacement chosen first absorbs part
  /// of a delay (a smoothed sign(v) looks like a delayed one at the reversals) and the delay found behind it is biased.
  /// "" = none.
  std::string refined_parameter;
  double refinement_range = 4.0;  ///< > 1: how far (a factor either way) the re-estimate may move the parameter
  /// The largest value of the refined parameter that still means the effect on this record (its physical range; empty
  /// = none): a Stribeck velocity beyond the record's top speed is a hump that never decays, a constant friction level
  /// minus a v² term, no Stribeck effect (the joint refit walked one to 16 m/s on a 0.2 m/s record where a viscosity
  /// followed the oil temperature, and the law it chose kept improve 1.45 × above the floor).
  std::function<double(const DiagnosisSignals&)> refined_upper_bound;
  /// The name under which the effect's one coefficient is reported among its parameters (friction_drift: "change",
  /// the viscous coefficient's change over the record); "" = not reported there.
  std::string coefficient_parameter;
  /// The effect's columns hold those of its multiplier × 1 (a pair with its own level, MultiplierRow::own_level): the
  /// forward selection chooses it over that smaller pair only where its held-out gain over it is significant
  /// (Diebold–Mariano, as any gain, at the family-wise bar of the search when the pair is one it proposed: its shape
  /// was scanned by it), else the smaller pair — a drag constant over the record is no drag drifting by nothing, though
  /// the ramp's column always fits a little of the noise.
  bool nests_constant_pair = false;
  /// The modulators of the grammar whose pairs with the same multiplier this pair holds as a limit of its shape
  /// (ModulatorRow::nests: a window holds a step): chosen over such a pair, as over its multiplier × 1, only where its
  /// held-out gain over it is significant.
  std::vector<std::string> nested_modulators;
};

/// Simulation mode: does the effect's force reach the compared output through the closed loop? Every force does; an
/// effect of the measurement chain (regressor_in_output_band: a sensor delay, quantisation) acts on the output itself.
inline bool ThroughTheLoop(const EffectTraits& traits) {
  return !traits.regressor_in_output_band || traits.command_path;
}

/// Simulation mode: a command-path effect whose block the diagram itself simulates (DiagnosisSignals::simulate_effect):
/// its column is already the compared output's change, not a force for the loop.
inline bool EffectSimulatedInTheDiagram(const EffectTraits& traits, const DiagnosisSignals& signals) {
  return traits.command_path && static_cast<bool>(signals.simulate_effect);
}

/// One parameter of an effect instance (EffectInstance::parameters), SI units.
struct EffectParameter {
  std::string name;
  std::string unit;         ///< SI ("m", "Hz", "s", "m/s"), "" for counts and ratios
  std::string description;
};

/// Where a suggested block goes in the diagram (tools/workflow/suggest.h).
enum class BlockPlacement {
  kAddToOutput,         ///< its output port is summed into the signal feeding the output connector
  kInsertBeforeOutput,  ///< it is put between that signal and the output connector (ports "u" → "y")
  /// It acts on the logged command before the command moves the axis (a drive's lag, its current limit; ports "u" →
  /// "y"). In equation-error mode, where the logged command is the compared output and the model computes the force
  /// that acted from the motion, the amended diagram reads the logged command through an input connector on the
  /// output's column (added when absent), passes it through the block, and adds what the log holds beyond what acted,
  /// u − y, to the model's output: the residual becomes y − ŷ. Simulation mode is refused (put the block between the
  /// command's input connector and the plant by hand).
  kOnCommand,
};

/// A measured motion quantity that a suggested block reads from the diagram's input connectors (found by unit).
enum class MotionInput { kPosition, kVelocity, kAcceleration };

/// A factor that multiplies an effect block's output (the grammar's products, models/diagnosis/factors.h: sign(v) × a
/// table of the position is a friction at one place): a block of `block_type` (ports "u" → "y") reading the input
/// connector of `input` — or, with `of_model_force`, the model's own force (the block reading it when block_type is
/// set: |ŷ|) —, times `times` when set; a product element multiplies it and the
/// effect block's output, and the product is what is summed into the model's output (BlockPlacement::kAddToOutput).
struct MotionMultiplier {
  std::string block_type;  ///< empty: the input connector itself (or, with of_model_force, the force) is the factor
  MotionInput input = MotionInput::kVelocity;
  std::function<nlohmann::json(const DiagnosedEffect&)> parameters;  ///< the multiplier element's parameters
  /// The multiplier element's parameters refit jointly with the effect's own (EffectBlockTemplate::free): a friction
  /// factor's slip velocity, which the diagnosis found on a grid, placed by the refit of the amended diagram.
  std::vector<std::string> free;
  /// The factor is the force the model computes from the measured motion — the signal summed into the output before
  /// the effect is (ŷ × a ripple of the position: a force constant that ripples). Equation-error mode only: in
  /// simulation mode the output is the motion, not the force.
  bool of_model_force = false;
  /// The factor is 1: a constant block of value 1 (a force of the modulator alone, fed to a gain scheduled in time:
  /// a force that steps, drifts or is there for a while).
  bool one = false;
  /// The factor is the time, from a clock block (blocks/clock.h): the part of a pair whose amplitude drifts in time (a
  /// third factor, models/diagnosis/amplitude_factor.h).
  bool clock = false;
  /// The factor is the log column the effect's amplitude follows (DiagnosedEffect::amplitude_column, a third factor),
  /// read through its input connector (added when the diagram has none).
  bool amplitude_column = false;
  /// A second factor the first is multiplied by (the grammar's two-factor multipliers: v·|v|, ŷ·|ŷ|, |ŷ|·tanh(v/v_s)),
  /// through a product element; nullptr = none.
  std::shared_ptr<const MotionMultiplier> times = nullptr;
  /// Whether this factor or the one it is multiplied by is the model's force.
  bool NeedsModelForce() const { return of_model_force || (times && times->NeedsModelForce()); }
};

/// The block that adds an effect to a diagram, as `compare --suggest` and `improve` insert it.
struct EffectBlockTemplate {
  std::string block_type;    ///< a registered block type (blocks/)
  std::string element_name;  ///< the new element's name, made unique ("ripple", "ripple_2", …)
  BlockPlacement placement = BlockPlacement::kAddToOutput;
  std::string output_port = "y";  ///< the port summed into the output (kAddToOutput)
  std::vector<std::pair<MotionInput, std::string>> inputs;  ///< input connector → block port, wired in order
  bool discrete = false;  ///< gets sampleTime [Ts, 0], Ts = the diagram's solver.step or defaultExperiment.stepSize
  /// The element's "parameters" from the diagnosis (its parameters and joint-fit coefficients, effect_block.h).
  /// Throws std::invalid_argument when a key parameter is missing or out of range (saying why).
  std::function<nlohmann::json(const DiagnosedEffect&)> parameters;
  std::vector<std::string> free;       ///< element parameters refit jointly with the base by the next compare
  std::vector<std::string> refinable;  ///< also refit when the loop refines periods (improve --refine-periods)
  /// Parameters that belong to the record rather than the machine (the encoder zero): refit on a validation
  /// record while the rest stays (improve's held-out score, demo step 4).
  std::vector<std::string> record_specific;
  /// Where an element parameter keeps its physical meaning, [low, high] in the block's units: a joint refit that
  /// leaves it (a resonance's damping ratio above 1 is no resonance) makes the step a different effect, and improve
  /// refuses it with the reason.
  std::map<std::string, std::pair<double, double>> physical_range;
  /// The factor of the motion the block's output is multiplied by (kAddToOutput only); nullopt = none.
  std::optional<MotionMultiplier> multiplier;
  /// With a multiplier: the block's port the factor is wired into (a gain scheduled in time, y = g(t)·u, multiplies
  /// its input itself), instead of a product element of the block's output and the factor; empty = the product.
  std::string multiplier_port;
  /// The block's port that reads the log column the effect names (DiagnosedEffect::log_column: a column the diagram
  /// did not read), through an input connector on that column, added when the diagram has none; empty = none.
  std::string log_column_port;
};

/// One registered effect: everything the catalogue knows about it.
struct EffectType {
  std::string name;  ///< stable catalogue name (compare.json, improve.json): snake_case, e.g. "position_periodic"
  /// Where the effect's candidates come in the candidate list (ascending); ties go by name. Candidates earlier in
  /// the list win exact ties of the forward selection.
  int catalogue_order = 0;
  std::string physics;             ///< one sentence: the physics and how to add it to a model (reports)
  std::string regressor_formula;   ///< the regressor columns as a formula, e.g. "cos(2πkx/P), sin(2πkx/P), k = 1..K"
  std::vector<EffectParameter> parameters;
  EffectTraits traits;
  /// The grammar's factors the effect is the product of (models/diagnosis/factors.h, issue 45): the ids of a row of the
  /// multipliers' table ("slip", "velocity", "model_force", …) and of the modulators' table ("position_periodic",
  /// "column", "time_step", …); both empty for an effect that is no product (a delay, a resonance, a saturation, a
  /// friction law). At most one effect holds a pair: a hand-written effect of the catalogue (its own proposal rule)
  /// takes the place of the pair the grammar generates (EffectType::generated).
  std::string multiplier, modulator;
  /// Made by the grammar's cross product (effects/factor_products.cc), not written by hand: it yields its pair to a
  /// hand-written effect registered with the same multiplier and modulator, before or after it.
  bool generated = false;
  /// A pair of the grammar that no one named before (proposed only with CatalogueOptions::every_pair): one hypothesis
  /// of a search over ~100, whose significance is family-wise over the searched candidates of the record
  /// (DiagnosisOptions::significance_t), where the catalogue's effects and the named pairs are hypotheses of their own.
  bool searched = false;
  /// The regressor columns (N × k, names "<effect>" or "<effect>.<column>") on the signals. Throws
  /// std::invalid_argument naming a missing or invalid parameter or an absent optional signal.
  std::function<EffectRegressors(const EffectInstance&, const DiagnosisSignals&)> regressors;
  /// Parameters read off the fitted coefficients (k, in column order), added to the diagnosed effect's: hysteresis's
  /// stroke and break-away force from its elements' forces. Empty when the effect has none.
  std::function<std::map<std::string, double>(const EffectInstance&, const Eigen::VectorXd& coefficients)>
      derived_parameters;
  /// The proposal rule: estimates the effect's parameters from the residual (periodogram peaks, spectrum, a
  /// scan of the joint fit, …) and adds zero or more candidates to the context (ProposalContext::Propose).
  std::function<void(ProposalContext&)> propose;
  /// The block that adds the effect to a diagram, registered by that block's file (MB_REGISTER_EFFECT_BLOCK);
  /// nullopt when there is none (the report says to add it by hand) or the blocks are not linked.
  std::optional<EffectBlockTemplate> block;
};

class EffectRegistry {
 public:
  /// The process-wide registry that the effect files add themselves to during static initialisation.
  static EffectRegistry& Global();

  /// Adds an effect. @throws std::logic_error if the name is taken or empty, or a function is missing, or its
  /// (multiplier, modulator) pair is held by another effect of the same kind (two hand-written, or two generated). A
  /// generated effect whose pair a hand-written one holds is not added (or removed when the hand-written one comes
  /// later, its block kept unclaimed under its name). Returns true (for static registration).
  bool Add(EffectType type);
  /// Attaches `block` as the block that adds effect `effect_name` to a diagram, whether the effect registers
  /// before or after. @throws std::logic_error if the effect has a block already, or `block` names no block type
  /// or has no parameters function. Returns true (for static registration).
  bool AddBlockTemplate(const std::string& effect_name, EffectBlockTemplate block);
  /// Block templates registered for effects that are not in the catalogue (a misspelt MB_REGISTER_EFFECT_BLOCK):
  /// their effect names. Empty when every template found its effect.
  std::vector<std::string> UnclaimedBlockTemplates() const;
  /// nullptr if unknown.
  const EffectType* Find(std::string_view name) const;
  /// The effect holding the grammar's pair multiplier × modulator (factors.h ids); nullptr if none.
  const EffectType* FindPair(const std::string& multiplier, const std::string& modulator) const;
  /// The effect; @throws std::invalid_argument "unknown effect 'x'; did you mean 'y'? The catalogue has: …".
  const EffectType& Get(std::string_view name) const;
  /// Every effect in catalogue order (the order candidates are proposed in).
  std::vector<const EffectType*> Effects() const;
  /// The registered names closest to `name` (edit distance), for "did you mean" messages.
  std::vector<std::string> Suggest(std::string_view name, std::size_t max_suggestions = 3) const;

 private:
  std::map<std::string, EffectType, std::less<>> effects_;
  std::map<std::string, EffectBlockTemplate, std::less<>> unclaimed_blocks_;  ///< effect not registered (yet)
  std::map<std::pair<std::string, std::string>, std::string> pairs_;  ///< (multiplier, modulator) → the effect holding it
};

/// EffectRegistry::Global().Get(name).
const EffectType& LookupEffect(std::string_view name);

/// The record-specific parameters (EffectBlockTemplate::record_specific) of a block type, over every registered
/// effect whose block is of that type, each once; empty for other types.
std::vector<std::string> RecordSpecificParameters(std::string_view block_type);

}  // namespace mb

/// Registers effect `type` (an EffectType expression) at static-initialisation time. Use once per effect file.
#define MB_REGISTER_EFFECT(identifier, ...)                                         \
  namespace {                                                                       \
  [[maybe_unused]] const bool kEffectRegistered_##identifier =                      \
      ::mb::EffectRegistry::Global().Add(__VA_ARGS__);                              \
  }

/// Registers `block` (an EffectBlockTemplate expression) as the block that adds effect `effect` to a diagram
/// (EffectRegistry::AddBlockTemplate). Use in the block's own file, beside its MB_REGISTER_BLOCK.
#define MB_REGISTER_EFFECT_BLOCK(effect, ...)                                       \
  namespace {                                                                       \
  [[maybe_unused]] const bool kEffectBlockRegistered_##effect =                     \
      ::mb::EffectRegistry::Global().AddBlockTemplate(#effect, __VA_ARGS__);        \
  }

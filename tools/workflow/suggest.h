#pragma once
// `compare --suggest`: the diagram amended with the block of a diagnosed missing effect, its parameters set
// from the diagnosis, its coefficients added to the diagram's free parameters so that the next compare refits
// them jointly with the base model (DIAGNOSIS.md step 1).

#include <filesystem>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/diagram_document.h"
#include "models/diagnosis/diagnosis.h"

namespace mb {

/// Whether the effect registry (models/diagnosis/effect_registry.h) has a block template for `effect` that
/// SuggestAmendedDiagram can insert (false for unknown effects and for those without a block).
bool HasEffectBlock(const std::string& effect);

/// The ranked effects of `diagnosis` in the order they are applied to a diagram, the one order `compare` reports,
/// `compare --suggest` applies and `improve` tries: the friction-law replacements first (DiagnosisResult::friction_law,
/// in its order: the model's friction law near zero velocity is wrong, and the diagnosis searched the other effects in
/// what the replacements leave), then the missing effects in the order the forward selection chose them
/// (DiagnosedEffect::selection_order; cumulative_share rises along it while each lowers the held-out error). Pointers
/// into `diagnosis.effects` (valid while it lives); every effect once.
std::vector<const DiagnosedEffect*> EffectsInApplicationOrder(const DiagnosisResult& diagnosis);

/// Whether `diagnosis` chose `effect` as a friction-law replacement (DiagnosisResult::friction_law).
bool IsFrictionLawReplacement(const DiagnosisResult& diagnosis, const std::string& effect);

/// Returns the diagram with an element for `effect` built from the effect's block template (EffectBlockTemplate,
/// registered in the effect's file in models/diagnosis/effects/): its type and name (made unique), its parameters
/// from the diagnosis (period, frequency, delay, Stribeck velocity; the joint fit's coefficients as initial
/// values), a sampleTime = the diagram's solver step or defaultExperiment.stepSize when the block is discrete, its
/// inputs wired from the input connectors carrying position ("m"), velocity ("m/s") or acceleration ("m/s^2"), and
/// its free parameters appended to the diagram's "free" list so that the next compare refits them jointly with the
/// base model. An additive element is summed into the signal feeding output connector `output` through a new sum
/// element; one that acts on the model's output (a delay, a quantizer) is inserted between that signal and the
/// connector. An effect that takes over a base parameter (DiagnosedEffect::replaced_parameter, e.g. the smooth
/// Coulomb law taking over "friction.coulomb") sets that parameter to 0 and removes it from "free", with a note; a
/// diagram without that element (edited since the diagnosis) keeps its parameters. An effect with a third factor
/// (models/diagnosis/amplitude_factor.h) is added as the pair as diagnosed at z₀ and, beside it, its part times z − z₀
/// (a clock block, or the column's input connector, less a constant). docs/diagnosis.md lists each effect's block.
/// @throws std::invalid_argument if the effect is unknown or has no block, its template refuses the diagnosed
/// parameters (a key parameter missing or out of range, a negative delay), or the diagram lacks the needed input
/// connector, sample period or a connection into `output` (the message says what to add).
/// In simulation mode an effect of the force constant multiplies the model's drive force, and a command-path block
/// goes after it: `drive_force` is the diagram's signal that holds it (DiagnosedComparison::drive_force_source);
/// without it such an effect is refused there.
nlohmann::json SuggestAmendedDiagram(const nlohmann::json& diagram, const DiagnosedEffect& effect,
                                     const std::string& output,
                                     const std::optional<Endpoint>& drive_force = std::nullopt);

/// The non-parametric fallback as a block: the diagram with a `gpr` element "residual_gp" (blocks/gpr.h) that loads
/// `model_path` (a TISO-GPR fitted to the residual, models/gpr/residual_gpr.h; pass an absolute path or one relative
/// to `base_directory`, the folder the amended diagram will be read from; empty: the current folder), fed by the
/// position ("m") and velocity ("m/s") input connectors, its posterior mean summed into the signal feeding output
/// connector `output`. Nothing is added to "free": the model is fitted.
/// @throws std::invalid_argument if the diagram lacks a position or velocity input connector or a connection into
/// `output` (the message says what to add), or the model file is not there.
nlohmann::json SuggestGprFallbackBlock(const nlohmann::json& diagram, const std::string& model_path,
                                       const std::string& output, const std::filesystem::path& base_directory = {});

}  // namespace mb

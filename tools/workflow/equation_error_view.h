#pragma once
// The equation-error view of a simulation-mode comparison (issue 46): where the closed-loop diagram holds the
// controller and the log holds that controller's output, the force the controller commanded — the logged output fed
// through the diagram's own drive path — is set against the plant's inverse on the measured motion, and that force
// residual is diagnosed as equation-error mode diagnoses one (measured motion in, force out; parallel filtering).
// A missing force reaches a position error only through the loop, which filters it; the force residual holds it
// as it acted. The view names the same catalogue and says where it agrees with the position's.
//
// How the view is built from the closed-loop diagram, naming no block type:
//   - the plant is the element whose output the compared position is; its outputs read the measured position and
//     the derived velocity instead (DiagramDocument::ReadInstead), classified by their ports' units;
//   - the first log column recognised as the loop's own signal (DiagnosedComparison::reactions) replaces the signal
//     it equals: the controller's output as it ran;
//   - the plant's force input (its one input in a force unit) is then the net force the machine received by the
//     model, f(t); the plant's inverse is identified from the plant's own response to f in the same run,
//     f = M·dv/dt + B·v (least squares; a plant whose run this law does not reproduce to 1 % has no view);
//   - r = f − M·a − B·v on the measured acceleration a and velocity v, f low-passed as the derived motion
//     (ModelComparison::set_output_filter), is the residual; the diagram's free parameters' sensitivities of f (and
//     M·a when the plant's own parameters are free) are the base regressors.
// Source: Ljung, System Identification (1999), §7.3 (equation error against output error); Gautier's IDIM-LS
// (Janot, Gautier, Brunot 2019) for parallel filtering.

#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "models/diagnosis/diagnosis.h"
#include "tools/workflow/comparison.h"
#include "tools/workflow/measurement.h"

namespace mb {

/// The equation-error view of one simulation-mode compare, or why there is none.
struct EquationErrorView {
  std::optional<DiagnosisResult> diagnosis;  ///< the force residual's ranked effects; none: see `skipped`
  std::string skipped;                       ///< why there is no view (empty when there is one)
  std::string command_column;                ///< the log column read as the controller's output
  std::string command_signal;                ///< the diagram's signal it replaced ("element.port")
  std::string force_signal;                  ///< the plant's force input's driver ("element.port")
  double mass = 0.0;                         ///< the plant's inverse: M [kg, or kg·m² on a rotary axis]
  double damping = 0.0;                      ///< B [N·s/m, or N·m·s/rad]
  std::string force_unit = "N";              ///< the residual's unit: the diagram's axis' force (N, or N·m)
  /// The first effect named outside the friction-law replacements here and in the position view ("" = none).
  std::string first_named;
  std::string position_first_named;
  std::string note;                          ///< one sentence: how the view was built and whether both agree
  /// Simulation mode's verdict from both views (CombineViews): the effects it names, in order, each with the
  /// parameters of the view that measures it; and which view it rests on ("both", "equation-error view",
  /// "position view", "" = neither names anything).
  std::vector<DiagnosedEffect> verdict;
  std::string verdict_from;
  /// {"skipped"} or {"command_column", "command_signal", "force_signal", "mass", "damping", "force_unit",
  /// "first_named", "position_first_named", "agrees", "note", "diagnosis": DiagnosisResult::ToJson, "ranked":
  /// [{effect, score, parameters}], "verdict": {"from", "ranked": [{effect, score, parameters}]}}.
  nlohmann::json ToJson() const;
};

/// Simulation mode's verdict from its two views of one record (issue 46): the position view (the closed loop's
/// simulated position against the measured) and the equation-error view (the commanded force against the plant's
/// inverse), two instruments on the same machine. An effect both name is confirmed: the verdict is those effects, in
/// the force's order, each with the equation-error view's parameters (the force is measured there; the loop filters
/// it on its way to the position), but an effect of the measurement chain (EffectTraits::regressor_in_output_band
/// and not on the command path: it acts on the measured output) with the position view's. An effect only one names is
/// left out of it. When they name nothing in common, the verdict is the view whose first effect explains the larger
/// share of its own held-out residual (DiagnosedEffect::score), whole: the other has not found what that one has.
/// Returns the effects and "both", "equation-error view", "position view" or "" (neither names anything). Throws
/// nothing for effects of the catalogue (LookupEffect throws std::invalid_argument for a name outside it). Source:
/// Ljung, System Identification (1999), §7.3 — the equation-error and output-error criteria of one model, here read
/// as two tests whose agreement confirms a structure.
std::pair<std::vector<DiagnosedEffect>, std::string> CombineViews(const DiagnosisResult& position,
                                                                  const DiagnosisResult& force);

/// The first effect of `d` outside its friction-law replacements ("" when none).
std::string FirstNamedEffect(const DiagnosisResult& d);

/// The equation-error view of `compared` (CompareAndDiagnose in simulation mode, with a diagnosis), its diagram from
/// `base_directory`, named `source`, on `log` read with `settings`. No view (EquationErrorView::skipped) in
/// equation-error mode, without a diagnosis, when no log column is the loop's own signal, when the compared output
/// is not a plant's, or when the plant is not a rigid body. @throws what ModelComparison and DiagnoseMissingEffects
/// throw on the opened diagram (a diagram that cannot run).
EquationErrorView DiagnoseEquationErrorView(const DiagnosedComparison& compared,
                                            const std::filesystem::path& base_directory, const std::string& source,
                                            const MeasurementLog& log, const MeasurementSettings& settings);

}  // namespace mb

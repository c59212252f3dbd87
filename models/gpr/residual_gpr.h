#pragma once
// The diagnosis's non-parametric fallback (issue 6, DIAGNOSIS.md "when the catalogue runs out"): a TISO-GPR
// (paper §3, eq. 19 or 27) learns what is left of the residual as a function of position and velocity, d(x, ẋ),
// and is scored the way the catalogue's effects are — by the share of the residual energy it explains on
// contiguous blocks of the record it was not fitted to. It names no physics; it says that something still
// depends on the motion state, how much of the error it carries, and gives a model file a `gpr` block
// (blocks/gpr.h) can add to the diagram.

#include <optional>
#include <string>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "models/diagnosis/diagnosis.h"
#include "models/diagnosis/effect_catalogue.h"
#include "models/gpr/gpr_fit.h"
#include "models/gpr/gpr_model.h"

namespace mb {

struct ResidualGprOptions {
  /// "PS" (periodic in x with `period`, plus SE in ẋ) or "DS" (SE + SE). With std::nullopt: "PS" when `period`
  /// is given, else "DS".
  std::optional<GprKernel> kernel;
  double period = 0.0;           ///< τ [m, or the position_unit] for "PS" (e.g. the pole pitch or the residual's periodogram peak); 0 = none
  Eigen::Index folds = 5;        ///< contiguous cross-validation blocks, 2..N/64
  double min_gain = 0.01;        ///< below this held-out share the fallback is "not useful"
  /// Fits use at most this many samples, evenly strided over the training blocks (the weight-space fit takes
  /// 10⁵ samples in a few tenths of a second; the stride keeps k + 1 fits of a long log quick).
  Eigen::Index max_training_samples = 20000;
  int restarts = 1;              ///< extra MAP starts per fit (GprFitOptions::restarts)
  /// The position's unit, for the description ("m" is written in mm; rad, rev, V as they are).
  std::string position_unit = "m";
};

struct ResidualGprResult {
  bool useful = false;             ///< held-out share ≥ min_gain
  GprKernel kernel = GprKernel::kSeSe;
  double period = 0.0;             ///< τ [m, or the position_unit] used ("PS")
  double heldout_rmse_before = 0.0;  ///< RMS of the residual over the held-out blocks (the GP's mean not counted)
  double heldout_rmse_after = 0.0;   ///< RMS of residual − GP prediction fitted on the other blocks
  double heldout_share = 0.0;        ///< 1 − after²/before²: share of the residual energy the GP explains
  double rmse_after = 0.0;           ///< in-sample RMS of residual − GP prediction of the final model
  std::optional<GprModel> model;   ///< fitted on all samples (the final model), set when useful
  std::string description;         ///< one or two sentences for users
  nlohmann::json ToJson() const;   ///< every field except the model (its file is written separately)
};

/// Fits and scores the fallback on the residual r (length N, unit of the output) at the signals' positions [m]
/// and velocities [m/s]. Each held-out block is predicted by a GP fitted (MAP, weight space) on the other
/// blocks; the final model is fitted on all blocks.
/// @throws std::invalid_argument as DiagnosisSignals::Validate, for a residual of the wrong length or with
/// NaN/Inf, folds outside 2..N/64, min_gain outside [0, 1), period < 0, or "PS" without a period;
/// std::runtime_error when a fit fails (FitGpr's message).
ResidualGprResult FitResidualGpr(const DiagnosisSignals& signals, const Eigen::Ref<const Eigen::VectorXd>& residual,
                                 const ResidualGprOptions& options = {});

/// The fallback after a diagnosis: fitted to what the diagnosis left (signals.residual minus PredictCorrection of
/// `diagnosis` with `base`), with "PS" at the period of a chosen position_periodic or velocity_dependent_ripple
/// effect, else "DS" (a periodogram peak the ranking did not choose is no period to build a kernel on: on a smooth
/// force over the travel it sent "PS" to a 24 mm period that explained nothing). `options.period` and
/// `options.kernel`, when set, win.
/// @throws as FitResidualGpr and PredictCorrection.
ResidualGprResult FitResidualGprAfterDiagnosis(const DiagnosisSignals& signals, const BaseRegressors& base,
                                               const DiagnosisResult& diagnosis, ResidualGprOptions options = {});

}  // namespace mb

// Naming the missing physical effect (DIAGNOSIS.md): rank the catalogue's candidate effects by how much
// of the held-out residual they explain when fitted jointly with the base model's free parameters.
//
// Algorithm (forward selection, SINDy-like; Brunton, Proctor & Kutz 2016):
//  1. Refit the base model's free-parameter regressors X_b (e.g. a, v, sign(v), 1 for a rigid body)
//     to the residual by least squares: the base parameters are biased while an effect is missing.
//  2. Propose candidates with their nonlinear parameters from the refit residual
//     (ProposeCandidateEffects: periodograms, Welch spectrum, delay search, ...). Drop those the base's
//     regressors already span (DiagnosisOptions::redundant_with_base): they are in the model, refit.
//  3. Split the record into k = 5 CONTIGUOUS time blocks. For a set S of regressors, the held-out error
//     MSE(S) = Σ_blocks ‖r_b − X_b(S)·θ_{−b}‖²/N, θ_{−b} fitted by least squares on the other blocks
//     (columns scaled to unit RMS, ridge 1e-9 for collinear columns; computed from per-block Gram
//     matrices, so each fit costs O(p³)).
//  4. Each round adds the candidate with the lowest MSE(S ∪ {c}) (ties within 0.1 % go to the lower BIC);
//     its score = 1 − MSE(S ∪ {c})/MSE(S), the share of the held-out residual energy left by the previous
//     round that it explains. Stop when the best score < min_gain (default 1 %).
//  5. Final coefficients: one joint least-squares fit of base + chosen effects on all data, after the chosen effects'
//     nonlinear parameters are re-estimated in it (DiagnosisOptions::refinement_sweeps), each chosen effect is compared
//     with its rivals of the same round refined in its place (rival_reconsideration.h) and each chosen product's
//     multiplier is chosen again with them refit (multiplier_reconsideration.h).
// Robust to a wrong base model (DIAGNOSIS.md, "When the base model is wrong elsewhere"): every fit is weighted by
// Huber weights (IRLS, DiagnosisOptions::huber_k); when the base has a Coulomb law, the friction-law replacements
// (EffectTraits::friction_law_replacement) are ranked first and the candidates re-proposed in what they leave; a
// candidate is chosen only when its held-out gain is significant against the residual's autocorrelation
// (Diebold–Mariano with batch-mean variance, DiagnosisOptions::significance_t). docs/diagnosis.md, "Ranking".
// Nothing passing: "no missing effect" (with the residual's whiteness and the periodogram's
// significance as supporting evidence). A position-periodic and a time-periodic effect cannot be told
// apart when the motion has essentially one speed: then position_time_indistinguishable is set.
#pragma once

#include <array>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "models/diagnosis/effect_catalogue.h"
#include "models/diagnosis/periodogram.h"
#include "models/diagnosis/signal_processing.h"
#include "models/diagnosis/signal_relevance.h"

namespace mb {

// The base model's free-parameter regressors (N × p) with a name per column, such that the base model's
// output is columns·θ (+ fixed parts). p = 0 is allowed (nothing is refit).
struct BaseRegressors {
  Eigen::MatrixXd columns;
  std::vector<std::string> names;
};

struct DiagnosisOptions {
  Eigen::Index folds = 5;          // contiguous cross-validation blocks, >= 2
  double min_gain = 0.01;          // stop when the best held-out gain is below this share
  Eigen::Index max_effects = 6;    // rounds of forward selection at most
  CatalogueOptions catalogue{};
  // Parallel filtering for equation-error data: when > 0, every candidate's regressor columns built from the
  // motion (x, v, a, t) pass through ZeroPhaseLowPass at this cut-off [Hz], the filter the model output and the
  // measured output went through (ModelComparison::set_output_filter). Without it a candidate differs from the
  // base's (filtered) columns only by the derivative noise it carries, and that noise "explains" a few per cent
  // of the residual: a mass mismatch invented on data with nothing missing. 0 = off.
  double regressor_filter_hz = 0.0;
  // The record's median sample period [s], at which the regressor filter runs: DiagnoseMissingEffects sets it from
  // the signals' time once (every candidate's columns are filtered, and each of a refinement's trials, and the median
  // of N steps each time took 5 % of compare on EMPS). 0: each filtering takes the median of the signals' own steps.
  double sample_period = 0.0;
  // A candidate whose regressor columns the base's free-parameter regressors reproduce to at least this share of
  // their energy (least squares) is already in the model and is not ranked (a note says so): e.g.
  // coulomb_friction when F_c is free, which would otherwise score on its dead band alone.
  double redundant_with_base = 0.98;
  // Simulation mode: the candidates' columns through the loop's simulator (LoopResponse::Simulate, the full diagram)
  // rather than its linearisation (Apply). Set by the diagnosis itself for the chosen effects' last refit (step 3g);
  // a caller leaves it false.
  bool simulate_loop_columns = false;
  // The position's unit ("m", or "rad", "rev", "deg" on a rotary axis; engine/units.h), for the reports: periods in
  // mm for metres, else in the unit (and per revolution for angles). Velocities are in position_unit/s.
  std::string position_unit = "m";
  // Position- vs time-periodic: the top periodic effect and its counterpart under the other hypothesis (at the
  // record's mean speed) are refit to the residual; when their shares differ by less than this fraction of the larger,
  // the record cannot tell them apart (CheckPositionTimeAmbiguity, ambiguity_checks.h).
  double position_time_margin = 0.05;
  // Robust loss (DIAGNOSIS.md, "When the base model is wrong elsewhere"): every least-squares fit of the ranking is
  // weighted by Huber weights w = min(1, k·σ/|r|) (σ = 1.4826·MAD of the residual, k = huber_k), found by
  // iteratively reweighted least squares of the base (then of the base with the friction-law replacements chosen,
  // and for the final joint fit with every chosen effect): a few badly modelled samples (the model's sign(v) flipping
  // ±F_c on velocity noise while the machine dwells) no longer drag the base refit. The held-out errors and shares
  // are then of the weighted residual. 0 = plain least squares.
  double huber_k = 3.0;
  // No invented effect: a candidate is chosen only when its held-out gain is significant against the residual's own
  // autocorrelation — a Diebold–Mariano test (Diebold & Mariano 1995) on the per-sample held-out loss differences,
  // the variance of their mean from significance_batches contiguous batch means (the effective sample size is then
  // about the number of batches, whatever the residual's correlation time below N/batches). One-sided t at least
  // this (2.33: p ≈ 0.01) for an effect of the catalogue or a pair named before; for a pair the grammar's search
  // proposes (EffectType::searched), among m such candidates, the t whose one-sided normal tail is p/m (Bonferroni:
  // the family-wise chance that noise passes stays p; 3.72 for 100), so that a search over ~100 pairs, each with its
  // shape scanned on the record, does not find one that fits the noise by luck. 0 = off.
  double significance_t = 2.33;
  Eigen::Index significance_batches = 40;
  // A gain of at least this share of the held-out residual energy needs no test: noise fitted by a column does not
  // explain a quarter of the held-out energy, while a real effect that acts at rare instants (a delay's error at the
  // few reversals of a slow back-and-forth) makes the batch means scatter and would fail the test.
  double significance_exempt_gain = 0.25;
  // Step 3c: the chosen effects' nonlinear parameters (EffectTraits::refined_parameter: a delay, a gap, the law's v_c)
  // re-estimated in the joint fit with every other chosen effect in, by at most this many coordinate passes; the
  // scores are then recomputed with the refined parameters (a note per parameter that moved). 0 = off.
  int refinement_sweeps = 2;
  // No effect may fit the noise (DIAGNOSIS.md, "The noise floor, and leaks"): a candidate whose held-out RMSE would
  // fall below this fraction of the record's white noise floor (NoiseFloor::white_rms) fits the
  // measurement's own noise — a regressor built from the compared output, a leak — and is refused with a note.
  // 0 = off.
  double leak_floor_ratio = 0.7;
  // Nor is an effect named that matters less than the noise: a candidate that lowers the held-out error by an RMS
  // (the square root of the fall in mean square) under this fraction of the white noise floor is left out with a
  // note. √(1.3² − 1) ≈ 0.83 says: without it the model stays within 1.3 × the floor, the band a model is judged to
  // have reached the floor in (improve's acceptance). It needs held-out errors of the residual itself, commensurate
  // with the floor: compare sets it in simulation mode, where the fit is plain least squares (huber_k 0). Off (0) by
  // default: Huber-weighted errors are smaller than the residual's, and on the independent equation-error cases it
  // refused a quadratic drag of 0.77 × the white floor. Measured against the floor the leak check uses (off too when
  // leak_floor_ratio is 0).
  double relevance_floor_ratio = 0.0;
};

// One effect the ranking chose.
struct DiagnosedEffect {
  std::string effect;                        // stable catalogue name
  // The grammar's pair the effect is (EffectType::multiplier, ::modulator; factors.h): "" for an effect that is none.
  std::string multiplier, modulator;
  double score = 0.0;                        // share of the remaining held-out residual energy explained, 0..1
  double cumulative_share = 0.0;             // share of the base's held-out residual energy explained so far
  // Share of the base's held-out residual energy that this effect removed where it was added: its cumulative_share
  // less the one chosen before it's, i.e. its score times what the effects before it left. The ranking's order: a
  // score is of what was left, and an effect chosen second can have a higher score on a far smaller remainder.
  double base_share = 0.0;
  // Where the forward selection chose it, 0 first (the friction-law replacements come first): the order a diagram is
  // amended in (EffectsInApplicationOrder). cumulative_share rises along it only while each effect lowers the held-out
  // error; one kept for its significance can lower the cumulative share (grammar seed 92: three effects chosen after
  // a 99.9 % drift, each at −0.3 … −10.7 %).
  int selection_order = 0;
  std::map<std::string, double> parameters;  // SI; periodic effects also get "amplitude" (first harmonic)
  std::vector<std::string> column_names;
  Eigen::VectorXd coefficients;              // from the final joint fit, unit of residual per unit of column
  Eigen::VectorXd coefficient_std;           // their standard deviations (σ²(XᵀX)⁻¹)
  // The base's free parameter that this effect takes over (EffectTraits::replaces_coulomb_law: the model's Coulomb
  // level, e.g. "friction.coulomb"); "" for an effect that adds to the model.
  std::string replaced_parameter;
  // The log column the effect reads, for a factor of a column the diagram does not read (logged_column: its name in
  // DiagnosisSignals::extra_names); "" for every other effect.
  std::string log_column;
  // The log column the effect's amplitude follows (a third factor of a column, amplitude_factor.h: its name in
  // DiagnosisSignals::extra_names); "" when it has none or follows time.
  std::string amplitude_column;
  // Where the effect's fitted contribution is largest: 5–95 % ranges of t, x, v over the 10 % of samples
  // where |contribution| is largest, and its RMS.
  double contribution_rms = 0.0;
  double time_range[2] = {0.0, 0.0}, position_range[2] = {0.0, 0.0}, velocity_range[2] = {0.0, 0.0};
  std::string description;                   // in words, with the figures above
  // Products of the same modulator that the record cannot tell from this one (they fit within the ambiguity margin:
  // CheckMultiplierAmbiguity); empty when told apart or not checked.
  std::vector<std::string> alike;
  // The same products as diagnosed effects (their shape as found, their columns fitted beside the base), for `improve`
  // to try in this one's place: a record other than this one (its validation record) may tell them apart.
  std::vector<DiagnosedEffect> alike_effects;
  // Where the record places each of its change times ("change_time", "on_time", "off_time") [s]: the profile interval
  // of the final joint fit, low and high (change_time_interval.h); empty for an effect without one.
  std::map<std::string, std::array<double, 2>> time_intervals;
  // `parameters` as JSON for compare.json and improve.json: a count (a parameter without a unit in the effect
  // registry, whole-valued: the harmonics) as an integer, not 2.0.
  nlohmann::json ParametersJson() const;
};

struct DiagnosisResult {
  // The missing effects by base_share, highest first, then the friction-law replacements (the summary's order; the
  // order they are applied in: EffectsInApplicationOrder, tools/workflow/suggest.h).
  std::vector<DiagnosedEffect> effects;
  bool missing_effect_found = false;
  bool position_time_indistinguishable = false;
  std::string summary;                       // one paragraph for users
  std::string position_unit = "m";           // the position's unit (DiagnosisOptions::position_unit), for texts
  // Simulation mode: the closed loop the effects' forces reach the output through (CatalogueOptions::loop); null in
  // equation-error mode. EffectContribution and PredictCorrection apply it.
  std::shared_ptr<const LoopResponse> loop;
  std::vector<std::string> notes;            // supporting evidence and caveats

  double rmse_before = 0.0;                  // RMSE of the residual as given
  double rmse_base_refit = 0.0;              // after refitting the base regressors (in-sample)
  double rmse_after = 0.0;                   // after the joint fit of base + chosen effects (in-sample)
  double heldout_rmse_base = 0.0;            // cross-validated, base regressors only
  double heldout_rmse_after = 0.0;           // cross-validated, base + chosen effects
  double explained_share = 0.0;              // 1 − heldout_mse_after/heldout_mse_base
  // The record's noise floor (EstimateNoiseFloor of the base-refit residual, with AddQuantizationFloor's part in
  // equation-error mode): no model can do better than about this
  // RMS [unit of the output]; 0 when the record is too short to tell.
  NoiseFloor noise_floor;

  std::vector<std::string> base_names;
  Eigen::VectorXd base_coefficients;         // corrections to the base parameters (joint fit)
  Eigen::VectorXd base_coefficient_std;
  double condition_number = 0.0;             // of the final (unit-RMS-scaled) regressor matrix

  AutocorrelationTest whiteness_before;      // of the base-refit residual
  AutocorrelationTest whiteness_after;       // after the chosen effects
  std::vector<PeriodogramPeak> position_peaks;  // position periodogram of the base-refit residual [m]
  std::vector<PeriodogramPeak> time_peaks;      // time periodogram [s]
  std::vector<EffectInstance> candidates;       // everything that was tried
  // The friction-law replacements chosen (EffectTraits::friction_law_replacement; also in `effects`): the model's
  // friction law near zero velocity is wrong; the other effects were searched in what they leave.
  std::vector<std::string> friction_law;
  double robust_weight_share = 1.0;             // mean Huber weight of the final fit (1 = no sample down-weighted)
  // What the residual left after the chosen effects depends on (RankSignalRelevance): each signal's held-out share,
  // most relevant first — the answer when no term fits.
  std::vector<SignalRelevance> relevance;

  // The chosen effects as instances (to rebuild regressors on new data).
  std::vector<EffectInstance> chosen() const;
  // JSON for reports: every field above (Eigen vectors as arrays).
  nlohmann::json ToJson() const;
};

// Runs the ranking. signals.residual = measured − model; base as described above.
// Throws std::invalid_argument as DiagnosisSignals::Validate, when base.columns has the wrong number of
// rows or names, or when options are out of range (folds < 2 or > N/16, min_gain not in [0, 1), redundant_with_base not in (0, 1]).
DiagnosisResult DiagnoseMissingEffects(const DiagnosisSignals& signals, const BaseRegressors& base,
                                       const DiagnosisOptions& options = {});

// One chosen effect's part of the compared output on `signals` [output unit]: its regressors times its coefficients,
// in simulation mode through the closed loop (DiagnosisResult::loop; an effect of the measurement chain, EffectTraits::
// regressor_in_output_band, acts on the output directly). Throws as BuildEffectRegressors and LoopResponse::Apply.
Eigen::VectorXd EffectContribution(const DiagnosisResult& result, const DiagnosedEffect& effect,
                                   const DiagnosisSignals& signals);

// The correction the diagnosis fitted (base-parameter corrections + chosen effects, EffectContribution), evaluated on
// other signals (e.g. a validation record): subtract it from that record's residual to see the error fall.
// base must hold the same regressors (same order) built on the new signals.
// Throws std::invalid_argument as BuildEffectRegressors, or on a size mismatch.
Eigen::VectorXd PredictCorrection(const DiagnosisResult& result, const DiagnosisSignals& signals,
                                  const BaseRegressors& base);

// Residual binned against an abscissa (friction shape vs velocity, ripple vs position): per uniform bin
// over [min, max], the bin centre, count, mean and standard deviation of the residual (NaN-free: empty
// bins have count 0, mean 0, std 0). Throws std::invalid_argument on a size mismatch, bins < 1, or a
// constant abscissa.
struct BinnedResidual {
  Eigen::VectorXd centers, mean, std;
  Eigen::VectorXi count;
};
BinnedResidual BinResidual(const Eigen::Ref<const Eigen::VectorXd>& abscissa,
                           const Eigen::Ref<const Eigen::VectorXd>& residual, Eigen::Index bins = 40);

}  // namespace mb

#pragma once
// What an effect's proposal rule (EffectType::propose) works with: the signals, the residual after the base
// refit, the base's regressors, the options, and the analyses that several effects share — the position and
// time periodograms of the residual, the motion's own repetition frequency, the position periods worth
// proposing. ProposeCandidateEffects (effect_catalogue.h) builds one context and calls every registered effect's
// rule in catalogue order; the rules add candidates and notes to it.

#include <algorithm>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "models/diagnosis/effect_catalogue.h"

namespace mb {

/// A position period worth proposing: a strong independent peak of the residual's position periodogram.
struct ProposedPeriod {
  double period = 0.0;  ///< [m]; a sub-harmonic found in the periodogram makes it k × the peak's period
  int harmonics = 1;    ///< 1 + the highest harmonic order flagged, at most CatalogueOptions::max_harmonics
  double power = 0.0;   ///< its periodogram peak's share of the residual's variance, 0..1 (PeriodogramPeak::power)
};

/// Where one effect's proposal rule puts its candidates and notes when the rules run concurrently
/// (ProposeCandidateEffects merges the sinks in catalogue order: the same list as a serial run).
struct ProposalSink {
  std::vector<EffectInstance> candidates;
  std::vector<std::string> notes;
};

class ProposalContext {
 public:
  /// Runs the shared analyses: the position periodogram (when the position moves; max_period automatic =
  /// travel/min_position_cycles), the time periodogram of the residual and the motion's repetition frequency
  /// (the strongest period of the position in time), written to `search`. The arguments must outlive the context.
  /// Throws as PositionPeriodogram and TimePeriodogram.
  ProposalContext(const DiagnosisSignals& signals, const Eigen::VectorXd& residual,
                  const Eigen::MatrixXd& base_columns, const CatalogueOptions& options, CandidateSearch* search);

  const DiagnosisSignals& signals() const { return signals_; }
  /// The residual after the base refit (N).
  const Eigen::VectorXd& residual() const { return residual_; }
  /// The base model's regressors (N × p, p may be 0).
  const Eigen::MatrixXd& base_columns() const { return *base_columns_; }
  const CatalogueOptions& options() const { return options_; }
  /// Simulation mode: the closed loop a candidate force reaches the output through (CatalogueOptions::loop); null in
  /// equation-error mode. Pass it to JointFitResidual for every joint fit of candidate forces.
  const LoopResponse* loop() const { return options_.loop.get(); }
  const CandidateSearch& search() const { return *search_; }
  Eigen::Index size() const { return signals_.size(); }

  double max_speed() const { return max_speed_; }         ///< max |v| [m/s]
  double dead_band() const { return dead_band_; }         ///< of sign(v): dead_band_fraction × max |v| [m/s]
  double position_span() const { return position_span_; }  ///< max x − min x [m]
  double sample_period() const { return sample_period_; }   ///< median time step [s]
  /// The base's regressors with a constant column appended (N × (p + 1)), for joint fits in parameter searches.
  Eigen::MatrixXd BaseWithConstant() const;
  /// Equation-error mode: how many samples at each end of the record the derived motion is still its derivative
  /// filter's edge transient — FilterEdgeSamples (signal_processing.h) at the band limit (CatalogueOptions::
  /// band_limit_hz): two periods of it, at most 5 % of the record. Not the physics: a sweep's first kick of the
  /// controller there is a hundred times the noise, and a search that weighs it is drawn to it. 0 in simulation mode
  /// (the position is compared as logged) or without a band limit.
  Eigen::Index edge_samples() const;
  /// Up to CatalogueOptions::max_position_periods periods from the position periodogram, strongest first
  /// (empty when the position does not move), and the few-cycle periods (CatalogueOptions::
  /// min_position_cycles_with_harmonics to min_position_cycles cycles in the travel: a short stroke) that their
  /// harmonics confirm, or that, without harmonics, fit the residual better than a cubic of the position on held-out
  /// contiguous blocks (5 folds, jointly with the base), placed by their power.
  const std::vector<ProposedPeriod>& position_periods() const { return position_periods_; }

  /// EstimateModelOutputDelay(*this), computed once (time_delay and actuator_lag both ask) and shared with the
  /// copies WithSink makes; thread-safe (a second caller waits for, or helps, the first).
  double model_output_delay() const;

  /// A copy that adds its candidates and notes to `sink` (which must outlive it) instead of the search: one effect's
  /// rule run concurrently with the others'. The analyses and the model-output delay are shared.
  ProposalContext WithSink(ProposalSink* sink) const;
  /// A copy whose base regressors are `base_columns` (N × p′; must outlive it), the residual and the analyses kept: a
  /// shape scan that fits a pair's own columns beside the base's (a multiplier's level, MultiplierRow::own_level).
  ProposalContext WithBase(const Eigen::MatrixXd& base_columns) const;

  /// Adds a candidate (catalogue name, SI parameters) to the search, or to the sink of a WithSink copy.
  void Propose(std::string effect, std::map<std::string, double> parameters = {});
  /// Adds a note for the report (why something was or was not proposed), to the search or the sink.
  void Note(std::string note);

 private:
  const DiagnosisSignals& signals_;
  const Eigen::VectorXd& residual_;
  const Eigen::MatrixXd* base_columns_;
  const CatalogueOptions& options_;
  CandidateSearch* search_;
  ProposalSink* sink_ = nullptr;
  // Adds the periods of too few cycles for the main search that their harmonics confirm (CatalogueOptions).
  // `main`: the periodogram whose peaks confirm their harmonics.
  void AddFewCyclePeriods(const Eigen::VectorXd& position, const Eigen::VectorXd& residual, const Periodogram& main);
  // Simulation mode: adds the periods of the output residual's own position periodogram that the force's lacks, the
  // few-cycle ones too.
  void AddOutputPeriods(const DiagnosisSignals& signals, const Eigen::VectorXd& residual);
  double max_speed_ = 0.0, dead_band_ = 0.0, position_span_ = 0.0, sample_period_ = 0.0;
  std::vector<ProposedPeriod> position_periods_;
  struct OutputDelayOnce;  // the delay and its once-flag (effect_proposal.cc)
  std::shared_ptr<OutputDelayOnce> model_output_delay_;
};

/// Harmonics of peak `index` of a periodogram: 1 + the highest positive harmonic order flagged against it, at
/// most max_harmonics.
int HarmonicCount(const Periodogram& periodogram, std::size_t index, int max_harmonics);

/// Residual sum of squares of the least-squares fit of r on [base, extra] (normal equations, small ridge).
double ResidualSumOfSquares(const Eigen::MatrixXd& base, const Eigen::Ref<const Eigen::MatrixXd>& extra,
                            const Eigen::VectorXd& r);

/// ResidualSumOfSquares for many `extra` with one base B (N × p) and one r (N): BᵀB, Bᵀr and rᵀr are formed once
/// (N·p²), so each fit costs N·k·(p + k) for k extra columns instead of N·(p + k)² — what a one-parameter scan of
/// the joint fit repeats tens of times. The normal equations of [B, extra] are scaled to unit column norms and
/// given a ridge of 1e-10 on the diagonal; the sum of squares is rᵀr − 2βᵀXᵀr + βᵀXᵀXβ (clamped at 0), in r's
/// unit squared. Keeps references to `base` and `r`, which must outlive it; `extra` (N × k, k ≥ 0) must have N rows
/// (a shape error is Eigen's assertion, not an exception). Throws nothing else. Source: the normal equations of
/// linear least squares (Björck, "Numerical Methods for Least Squares Problems", SIAM 1996, §2.1).
class JointFitResidual {
 public:
  /// `loop` (simulation mode, ProposalContext::loop; must outlive it): each `extra` is a force, passed through the
  /// closed loop (LoopResponse::Apply) before the fit, whose base and r are then in the compared output's unit.
  JointFitResidual(const Eigen::MatrixXd& base, const Eigen::VectorXd& r, const LoopResponse* loop = nullptr);
  /// A temporary base would dangle (the references above): name it first.
  JointFitResidual(Eigen::MatrixXd&& base, const Eigen::VectorXd& r, const LoopResponse* loop = nullptr) = delete;
  JointFitResidual(const Eigen::MatrixXd& base, Eigen::VectorXd&& r, const LoopResponse* loop = nullptr) = delete;
  /// The same with BᵀB given (p × p, formed as base.transpose() * base): for a scan whose r changes but not B.
  JointFitResidual(const Eigen::MatrixXd& base, const Eigen::MatrixXd& base_gram, const Eigen::VectorXd& r,
                   const LoopResponse* loop = nullptr);
  /// The residual sum of squares of r on [base, extra]; extra_coefficients (optional): extra's coefficients in that
  /// fit (k, in the unit of r per unit of each column).
  double operator()(const Eigen::Ref<const Eigen::MatrixXd>& extra,
                    Eigen::VectorXd* extra_coefficients = nullptr) const;

 private:
  const Eigen::MatrixXd& base_;
  const Eigen::VectorXd& r_;
  Eigen::MatrixXd base_gram_;      // BᵀB (p × p)
  Eigen::VectorXd base_moment_;    // Bᵀr (p)
  double r_squared_ = 0.0;         // rᵀr
  const LoopResponse* loop_ = nullptr;
};

/// Does the model have a Coulomb law (sign(v)) to replace? One base column is sign(v) over the moving samples
/// (faster than 10 % of max |v|: squared correlation ≥ 0.97; at rest the model's law chatters on velocity noise,
/// which is what the friction-law replacements are about). The replacements and coulomb_friction ask this.
bool BaseHasCoulombLaw(const ProposalContext& context);
/// The same on the base's columns (N × p) and the velocity (N) themselves.
bool HasCoulombLaw(const Eigen::MatrixXd& base_columns, const Eigen::VectorXd& velocity);
/// The index of the base column that is the model's Coulomb law (as HasCoulombLaw judges it; the first such), or −1.
Eigen::Index CoulombLawColumn(const Eigen::MatrixXd& base_columns, const Eigen::VectorXd& velocity);

/// Golden-section search for the minimum of `cost` on [lo, hi] (lo < hi, cost assumed unimodal there) until the bracket
/// is narrower than `tolerance` × |its midpoint| (at most 60 steps); returns the last bracket's midpoint, in the unit of
/// lo and hi. Throws what cost throws. Source: Kiefer, "Sequential minimax search for a maximum", Proc. AMS 4, 1953;
/// Press et al., "Numerical Recipes", 3rd ed., §10.2.
double GoldenSectionMinimum(const std::function<double(double)>& cost, double lo, double hi, double tolerance);

/// The minimum of sse(value) over [lo, hi] (0 < lo < hi): a log grid of `grid` points (>= 3), then a golden-section
/// search in log between the best point's neighbours (`iterations` steps); the grid's best when the search ends higher.
/// parallel_grid: the grid's points evaluated concurrently (TBB; sse must then be thread-safe), the same result.
double MinimiseOnLogGrid(double lo, double hi, int grid, int iterations, const std::function<double(double)>& sse,
                         bool parallel_grid = false);

/// A one-parameter scan of the joint fit: the value in [lo, hi] (log grid of `grid` points, then golden section in
/// log between the best point's neighbours) minimising the residual sum of squares of the residual on
/// [base, 1, columns(value)]. Returns 0 when lo or hi is not positive or lo >= hi. The grid's values are tried in
/// parallel: columns must be thread-safe (a pure function of the value).
double ScanJointFit(const ProposalContext& context, double lo, double hi, int grid,
                    const std::function<Eigen::MatrixXd(double)>& columns);

/// The lag of the measured output behind the model output ŷ that the residual holds, signed [s]: d > 0 when the
/// measurement lags the model (measured ≈ ŷ(t − d): a sensor or logging delay), d < 0 when it leads it (measured ≈
/// ŷ(t + |d|): in equation-error mode, a logged command that acts |d| later — an actuator lag). A first guess d0 = −c
/// from the least-squares fit of r on [1, dŷ/dt] (for a small delay r ≈ −d·dŷ/dt; DIAGNOSIS.md, `resid`), then a
/// log-grid scan of |d| over [|d0|/8, 8|d0|] and a golden-section refinement of the joint fit of r on
/// [base, 1, ŷ(t − d) − ŷ(t)]. 0 when the signals carry no model output, the guess is not finite, or |d| stays
/// below CatalogueOptions::min_delay_samples sample periods (what the data do not resolve). Throws nothing.
double EstimateModelOutputDelay(const ProposalContext& context);

/// `x` (the record's first x.rows() rows, x.rows() × k) with the derived motion's edge transients zeroed — its first
/// `edge` rows (ProposalContext::edge_samples), and its last `edge` where it reaches the record's end (`record_size`
/// rows) — so that a least-squares fit leaves them out. Throws nothing.
template <typename M>
M WithoutEdges(M x, Eigen::Index edge, Eigen::Index record_size) {
  const Eigen::Index cut = std::min(edge, static_cast<Eigen::Index>(x.rows()));
  x.topRows(cut).setZero();
  if (x.rows() == record_size) x.bottomRows(cut).setZero();
  return x;
}

}  // namespace mb

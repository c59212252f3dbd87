#include "models/diagnosis/effect_proposal.h"

#include <algorithm>
#include <cmath>
#include <exception>
#include <limits>
#include <utility>
#include <vector>

#include <Eigen/Dense>
#include <fmt/format.h>
#include <tbb/collaborative_call_once.h>
#include <tbb/parallel_for.h>
#include <tbb/parallel_invoke.h>

#include "models/diagnosis/effect_regressors.h"
#include "models/diagnosis/parameter_text.h"
#include "models/diagnosis/signal_processing.h"

namespace mb {
namespace {

constexpr double kForceRegularisation = 1e-3;  // Wiener's λ over max |H|² for the spectra in simulation mode

// The strongest independent peaks of the position periodogram, each at its true period: a weaker peak at k·P
// (a sub-harmonic) means the period is k·P; periods beyond the search range are left out.
std::vector<ProposedPeriod> PositionPeriods(const Periodogram& pg, const CatalogueOptions& options) {
  std::vector<ProposedPeriod> out;
  for (std::size_t i = 0; i < pg.peaks.size() && static_cast<int>(out.size()) < options.max_position_periods; ++i) {
    if (pg.peaks[i].harmonic_of >= 0) continue;
    int sub = 1;
    for (const auto& p : pg.peaks) {
      if (p.harmonic_of == static_cast<int>(i) && p.harmonic_order < 0) sub = std::max(sub, -p.harmonic_order);
    }
    const double period = pg.peaks[i].period * sub;
    if (period > pg.max_period) continue;
    out.push_back({period, std::min(options.max_harmonics, sub * HarmonicCount(pg, i, options.max_harmonics)),
                   pg.peaks[i].power});
  }
  return out;
}

// Periods of fewer cycles than the main search allows (its max_period up to travel/min_position_cycles_with_harmonics):
// a significant peak of their own periodogram whose harmonic P/k (k = 2..8) the main periodogram holds too. Harmonics:
// 1 + the highest such k, at most max_harmonics.
std::vector<std::pair<ProposedPeriod, double>> FewCyclePeriods(const Eigen::VectorXd& position,
                                                               const Eigen::VectorXd& residual, const Periodogram& main,
                                                               double span, const CatalogueOptions& options) {
  std::vector<std::pair<ProposedPeriod, double>> out;  // with the peak's power
  const double longest = span / options.min_position_cycles_with_harmonics;
  if (!(longest > main.max_period) || main.peaks.empty()) return out;
  PeriodogramOptions po = options.position_periodogram;
  po.min_period = main.max_period;
  po.max_period = longest;
  po.max_peaks = 3;
  const Periodogram few = PositionPeriodogram(position, residual, po);
  for (const PeriodogramPeak& peak : few.peaks) {
    if (!peak.significant || peak.harmonic_of >= 0) continue;
    int highest = 0;
    for (const PeriodogramPeak& p : main.peaks) {
      const double k = std::round(peak.period / p.period);
      if (k >= 2.0 && k <= 8.0 && std::abs(peak.period / p.period - k) <= options.position_periodogram.harmonic_tolerance * k) {
        highest = std::max(highest, static_cast<int>(k));
      }
    }
    // Without harmonics (harmonics 0 here): a candidate only if it beats a smooth function of the position on
    // held-out blocks (ProposalContext::AddFewCyclePeriods).
    out.push_back({{peak.period, highest > 0 ? std::min(options.max_harmonics, highest) : 0, peak.power}, peak.power});
  }
  return out;
}

// The contiguous-block cross-validated sum of squares of the least-squares fit of r on [base, extra] (`folds` blocks,
// each predicted from the others; a small ridge on the unit-scaled normal equations).
double HeldOutSumOfSquares(const Eigen::MatrixXd& base, const Eigen::MatrixXd& extra, const Eigen::VectorXd& r,
                           int folds) {
  const Eigen::Index n = r.size(), p = base.cols() + extra.cols();
  Eigen::MatrixXd x(n, p);
  x << base, extra;
  const Eigen::MatrixXd gram = x.transpose() * x;
  const Eigen::VectorXd moment = x.transpose() * r;
  double sse = 0.0;
  for (int f = 0; f < folds; ++f) {
    const Eigen::Index begin = n * f / folds, end = n * (f + 1) / folds;
    const auto block = x.middleRows(begin, end - begin);
    Eigen::MatrixXd g = gram - block.transpose() * block;
    const Eigen::VectorXd m = moment - block.transpose() * r.segment(begin, end - begin);
    const Eigen::VectorXd scale = (g.diagonal().array().sqrt() + 1e-300).inverse();
    g = scale.asDiagonal() * g * scale.asDiagonal();
    g.diagonal().array() += 1e-10;
    const Eigen::VectorXd beta = scale.cwiseProduct(g.ldlt().solve(scale.cwiseProduct(m)));
    sse += (r.segment(begin, end - begin) - block * beta).squaredNorm();
  }
  return sse;
}

// A smooth function of the position over the travel: ξ, ξ², ξ³ with ξ = (x − centre)/half-range (what
// position_dependent_force proposes).
Eigen::MatrixXd SmoothOfPosition(const Eigen::VectorXd& x) {
  const double centre = 0.5 * (x.maxCoeff() + x.minCoeff()), half = 0.5 * (x.maxCoeff() - x.minCoeff());
  const Eigen::ArrayXd xi = (x.array() - centre) / half;
  Eigen::MatrixXd out(x.size(), 3);
  out << xi.matrix(), (xi * xi).matrix(), (xi * xi * xi).matrix();
  return out;
}

// The position and residual of the samples moving faster than `dead_band` (all samples when fewer than a quarter move).
std::pair<Eigen::VectorXd, Eigen::VectorXd> MovingSamples(const DiagnosisSignals& signals, const Eigen::VectorXd& residual,
                                                          double dead_band) {
  std::vector<Eigen::Index> moving;
  for (Eigen::Index i = 0; i < signals.size(); ++i) {
    if (std::abs(signals.velocity(i)) > dead_band) moving.push_back(i);
  }
  if (4 * static_cast<Eigen::Index>(moving.size()) < signals.size()) return {signals.position, residual};
  Eigen::VectorXd x(static_cast<Eigen::Index>(moving.size())), r(x.size());
  for (std::size_t k = 0; k < moving.size(); ++k) {
    x(static_cast<Eigen::Index>(k)) = signals.position(moving[k]);
    r(static_cast<Eigen::Index>(k)) = residual(moving[k]);
  }
  return {x, r};
}

}  // namespace

struct ProposalContext::OutputDelayOnce {
  tbb::collaborative_once_flag flag;  // waiting callers help rather than block a TBB worker
  double delay = 0.0;
};

ProposalContext::ProposalContext(const DiagnosisSignals& signals, const Eigen::VectorXd& residual,
                                 const Eigen::MatrixXd& base_columns, const CatalogueOptions& options,
                                 CandidateSearch* search)
    : signals_(signals), residual_(residual), base_columns_(&base_columns), options_(options), search_(search),
      model_output_delay_(std::make_shared<OutputDelayOnce>()) {
  max_speed_ = signals.velocity.cwiseAbs().maxCoeff();
  dead_band_ = options.dead_band_fraction * max_speed_;
  position_span_ = signals.position.maxCoeff() - signals.position.minCoeff();
  sample_period_ = MedianTimeStep(signals.time);
  // A periodogram the record cannot support (e.g. position steps so large against the travel that the period range
  // is empty) is skipped with a note: the effects that need it are not proposed, the others are.
  const auto skipped = [&](const char* what, const std::exception& e) {
    Note(fmt::format("{} skipped on this record: {}", what, NoteText(e.what())));
  };
  // The three periodograms are independent: computed in parallel, then used (and their failures noted) in order.
  // Simulation mode: the spectra are read on the force the residual is (LoopResponse::ForceOf), since every candidate
  // is a force and the loop shapes the position's spectrum (a force's peak above the loop's bandwidth is lost in it);
  // the position periods the output's own periodogram holds are proposed too (a slow force the loop lets through
  // stands out there).
  const Eigen::VectorXd spectral = options.loop ? options.loop->ForceOf(residual, kForceRegularisation) : residual;
  const std::pair<Eigen::VectorXd, Eigen::VectorXd> moving = position_span_ > 0.0
                                                                  ? MovingSamples(signals, spectral, dead_band_)
                                                                  : std::pair<Eigen::VectorXd, Eigen::VectorXd>();
  const Eigen::VectorXd& position = moving.first;
  const Eigen::VectorXd& moving_residual = moving.second;
  std::exception_ptr position_error, time_error, motion_error;
  Periodogram motion;
  const auto guarded = [](std::exception_ptr* error, const auto& compute) {
    try {
      compute();
    } catch (...) {
      *error = std::current_exception();
    }
  };
  tbb::parallel_invoke(
      [&] {
        if (!(position_span_ > 0.0)) return;
        PeriodogramOptions po = options.position_periodogram;
        if (po.max_period <= 0.0) po.max_period = position_span_ / options.min_position_cycles;
        // Only the samples in motion: while the machine dwells its samples pile up at a few positions, and a fine
        // period fits their means by chance (a "ripple" of 0.4 mm was named first on a point-to-point record whose
        // dwells hold a smooth spring force).
        guarded(&position_error,
                [&] { search->position_periodogram = PositionPeriodogram(position, moving_residual, po); });
      },
      [&] {
        guarded(&time_error,
                [&] { search->time_periodogram = TimePeriodogram(signals.time, spectral, options.time_periodogram); });
      },
      [&] {
        if (!(position_span_ > 0.0)) return;
        PeriodogramOptions mo = options.time_periodogram;
        mo.max_peaks = 1;  // only the strongest (the first found: best() is the same)
        guarded(&motion_error, [&] { motion = TimePeriodogram(signals.time, signals.position, mo); });
      });
  if (position_span_ > 0.0) {
    try {
      if (position_error) std::rethrow_exception(position_error);
      position_periods_ = PositionPeriods(search->position_periodogram, options);
      if (options.loop) AddOutputPeriods(signals, residual);
      AddFewCyclePeriods(position, moving_residual, search->position_periodogram);
    } catch (const std::invalid_argument& e) {
      skipped("the position periodogram (position-periodic candidates)", e);
    }
  }
  try {
    if (time_error) std::rethrow_exception(time_error);
  } catch (const std::invalid_argument& e) {
    skipped("the time periodogram (time-periodic candidates)", e);
  }
  if (position_span_ > 0.0) {
    try {
      if (motion_error) std::rethrow_exception(motion_error);
      search->motion_frequency_hz = 1.0 / motion.best().period;
    } catch (const std::exception& e) {
      skipped("the motion's repetition frequency", e);
    }
  }
}

void ProposalContext::AddOutputPeriods(const DiagnosisSignals& signals, const Eigen::VectorXd& residual) {
  const auto [position, moving_residual] = MovingSamples(signals, residual, dead_band_);
  PeriodogramOptions po = options_.position_periodogram;
  if (po.max_period <= 0.0) po.max_period = position_span_ / options_.min_position_cycles;
  const Periodogram output = PositionPeriodogram(position, moving_residual, po);
  for (const ProposedPeriod& period : PositionPeriods(output, options_)) {
    const bool known = std::any_of(position_periods_.begin(), position_periods_.end(), [&](const ProposedPeriod& p) {
      return std::abs(p.period - period.period) <= 0.01 * period.period;
    });
    if (!known) position_periods_.push_back(period);
  }
  AddFewCyclePeriods(position, moving_residual, output);
}

void ProposalContext::AddFewCyclePeriods(const Eigen::VectorXd& position, const Eigen::VectorXd& residual,
                                         const Periodogram& main) {
  if (options_.position_periodogram.max_period > 0.0) return;  // the user chose the band
  for (auto [period, power] : FewCyclePeriods(position, residual, main, position_span_, options_)) {
    if (period.harmonics == 0) {  // a short stroke's period on its own: only if it beats a smooth force of position
      const Eigen::MatrixXd base = BaseWithConstant();
      const double periodic =
          HeldOutSumOfSquares(base, PeriodicColumns(signals_.position, period.period, 1, "p").columns, residual_, 5);
      const double smooth = HeldOutSumOfSquares(base, SmoothOfPosition(signals_.position), residual_, 5);
      if (!(periodic < smooth)) {
        Note(fmt::format("a position period of {:.3g} cycles in the travel ({:.4g}) not proposed: without harmonics it "
                         "does not beat a smooth force of position (cubic) on held-out blocks",
                         position_span_ / period.period, period.period));
        continue;
      }
      period.harmonics = 1;
    }
    // In the order of power among the main periodogram's proposals (strongest first).
    auto at = position_periods_.begin();
    while (at != position_periods_.end()) {
      double p = 0.0;
      for (const auto& peak : main.peaks) if (std::abs(peak.period - at->period) <= 1e-9 * at->period) p = peak.power;
      if (power > p) break;
      ++at;
    }
    position_periods_.insert(at, period);
    Note(period.harmonics > 1
             ? fmt::format("a position period of only {:.3g} cycles in the travel ({:.4g}) proposed: the residual holds "
                           "its harmonics too (up to {})",
                           position_span_ / period.period, period.period, period.harmonics)
             : fmt::format("a position period of only {:.3g} cycles in the travel ({:.4g}) proposed: significant, and "
                           "it beats a smooth force of position on held-out blocks",
                           position_span_ / period.period, period.period));
  }
}

Eigen::MatrixXd ProposalContext::BaseWithConstant() const {
  Eigen::MatrixXd base(size(), base_columns_->cols() + 1);
  base << *base_columns_, Eigen::VectorXd::Ones(size());
  return base;
}

void ProposalContext::Propose(std::string effect, std::map<std::string, double> parameters) {
  (sink_ != nullptr ? sink_->candidates : search_->candidates).push_back({std::move(effect), std::move(parameters)});
}

void ProposalContext::Note(std::string note) {
  (sink_ != nullptr ? sink_->notes : search_->notes).push_back(std::move(note));
}

ProposalContext ProposalContext::WithSink(ProposalSink* sink) const {
  ProposalContext copy = *this;
  copy.sink_ = sink;
  return copy;
}

ProposalContext ProposalContext::WithBase(const Eigen::MatrixXd& base_columns) const {
  ProposalContext copy = *this;
  copy.base_columns_ = &base_columns;
  return copy;
}

Eigen::Index ProposalContext::edge_samples() const {
  if (loop() != nullptr) return 0;
  return FilterEdgeSamples(size(), sample_period(), options().band_limit_hz);
}

double ProposalContext::model_output_delay() const {
  OutputDelayOnce& once = *model_output_delay_;
  tbb::collaborative_call_once(once.flag, [&] { once.delay = EstimateModelOutputDelay(*this); });
  return once.delay;
}

int HarmonicCount(const Periodogram& pg, std::size_t index, int max_harmonics) {
  int h = 1;
  for (const auto& p : pg.peaks) {
    if (p.harmonic_of == static_cast<int>(index) && p.harmonic_order > 0) h = std::max(h, p.harmonic_order);
  }
  return std::min(h, max_harmonics);
}

JointFitResidual::JointFitResidual(const Eigen::MatrixXd& base, const Eigen::VectorXd& r, const LoopResponse* loop)
    : base_(base), r_(r), base_gram_(base.transpose() * base), base_moment_(base.transpose() * r),
      r_squared_(r.squaredNorm()), loop_(loop) {}

JointFitResidual::JointFitResidual(const Eigen::MatrixXd& base, const Eigen::MatrixXd& base_gram,
                                   const Eigen::VectorXd& r, const LoopResponse* loop)
    : base_(base), r_(r), base_gram_(base_gram), base_moment_(base.transpose() * r), r_squared_(r.squaredNorm()),
      loop_(loop) {}

double JointFitResidual::operator()(const Eigen::Ref<const Eigen::MatrixXd>& forces,
                                     Eigen::VectorXd* extra_coefficients) const {
  // Simulation mode: the candidate forces as the compared output sees them through the closed loop.
  Eigen::MatrixXd through_loop;
  if (loop_ != nullptr) through_loop = loop_->Apply(forces);
  const Eigen::Ref<const Eigen::MatrixXd> extra = loop_ != nullptr ? Eigen::Ref<const Eigen::MatrixXd>(through_loop) : forces;
  const Eigen::Index p = base_.cols(), k = extra.cols();
  Eigen::MatrixXd gram(p + k, p + k);
  gram.topLeftCorner(p, p) = base_gram_;
  gram.bottomLeftCorner(k, p) = extra.transpose() * base_;
  gram.topRightCorner(p, k) = gram.bottomLeftCorner(k, p).transpose();
  gram.bottomRightCorner(k, k) = extra.transpose() * extra;
  Eigen::VectorXd moment(p + k);
  moment << base_moment_, extra.transpose() * r_;
  // Unit column norms (the scaling that keeps the ridge relative), then the ridge.
  const Eigen::VectorXd scale = (gram.diagonal().array().sqrt() + 1e-300).inverse();
  const Eigen::MatrixXd scaled = scale.asDiagonal() * gram * scale.asDiagonal();
  const Eigen::VectorXd scaled_moment = scale.cwiseProduct(moment);
  Eigen::MatrixXd ridged = scaled;
  ridged.diagonal().array() += 1e-10;
  const Eigen::VectorXd beta = ridged.ldlt().solve(scaled_moment);
  if (extra_coefficients != nullptr) *extra_coefficients = beta.tail(k).cwiseProduct(scale.tail(k));
  return std::max(0.0, r_squared_ - 2.0 * beta.dot(scaled_moment) + beta.dot(scaled * beta));
}

double ResidualSumOfSquares(const Eigen::MatrixXd& base, const Eigen::Ref<const Eigen::MatrixXd>& extra,
                            const Eigen::VectorXd& r) {
  return JointFitResidual(base, r)(extra);
}

Eigen::Index CoulombLawColumn(const Eigen::MatrixXd& base_columns, const Eigen::VectorXd& velocity) {
  const double max_speed = velocity.size() > 0 ? velocity.cwiseAbs().maxCoeff() : 0.0;
  if (!(max_speed > 0.0)) return -1;
  const Eigen::VectorXd mask = (velocity.array().abs() > 0.1 * max_speed).cast<double>();
  const Eigen::VectorXd sign = SignDeadBand(velocity, 0.0).cwiseProduct(mask);
  for (Eigen::Index j = 0; j < base_columns.cols(); ++j) {  // one column that is sign(v) while moving
    const Eigen::VectorXd c = base_columns.col(j).cwiseProduct(mask);
    const double denominator = c.squaredNorm() * sign.squaredNorm();
    if (denominator > 0.0 && c.dot(sign) * c.dot(sign) / denominator >= 0.97) return j;
  }
  return -1;
}

bool HasCoulombLaw(const Eigen::MatrixXd& base_columns, const Eigen::VectorXd& velocity) {
  return CoulombLawColumn(base_columns, velocity) >= 0;
}

bool BaseHasCoulombLaw(const ProposalContext& context) {
  return HasCoulombLaw(context.base_columns(), context.signals().velocity);
}

double GoldenSectionMinimum(const std::function<double(double)>& cost, double lo, double hi, double tolerance) {
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
  double e1 = cost(x1), e2 = cost(x2);
  for (int it = 0; it < 60 && hi - lo > tolerance * std::abs(lo + hi) * 0.5; ++it) {
    if (e1 < e2) {
      hi = x2; x2 = x1; e2 = e1; x1 = hi - g * (hi - lo); e1 = cost(x1);
    } else {
      lo = x1; x1 = x2; e1 = e2; x2 = lo + g * (hi - lo); e2 = cost(x2);
    }
  }
  return 0.5 * (lo + hi);
}

double MinimiseOnLogGrid(double lo, double hi, int grid, int iterations, const std::function<double(double)>& sse,
                         bool parallel_grid) {
  const auto sse_log = [&](double log_value) { return sse(std::exp(log_value)); };
  const double a = std::log(lo), step = (std::log(hi) - a) / (grid - 1);
  // The grid's values are independent: with parallel_grid (sse then thread-safe) evaluated concurrently, the best
  // then taken in the grid's order as serially (the same result).
  std::vector<double> grid_sse(static_cast<std::size_t>(std::max(grid, 0)));
  const auto evaluate = [&](int i) { grid_sse[static_cast<std::size_t>(i)] = sse_log(a + i * step); };
  if (parallel_grid) {
    tbb::parallel_for(0, grid, evaluate);
  } else {
    for (int i = 0; i < grid; ++i) evaluate(i);
  }
  int best = 0;
  double best_sse = std::numeric_limits<double>::infinity();
  for (int i = 0; i < grid; ++i) {
    const double e = grid_sse[static_cast<std::size_t>(i)];
    if (e < best_sse) { best_sse = e; best = i; }
  }
  double l = a + std::max(0, best - 1) * step, h = a + std::min(grid - 1, best + 1) * step;
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  double x1 = h - g * (h - l), x2 = l + g * (h - l), e1 = sse_log(x1), e2 = sse_log(x2);
  for (int it = 0; it < iterations; ++it) {
    if (e1 < e2) { h = x2; x2 = x1; e2 = e1; x1 = h - g * (h - l); e1 = sse_log(x1); }
    else { l = x1; x1 = x2; e1 = e2; x2 = l + g * (h - l); e2 = sse_log(x2); }
  }
  const double found = 0.5 * (l + h);
  return std::exp(sse_log(found) <= best_sse ? found : a + best * step);
}

double ScanJointFit(const ProposalContext& context, double lo, double hi, int grid,
                    const std::function<Eigen::MatrixXd(double)>& columns) {
  if (!(lo > 0.0) || !(hi > lo) || grid < 3) return 0.0;
  const Eigen::MatrixXd base = context.BaseWithConstant();
  const JointFitResidual joint_fit(base, context.residual(), context.loop());
  // The columns' callbacks are pure functions of the value: the grid in parallel.
  return MinimiseOnLogGrid(lo, hi, grid, 20, [&](double value) { return joint_fit(columns(value)); }, true);
}

double EstimateModelOutputDelay(const ProposalContext& c) {
  const DiagnosisSignals& s = c.signals();
  const Eigen::Index n = c.size();
  if (s.model_output.size() != n) return 0.0;
  const Eigen::VectorXd& y = s.model_output;
  const Eigen::VectorXd& r = c.residual();
  const double ts = c.sample_period();
  const Eigen::MatrixXd base = c.BaseWithConstant();
  const Eigen::VectorXd dy = CentralDifference(s.time, y);
  Eigen::MatrixXd x(n, 2);
  x << Eigen::VectorXd::Ones(n), dy;
  const Eigen::Vector2d beta = x.colPivHouseholderQr().solve(r);
  const double d0 = -beta(1);
  if (!std::isfinite(d0) || !(std::abs(d0) > 1e-3 * ts)) return 0.0;
  const double sign = d0 > 0.0 ? 1.0 : -1.0;
  const JointFitResidual joint_fit(base, r);  // the base's Gram and moment once, not per trial delay
  auto sse = [&](double magnitude) {
    return joint_fit(ShiftedInTime(s.time, y, sign * magnitude) - y);
  };
  constexpr int kGrid = 25;
  const double lo_grid = std::abs(d0) / 8.0, ratio = std::pow(64.0, 1.0 / (kGrid - 1));
  int best = 0;
  double best_sse = std::numeric_limits<double>::infinity();
  for (int i = 0; i < kGrid; ++i) {
    const double e = sse(lo_grid * std::pow(ratio, i));
    if (e < best_sse) { best_sse = e; best = i; }
  }
  double lo = lo_grid * std::pow(ratio, best - 1), hi = lo_grid * std::pow(ratio, best + 1);
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
  double e1 = sse(x1), e2 = sse(x2);
  for (int it = 0; it < 30 && hi - lo > 1e-4 * lo; ++it) {
    if (e1 < e2) {
      hi = x2; x2 = x1; e2 = e1; x1 = hi - g * (hi - lo); e1 = sse(x1);
    } else {
      lo = x1; x1 = x2; e1 = e2; x2 = lo + g * (hi - lo); e2 = sse(x2);
    }
  }
  // A delay far below the sample period is not resolved by the data: what it "explains" is a free multiple of
  // dŷ/dt (on EMPS, −0.04 ms at 1 ms sampling), not a lag.
  const double delay = sign * 0.5 * (lo + hi);
  return std::abs(delay) >= c.options().min_delay_samples * ts ? delay : 0.0;
}

}  // namespace mb

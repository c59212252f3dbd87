// The profile interval of a chosen effect's change time and its posterior median (change_time_interval.h). Sources:
// Hinkley (1970), Biometrika 57(1); Siegmund (1988), International Statistical Review 56(1) — the likelihood-ratio
// interval for a change point; Smith (1975), Biometrika 62(2) — its posterior.
#include "models/diagnosis/change_time_interval.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string_view>
#include <tuple>

#include <Eigen/QR>
#include <tbb/parallel_for.h>

#include "models/diagnosis/candidate_matrix.h"
#include "models/diagnosis/effect_proposal.h"
#include "models/diagnosis/effect_registry.h"
#include "models/diagnosis/factors.h"
#include "models/diagnosis/forward_selection.h"

namespace mb::diagnosis_detail {
namespace {

constexpr int kProfileGrid = 100;                   // points across the record, 1 % of it apart
constexpr int kEdgeBisections = 8;                  // each end of the interval to 1/256 of a grid step
constexpr double kChiSquare95 = 3.841458820694124;  // χ²₁'s 95 % quantile
constexpr const char* kChangeTimes[] = {"change_time", "on_time", "off_time"};
constexpr double kResolvedCells = 3.0;              // an interval narrower than this many grid steps keeps the best fit

// The long-run variance of `e` (N): the variance of its batch means times the batch length.
double LongRunVariance(const Eigen::VectorXd& e, Eigen::Index batches) {
  const Eigen::VectorXd means = BatchMeans(e, batches);
  const double b = static_cast<double>(means.size());
  return (means.array() - means.mean()).square().sum() / (b - 1.0) * static_cast<double>(e.size()) / b;
}

// The median of the posterior ∝ exp(−(sse − lowest)/(2σ²)) over cells of equal width centred on `grid` (a flat
// prior), the density constant within each cell.
double PosteriorMedian(const std::vector<double>& grid, const std::vector<double>& sse, double lowest, double variance,
                       double cell) {
  std::vector<double> p(grid.size());
  double total = 0.0;
  for (std::size_t i = 0; i < grid.size(); ++i) {
    p[i] = std::isfinite(sse[i]) ? std::exp(-(sse[i] - lowest) / (2.0 * variance)) : 0.0;
    total += p[i];
  }
  double below = 0.0;
  for (std::size_t i = 0; i < grid.size(); ++i) {
    if (p[i] > 0.0 && below + p[i] >= 0.5 * total) return grid[i] - 0.5 * cell + cell * (0.5 * total - below) / p[i];
    below += p[i];
  }
  return grid.back();
}

}  // namespace

std::vector<TimeInterval> PlaceChangeTimes(Ranking* ranked, std::size_t position, const DiagnosisSignals& signals,
                                           const DiagnosisOptions& options) {
  RegressorMatrix& m = ranked->m;
  Candidate& c = m.cands[ranked->chosen.order[position]];
  const EffectType& type = *c.type;
  std::vector<TimeInterval> out;
  const Eigen::Index n = m.rows();
  if (n < 16 || m.sw.size() != n || signals.time.size() != n) return out;

  // The other chosen columns, weighted and scaled as the ranking holds them.
  std::vector<Eigen::Index> others;
  for (const Eigen::Index j : ranked->chosen.selected) {
    if (std::find(c.idx.begin(), c.idx.end(), j) == c.idx.end()) others.push_back(j);
  }
  Eigen::MatrixXd xo(n, static_cast<Eigen::Index>(others.size()));
  for (std::size_t j = 0; j < others.size(); ++j) {
    xo.col(static_cast<Eigen::Index>(j)) = m.sw.cwiseProduct(m.Col(others[j]));
  }
  const JointFitResidual profile(xo, m.wr);  // the weighted sum of squares with the effect's columns beside them
  // The effect's columns at `instance`, filtered like a candidate's (in simulation mode: through the loop), weighted.
  const auto unweighted_columns_at = [&](const EffectInstance& instance) {
    Eigen::MatrixXd columns = type.regressors(instance, signals).columns;
    FilterCandidateColumns(type, signals, options, &columns);
    return columns;
  };
  const auto columns_at = [&](const EffectInstance& instance) {
    return (unweighted_columns_at(instance).array().colwise() * m.sw.array()).matrix().eval();
  };

  const double t0 = signals.time(0), duration = signals.time(n - 1) - t0;
  for (const char* name : kChangeTimes) {
    const auto at = c.effect.parameters.find(name);
    if (at == c.effect.parameters.end() || !(duration > 0.0)) continue;
    // The estimate's own fit: its residual's long-run variance sets the threshold.
    Eigen::MatrixXd x;  // [the other columns, the effect's] (N × (q + k))
    try {
      const Eigen::MatrixXd xe = columns_at(c.effect);
      x.resize(n, xo.cols() + xe.cols());
      x << xo, xe;
    } catch (const std::invalid_argument&) {
      continue;
    }
    const Eigen::VectorXd residual = m.wr - x * x.colPivHouseholderQr().solve(m.wr);
    const double estimate_sse = residual.squaredNorm();
    const double variance = LongRunVariance(residual, options.significance_batches);
    const double threshold = kChiSquare95 * variance;
    // A window's edge stays on its side of the other edge. The profile's grid, 1 % of that span apart, keeps to the
    // stretch the scan searched (TimeScanRange: a change nearer the record's ends is one with a constant).
    double lo = t0, hi = t0 + duration;
    if (std::string_view(name) == "on_time" && c.effect.parameters.count("off_time")) {
      hi = c.effect.parameters.at("off_time");
    }
    if (std::string_view(name) == "off_time" && c.effect.parameters.count("on_time")) {
      lo = c.effect.parameters.at("on_time");
    }
    const double cell = (hi - lo) / kProfileGrid;
    double scan_lo = 0.0, scan_hi = 0.0;
    std::tie(scan_lo, scan_hi) = TimeScanRange(name, signals.time);
    std::vector<double> grid;
    for (int i = 0; i < kProfileGrid; ++i) {
      const double t = lo + (i + 0.5) * (hi - lo) / kProfileGrid;
      if (t >= scan_lo && t <= scan_hi) grid.push_back(t);
    }
    if (grid.empty()) continue;
    lo = std::max(lo, scan_lo);
    hi = std::min(hi, scan_hi);
    std::vector<double> sse(grid.size(), std::numeric_limits<double>::infinity());
    const auto sse_at = [&](double t) {
      EffectInstance trial = c.effect;
      trial.parameters[name] = t;
      try {
        return profile(columns_at(trial));
      } catch (const std::invalid_argument&) {
        return std::numeric_limits<double>::infinity();
      }
    };
    tbb::parallel_for(std::size_t{0}, grid.size(), [&](std::size_t i) { sse[i] = sse_at(grid[i]); });
    const double lowest = std::min(estimate_sse, *std::min_element(sse.begin(), sse.end()));
    const double level = lowest + threshold;
    const auto inside = [&](std::size_t i) { return sse[i] <= level; };
    // Every grid point within the level, and the estimate: its hull — a profile with two minima the record cannot
    // choose between spans both — each end then bisected between its outermost point inside and the next one out
    // (kEdgeBisections halvings of a grid step); an end that reaches the scan's stays there.
    const double estimate = at->second;
    const auto edge = [&](double in, double out_of) {
      for (int b = 0; b < kEdgeBisections; ++b) {
        const double mid = 0.5 * (in + out_of);
        (sse_at(mid) <= level ? in : out_of) = mid;
      }
      return in;
    };
    double up_in = estimate, down_in = estimate;
    std::optional<double> up_out, down_out;
    for (std::size_t i = 0; i < grid.size(); ++i) {
      if (!inside(i)) continue;
      up_in = std::max(up_in, grid[i]);
      down_in = std::min(down_in, grid[i]);
    }
    for (std::size_t i = 0; i < grid.size(); ++i) {
      if (grid[i] > up_in && !up_out) up_out = grid[i];
      if (grid[i] < down_in) down_out = grid[i];
    }
    TimeInterval interval{name, down_out ? edge(down_in, *down_out) : lo, up_out ? edge(up_in, *up_out) : hi,
                          estimate, estimate};
    // A nearly flat stretch: its posterior median, where it fits within the level.
    if (interval.high - interval.low >= kResolvedCells * cell) {
      const double median =
          std::clamp(PosteriorMedian(grid, sse, lowest, variance, cell), interval.low, interval.high);
      if (sse_at(median) <= level) {
        interval.estimate = median;
        c.effect.parameters[name] = median;
      }
    }
    // The columns change only where the time crosses a sample (1(t ≥ t_c), 1(t < t_off)): every time between the two
    // samples around an end fits alike, so the ends are the samples on either side.
    const double* first = signals.time.data();
    const double* last = first + n;
    const double* above = std::lower_bound(first, last, interval.high);
    if (above != last) interval.high = *above;
    const double* below = std::lower_bound(first, last, interval.low);
    if (below != first) interval.low = *(below - 1);
    out.push_back(interval);
  }
  // The candidate's columns and their scale at the times it now holds.
  if (std::any_of(out.begin(), out.end(), [](const TimeInterval& t) { return t.estimate != t.best_fit; })) {
    c.reg.columns = unweighted_columns_at(c.effect);
    for (Eigen::Index j = 0; j < c.reg.columns.cols(); ++j) {
      const double rms = c.reg.columns.col(j).norm() / std::sqrt(static_cast<double>(n));
      m.scale(c.idx[static_cast<std::size_t>(j)]) = rms > 0.0 ? rms : 1.0;
    }
  }
  return out;
}

}  // namespace mb::diagnosis_detail

// IntakeMeasurementLog and ColumnUnit (declared in measurement_log.h): users' logs as their loggers write them.
#include <algorithm>
#include <array>
#include <cmath>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>

#include "models/diagnosis/measurement_log.h"

namespace mb {
namespace {

using Columns = std::vector<Eigen::VectorXd>;

Columns ColumnsOf(const MeasurementLog& log) {
  Columns out;
  for (const auto& name : log.names()) out.push_back(log.column(name));
  return out;
}

// 1. Runs of rows with one time stamp become one row holding each column's mean. Returns the runs merged.
Eigen::Index MergeRepeatedTimes(Columns* columns, double* first_repeat) {
  const Eigen::VectorXd& t = columns->front();
  const Eigen::Index n = t.size();
  std::vector<std::pair<Eigen::Index, Eigen::Index>> runs;  // [begin, end) per distinct time
  Eigen::Index merged = 0;
  for (Eigen::Index i = 0; i < n;) {
    Eigen::Index j = i + 1;
    while (j < n && t(j) == t(i)) ++j;
    if (j - i > 1 && merged++ == 0) *first_repeat = t(i);
    runs.emplace_back(i, j);
    i = j;
  }
  if (merged == 0) return 0;
  for (auto& c : *columns) {
    Eigen::VectorXd out(static_cast<Eigen::Index>(runs.size()));
    for (std::size_t k = 0; k < runs.size(); ++k) {
      const auto [b, e] = runs[k];
      out(static_cast<Eigen::Index>(k)) = c.segment(b, e - b).mean();
    }
    c = std::move(out);
  }
  return merged;
}

double MedianPositiveStep(const Eigen::VectorXd& t) {
  std::vector<double> steps;
  for (Eigen::Index i = 1; i < t.size(); ++i) steps.push_back(t(i) - t(i - 1));
  const auto mid = steps.begin() + static_cast<std::ptrdiff_t>(steps.size() / 2);
  std::nth_element(steps.begin(), mid, steps.end());
  return *mid;
}

// 2. Segments between gaps, as [begin, end) row ranges, and the note on the gaps (empty when there is none).
std::vector<std::pair<Eigen::Index, Eigen::Index>> SplitAtGaps(const Eigen::VectorXd& t, double median,
                                                               const MeasurementIntakeOptions& options,
                                                               std::string* note) {
  std::vector<std::pair<Eigen::Index, Eigen::Index>> segments;
  Eigen::Index begin = 0, gaps = 0;
  std::string where;
  for (Eigen::Index i = 1; i <= t.size(); ++i) {
    if (i < t.size() && !(t(i) - t(i - 1) > options.gap_ratio * median)) continue;
    segments.emplace_back(begin, i);
    if (i < t.size()) {
      if (gaps < 3) where += fmt::format("{}{:.6g} s → {:.6g} s", gaps ? "; " : "", t(i - 1), t(i));
      ++gaps;
    }
    begin = i;
  }
  if (gaps > 0) {
    *note = fmt::format(
        "{} gap(s) in time longer than {} × the median step {:.4g} s ({}{}): the log is split into {} segments; "
        "filters and derivatives run on each separately and nothing is interpolated across a gap (a simulation "
        "runs through it with its inputs interpolated)",
        gaps, options.gap_ratio, median, where, gaps > 3 ? "; …" : "", segments.size());
  }
  return segments;
}

// Linear interpolation of every column of rows [b, e) onto the clock origin + k·step, k = 0 … rows − 1. An instant
// outside the stamps takes the nearest sample's value; a single row is held.
Columns Interpolated(const Columns& in, Eigen::Index b, Eigen::Index e, double origin, double step, Eigen::Index rows) {
  const Eigen::VectorXd& t = in.front();
  Columns out(in.size(), Eigen::VectorXd(rows));
  Eigen::Index j = b;
  for (Eigen::Index k = 0; k < rows; ++k) {
    const double tk = origin + static_cast<double>(k) * step;
    while (j + 2 < e && t(j + 1) <= tk) ++j;
    const double w = e - b < 2 ? 0.0 : std::clamp((tk - t(j)) / (t(j + 1) - t(j)), 0.0, 1.0);
    out[0](k) = tk;
    for (std::size_t c = 1; c < in.size(); ++c) {
      out[c](k) = e - b < 2 ? in[c](j) : in[c](j) + w * (in[c](j + 1) - in[c](j));
    }
  }
  return out;
}

// 3. Every column of rows [b, e) onto t(b) + k·step (irregular sampling).
Columns ResampleSegment(const Columns& in, Eigen::Index b, Eigen::Index e, double step) {
  const Eigen::VectorXd& t = in.front();
  const auto m = static_cast<Eigen::Index>(std::floor((t(e - 1) - t(b)) / step * (1.0 + 1e-12))) + 1;
  return Interpolated(in, b, e, t(b), step, m);
}

bool Jittered(const Eigen::VectorXd& t, Eigen::Index b, Eigen::Index e, double median, double tolerance) {
  for (Eigen::Index i = b + 1; i < e; ++i) {
    if (std::abs(t(i) - t(i - 1) - median) > tolerance * median) return true;
  }
  return false;
}

// The straight line t0 + k·step fitted to the stamps of rows [b, e) against the sample index k (least squares), and
// what the stamps leave around it: bounded white noise on a regular clock (a logger stamping on arrival), or a drift
// (irregular sampling: each step's error stays in the stamps that follow).
struct ClockFit {
  double t0 = 0.0, step = 0.0;
  double max_residual = 0.0, rms_residual = 0.0;  // of stamp − (t0 + k·step) [s]
  // Von Neumann's ratio Σ(r_k − r_{k−1})² / Σ r_k² of the residual: about 2 for independent stamp noise, near 0 when
  // the residual wanders (a random walk's is of order 1/N).
  double von_neumann = 2.0;
};

ClockFit FitClock(const Eigen::VectorXd& t, Eigen::Index b, Eigen::Index e) {
  const Eigen::Index n = e - b;
  const double k_mean = 0.5 * static_cast<double>(n - 1);
  const double t_mean = t.segment(b, n).mean();
  double skk = 0.0, skt = 0.0;
  for (Eigen::Index k = 0; k < n; ++k) {
    skk += (static_cast<double>(k) - k_mean) * (static_cast<double>(k) - k_mean);
    skt += (static_cast<double>(k) - k_mean) * (t(b + k) - t_mean);
  }
  ClockFit fit;
  fit.step = skt / skk;
  fit.t0 = t_mean - fit.step * k_mean;
  double sum_sq = 0.0, diff_sq = 0.0, previous = 0.0;
  for (Eigen::Index k = 0; k < n; ++k) {
    const double r = t(b + k) - (fit.t0 + static_cast<double>(k) * fit.step);
    fit.max_residual = std::max(fit.max_residual, std::abs(r));
    sum_sq += r * r;
    if (k > 0) diff_sq += (r - previous) * (r - previous);
    previous = r;
  }
  fit.rms_residual = std::sqrt(sum_sq / static_cast<double>(n));
  if (sum_sq > 0.0) fit.von_neumann = diff_sq / sum_sq;
  return fit;
}

// Noisy stamps on a regular clock: the residual stays within ±stamp_noise_bound steps and does not drift (von
// Neumann's ratio at least 1, half the white-noise value).
bool NoisyStampsOnARegularClock(const ClockFit& fit, const MeasurementIntakeOptions& options) {
  return fit.step > 0.0 && fit.max_residual <= options.stamp_noise_bound * fit.step && fit.von_neumann >= 1.0;
}

// Σ of the squared second divided differences of `y` on the times `t` (both of one segment): a signal's roughness on
// a time base. A smooth signal sampled at times other than `t` has its slope times each time error in it, divided by
// the step squared.
double Roughness(const Eigen::VectorXd& t, const Eigen::VectorXd& y) {
  double sum = 0.0;
  for (Eigen::Index k = 1; k + 1 < t.size(); ++k) {
    const double d2 = 2.0 * ((y(k + 1) - y(k)) / (t(k + 1) - t(k)) - (y(k) - y(k - 1)) / (t(k) - t(k - 1))) /
                      (t(k + 1) - t(k - 1));
    sum += d2 * d2;
  }
  return sum;
}

// Which time base the samples of rows [b, e) were taken on, when their stamps scatter boundedly about the fitted clock:
// the stamps themselves (a sampling loop with scheduling jitter that stamps each sample when it takes it) or the
// fitted clock (a logger stamping on arrival). Each column's roughness on the stamps over its roughness on the
// fitted clock: about 1 for a column of noise, below 1 for a smooth column sampled when stamped, above 1 for one
// sampled on the clock. The column farthest from 1 decides; the stamps are taken as accurate when it is smoother on
// them by more than `factor`. Returns that column's index (0 when the fitted clock is kept) and its ratio.
std::pair<std::size_t, double> StampsMakeTheColumnsSmoother(const Columns& in, Eigen::Index b, Eigen::Index e,
                                                            const ClockFit& fit, double factor) {
  const Eigen::Index n = e - b;
  const Eigen::VectorXd stamps = in[0].segment(b, n);
  const Eigen::VectorXd clock =
      Eigen::VectorXd::LinSpaced(n, fit.t0, fit.t0 + static_cast<double>(n - 1) * fit.step);
  std::size_t decisive = 0;
  double ratio = 1.0;
  for (std::size_t c = 1; c < in.size(); ++c) {
    const Eigen::VectorXd y = in[c].segment(b, n);
    const double on_stamps = Roughness(stamps, y), on_clock = Roughness(clock, y);
    if (!(on_stamps > 0.0) || !(on_clock > 0.0) || !std::isfinite(on_stamps) || !std::isfinite(on_clock)) continue;
    const double r = on_stamps / on_clock;
    if (std::abs(std::log(r)) > std::abs(std::log(ratio))) {
      decisive = c;
      ratio = r;
    }
  }
  return ratio < 1.0 / factor ? std::pair{decisive, ratio} : std::pair{std::size_t{0}, ratio};
}

// Every column of rows [b, e), sampled at its (accurate) stamps, onto the fitted clock t0 + k·step,
// k = 0 … e − b − 1: each instant lies within the jitter of its own sample.
Columns InterpolatedOntoFittedClock(const Columns& in, Eigen::Index b, Eigen::Index e, const ClockFit& fit) {
  return Interpolated(in, b, e, fit.t0, fit.step, e - b);
}

// Every column of rows [b, e) as logged, the time replaced by the fitted clock t0 + k·step.
Columns OnFittedClock(const Columns& in, Eigen::Index b, Eigen::Index e, const ClockFit& fit) {
  Columns out(in.size());
  for (std::size_t c = 1; c < in.size(); ++c) out[c] = in[c].segment(b, e - b);
  out[0].resize(e - b);
  for (Eigen::Index k = 0; k < e - b; ++k) out[0](k) = fit.t0 + static_cast<double>(k) * fit.step;
  return out;
}

std::string NoisyStampsNote(const std::vector<ClockFit>& fits) {
  double step_lo = INFINITY, step_hi = 0.0, worst = 0.0, worst_share = 0.0, rms = 0.0;
  for (const auto& f : fits) {
    step_lo = std::min(step_lo, f.step);
    step_hi = std::max(step_hi, f.step);
    rms = std::max(rms, f.rms_residual);
    if (f.max_residual / f.step > worst_share) {
      worst = f.max_residual;
      worst_share = f.max_residual / f.step;
    }
  }
  const std::string step = step_lo == step_hi ? fmt::format("T = {:.6g} s", step_lo)
                                              : fmt::format("T from {:.6g} to {:.6g} s", step_lo, step_hi);
  return fmt::format(
      "the time stamps are noisy on a regular clock (a logger stamping on arrival){}: stamp − fitted line t0 + k·T "
      "against the sample index stays within ±{:.3g} s ({:.0f} % of the step; RMS {:.3g} s) and does not drift; the "
      "fitted clock t_k = t0 + k·T ({}) was kept, as Lab Streaming Layer's dejitter does, and the samples as logged "
      "(interpolating them at the noisy stamps would add noise in proportion to each signal's slope)",
      fits.size() > 1 ? fmt::format(" in {} segments, each fitted on its own", fits.size()) : "", worst,
      100.0 * worst_share, rms, step);
}

// A segment sampled at its stamps, which scatter about a regular clock; the column that showed it and its roughness
// on the stamps over that on the fitted clock.
struct JitteredClock {
  ClockFit fit;
  std::string column;
  double ratio = 1.0;
};

std::string JitteredClockNote(const std::vector<JitteredClock>& clocks) {
  const JitteredClock* worst = &clocks.front();
  for (const auto& c : clocks) {
    if (c.fit.max_residual / c.fit.step > worst->fit.max_residual / worst->fit.step) worst = &c;
  }
  return fmt::format(
      "the samples were taken at their time stamps, which jitter about a regular clock{} (a sampling loop with "
      "scheduling jitter that stamps each sample when it takes it): stamp − fitted line t0 + k·T stays within ±{:.3g} "
      "s ({:.0f} % of the step T = {:.6g} s), and '{}' is {:.3g} × smoother against the stamps than against the "
      "fitted clock (its squared second differences), where a logger stamping on arrival would make it rougher; every "
      "column was interpolated (linearly) onto the fitted clock t_k = t0 + k·T, each instant within the jitter of its "
      "own sample",
      clocks.size() > 1 ? fmt::format(" in {} segments, each fitted on its own", clocks.size()) : "",
      worst->fit.max_residual, 100.0 * worst->fit.max_residual / worst->fit.step, worst->fit.step, worst->column,
      1.0 / worst->ratio);
}

std::string JitterNote(const Eigen::VectorXd& t, double median, Eigen::Index rows_before, Eigen::Index rows_after,
                       double drift_steps, const MeasurementIntakeOptions& options) {
  double lo = INFINITY, hi = 0.0;
  Eigen::Index outside = 0;
  for (Eigen::Index i = 1; i < t.size(); ++i) {
    const double h = t(i) - t(i - 1);
    if (h > options.gap_ratio * median) continue;
    lo = std::min(lo, h);
    hi = std::max(hi, h);
    outside += std::abs(h - median) > options.jitter_tolerance * median ? 1 : 0;
  }
  return fmt::format(
      "the time steps are not uniform (jitter: steps from {:.4g} to {:.4g} s, median {:.4g} s; {:.1f} % of them "
      "outside ±{:g} %) and the stamps are taken as accurate (irregular sampling: stamp − a line fitted against the "
      "sample index reaches {:.3g} steps, or drifts): every column was resampled onto a uniform grid of step {:.4g} s "
      "by linear interpolation, {} rows → {}",
      lo, hi, median, 100.0 * static_cast<double>(outside) / static_cast<double>(t.size() - 1),
      100.0 * options.jitter_tolerance, drift_steps, median, rows_before, rows_after);
}

}  // namespace

MeasurementLog IntakeMeasurementLog(const MeasurementLog& given, const MeasurementIntakeOptions& options) {
  const MeasurementLog raw = WithTimeInSeconds(given);
  Columns columns = ColumnsOf(raw);
  std::vector<std::string> notes;
  double first_repeat = 0.0;
  const Eigen::Index rows_read = raw.rows();
  if (const Eigen::Index merged = MergeRepeatedTimes(&columns, &first_repeat); merged > 0) {
    notes.push_back(fmt::format(
        "{} time stamp(s) appear on more than one row (first at t = {} s): each was merged into one row holding the "
        "mean of its rows, {} rows → {}",
        merged, first_repeat, rows_read, columns.front().size()));
  }
  if (columns.front().size() < std::max<Eigen::Index>(options.min_rows, 3)) {
    throw std::invalid_argument(fmt::format("{}: only {} distinct time stamp(s), at least {} are needed; record a "
                                            "longer log", raw.source(), columns.front().size(), options.min_rows));
  }
  const Eigen::VectorXd t = columns.front();
  const double median = MedianPositiveStep(t);
  std::string gap_note;
  const auto segments = SplitAtGaps(t, median, options, &gap_note);
  if (!gap_note.empty()) notes.push_back(gap_note);
  // 3. Each segment on its own: uniform steps as logged; noisy stamps on a regular clock on their fitted clock;
  // irregular sampling resampled.
  Columns out(columns.size());
  std::vector<Eigen::Index> starts;
  std::vector<ClockFit> fitted_clocks;
  std::vector<JitteredClock> jittered_clocks;
  Eigen::Index dropped = 0, rows = 0, resampled = 0;
  double drift_steps = 0.0;
  for (const auto& [b, e] : segments) {
    if (e - b < options.min_segment_rows) {
      ++dropped;
      continue;
    }
    Columns part(columns.size());
    if (!Jittered(t, b, e, median, options.jitter_tolerance)) {
      for (std::size_t c = 0; c < columns.size(); ++c) part[c] = columns[c].segment(b, e - b);
    } else if (const ClockFit fit = FitClock(t, b, e); NoisyStampsOnARegularClock(fit, options)) {
      const auto [column, ratio] = StampsMakeTheColumnsSmoother(columns, b, e, fit, options.smoother_on_stamps);
      if (column > 0) {
        part = InterpolatedOntoFittedClock(columns, b, e, fit);
        jittered_clocks.push_back({fit, raw.names()[column], ratio});
      } else {
        part = OnFittedClock(columns, b, e, fit);
        fitted_clocks.push_back(fit);
      }
    } else {
      part = ResampleSegment(columns, b, e, median);
      ++resampled;
      drift_steps = std::max(drift_steps, fit.max_residual / median);
    }
    starts.push_back(rows);
    rows += part.front().size();
    for (std::size_t c = 0; c < columns.size(); ++c) {
      Eigen::VectorXd joined(rows);
      joined << out[c], part[c];
      out[c] = std::move(joined);
    }
  }
  if (starts.empty()) {
    throw std::invalid_argument(fmt::format(
        "{}: no stretch of the log between its gaps has {} rows; record a longer log or lower the gap threshold",
        raw.source(), options.min_segment_rows));
  }
  if (dropped > 0) {
    notes.push_back(fmt::format("{} segment(s) shorter than {} rows between gaps were left out", dropped,
                                options.min_segment_rows));
  }
  if (!fitted_clocks.empty()) notes.push_back(NoisyStampsNote(fitted_clocks));
  if (!jittered_clocks.empty()) notes.push_back(JitteredClockNote(jittered_clocks));
  if (resampled > 0) notes.push_back(JitterNote(t, median, t.size(), rows, drift_steps, options));
  MeasurementLog log(raw.names(), std::move(out), raw.source());
  for (const auto& n : raw.notes()) log.AddNote(n);  // as read: the time converted to seconds
  for (auto& n : notes) log.AddNote(fmt::format("{}: {}", raw.source(), n));
  log.SetSegmentStarts(std::move(starts));
  return log;
}

MeasurementLog IntakeMeasurementLog(const std::string& path, const MeasurementIntakeOptions& options) {
  MeasurementLogOptions read;
  read.required_columns = options.required_columns;
  read.min_rows = options.min_rows;
  read.max_gap_ratio = 0.0;
  read.allow_repeated_times = true;
  return IntakeMeasurementLog(ReadMeasurementLog(path, read), options);
}

std::string ColumnUnit(std::string_view name) {
  // Longest suffixes first: "_m_s2" before "_s2", "_rad_s" before "_s".
  static constexpr std::array<std::pair<std::string_view, std::string_view>, 28> kSuffixes{{
      {"_m_s2", "m/s^2"}, {"_rad_s2", "rad/s^2"}, {"_rev_s2", "rev/s^2"}, {"_deg_s2", "deg/s^2"},
      {"_m_s", "m/s"},    {"_rad_s", "rad/s"},    {"_rev_s", "rev/s"},    {"_deg_s", "deg/s"},
      {"_Nm", "N·m"},     {"_N_m", "N·m"},        {"_mm", "mm"},          {"_rad", "rad"},
      {"_rev", "rev"},    {"_deg", "deg"},        {"_m", "m"},            {"_N", "N"},
      {"_A", "A"},        {"_V", "V"},            {"_s", "s"},            {"_Hz", "Hz"},
      {"_kg", "kg"},      {"_W", "W"},            {"_counts", ""},        {"_mA", "mA"},
      {"_um", "um"},      {"_cm", "cm"},          {"_ms", "ms"},          {"_us", "us"},
  }};
  for (const auto& [suffix, unit] : kSuffixes) {
    if (name.size() > suffix.size() && name.substr(name.size() - suffix.size()) == suffix) return std::string(unit);
  }
  return "";
}

}  // namespace mb

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

// 3. Linear interpolation of every column of rows [b, e) onto t(b) + k·step.
Columns ResampleSegment(const Columns& in, Eigen::Index b, Eigen::Index e, double step) {
  const Eigen::VectorXd& t = in.front();
  const auto m = static_cast<Eigen::Index>(std::floor((t(e - 1) - t(b)) / step * (1.0 + 1e-12))) + 1;
  Columns out(in.size(), Eigen::VectorXd(m));
  Eigen::Index j = b;
  for (Eigen::Index k = 0; k < m; ++k) {
    const double tk = t(b) + static_cast<double>(k) * step;
    while (j + 2 < e && t(j + 1) <= tk) ++j;
    const double w = e - b < 2 ? 0.0 : std::clamp((tk - t(j)) / (t(j + 1) - t(j)), 0.0, 1.0);
    out[0](k) = tk;
    for (std::size_t c = 1; c < in.size(); ++c) {
      out[c](k) = e - b < 2 ? in[c](j) : in[c](j) + w * (in[c](j + 1) - in[c](j));
    }
  }
  return out;
}

bool Jittered(const Eigen::VectorXd& t, Eigen::Index b, Eigen::Index e, double median, double tolerance) {
  for (Eigen::Index i = b + 1; i < e; ++i) {
    if (std::abs(t(i) - t(i - 1) - median) > tolerance * median) return true;
  }
  return false;
}

std::string JitterNote(const Eigen::VectorXd& t, double median, Eigen::Index rows_before, Eigen::Index rows_after,
                       const MeasurementIntakeOptions& options) {
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
      "outside ±{:g} %): every column was resampled onto a uniform grid of step {:.4g} s by linear interpolation, "
      "{} rows → {}",
      lo, hi, median, 100.0 * static_cast<double>(outside) / static_cast<double>(t.size() - 1),
      100.0 * options.jitter_tolerance, median, rows_before, rows_after);
}

}  // namespace

MeasurementLog IntakeMeasurementLog(const MeasurementLog& raw, const MeasurementIntakeOptions& options) {
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
  bool jitter = false;
  for (const auto& [b, e] : segments) jitter = jitter || Jittered(t, b, e, median, options.jitter_tolerance);

  Columns out(columns.size());
  std::vector<Eigen::Index> starts;
  Eigen::Index dropped = 0, rows = 0;
  for (const auto& [b, e] : segments) {
    if (e - b < options.min_segment_rows) {
      ++dropped;
      continue;
    }
    Columns part(columns.size());
    if (jitter) {
      part = ResampleSegment(columns, b, e, median);
    } else {
      for (std::size_t c = 0; c < columns.size(); ++c) part[c] = columns[c].segment(b, e - b);
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
  if (jitter) notes.push_back(JitterNote(t, median, t.size(), rows, options));
  MeasurementLog log(raw.names(), std::move(out), raw.source());
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
  static constexpr std::array<std::pair<std::string_view, std::string_view>, 24> kSuffixes{{
      {"_m_s2", "m/s^2"}, {"_rad_s2", "rad/s^2"}, {"_rev_s2", "rev/s^2"}, {"_deg_s2", "deg/s^2"},
      {"_m_s", "m/s"},    {"_rad_s", "rad/s"},    {"_rev_s", "rev/s"},    {"_deg_s", "deg/s"},
      {"_Nm", "N·m"},     {"_N_m", "N·m"},        {"_mm", "mm"},          {"_rad", "rad"},
      {"_rev", "rev"},    {"_deg", "deg"},        {"_m", "m"},            {"_N", "N"},
      {"_A", "A"},        {"_V", "V"},            {"_s", "s"},            {"_Hz", "Hz"},
      {"_kg", "kg"},      {"_W", "W"},            {"_counts", ""},        {"_mA", "mA"},
  }};
  for (const auto& [suffix, unit] : kSuffixes) {
    if (name.size() > suffix.size() && name.substr(name.size() - suffix.size()) == suffix) return std::string(unit);
  }
  return "";
}

}  // namespace mb

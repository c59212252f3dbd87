#include "models/diagnosis/measurement_log.h"

#include <algorithm>
#include <optional>
#include <stdexcept>

#include <fmt/format.h>

#include "engine/text_excerpt.h"
#include "engine/units.h"

namespace mb {
namespace {

// Time (the first column) strictly increasing, without gaps above max_gap_ratio × the median step.
void CheckTimeColumn(const std::vector<double>& t, const std::vector<std::size_t>& line_of_row, const std::string& path,
                     const std::string& time_name, const MeasurementLogOptions& options) {
  const std::size_t nrows = t.size();
  for (std::size_t i = 1; i < nrows; ++i) {
    if (!(t[i] > t[i - 1]) && !(options.allow_repeated_times && t[i] == t[i - 1])) {
      throw std::invalid_argument(fmt::format(
          "{}: line {}, column '{}': time {} does not increase (previous row, line {}, has {}); sort the "
          "rows by time and remove repeated samples",
          path, line_of_row[i], time_name, t[i], line_of_row[i - 1], t[i - 1]));
    }
  }
  if (options.max_gap_ratio > 0.0 && nrows >= 3) {
    std::vector<double> steps(nrows - 1);
    for (std::size_t i = 1; i < nrows; ++i) steps[i - 1] = t[i] - t[i - 1];
    std::vector<double> sorted = steps;
    std::nth_element(sorted.begin(), sorted.begin() + static_cast<std::ptrdiff_t>(sorted.size() / 2),
                     sorted.end());
    const double median = sorted[sorted.size() / 2];
    std::string where;
    std::size_t count = 0;
    for (std::size_t i = 0; i < steps.size(); ++i) {
      if (steps[i] > options.max_gap_ratio * median) {
        if (count < 5) {
          where += fmt::format("{}after t = {} s (line {}, step {} s)", count ? "; " : "", t[i],
                               line_of_row[i], steps[i]);
        }
        ++count;
      }
    }
    if (count > 0) {
      throw std::invalid_argument(fmt::format(
          "{}: column '{}': {} gap(s) in time larger than {} × the median step {} s: {}{}. Split the log "
          "at the gaps or resample it to a uniform step",
          path, time_name, count, options.max_gap_ratio, median, where, count > 5 ? "; ..." : ""));
    }
  }
}

}  // namespace

MeasurementLog WithTimeInSeconds(MeasurementLog log) {
  const std::string name = log.names().front();
  const std::string unit = ColumnUnit(name);
  const std::optional<double> factor = unit.empty() ? std::nullopt : UnitFactor(unit, "s");
  // "time_<unit>" declares a unit: one this reader does not know (time_fortnight, time_min) is refused, not read as
  // seconds; a name without that form (t, time, encoder_count) is read as seconds as before.
  const bool declares_unit = name.rfind("time_", 0) == 0 && name.size() > 5;
  if (declares_unit && !factor) {
    throw std::invalid_argument(fmt::format(
        "{}: the time column '{}' declares the unit '{}', which is no time unit known here: write the time in "
        "seconds, milliseconds or microseconds and name the column time_s, time_ms or time_us",
        log.source(), Excerpt(name), Excerpt(name.substr(5))));
  }
  if (!factor || *factor == 1.0) return log;
  if (log.has_column("time_s")) {
    throw std::invalid_argument(fmt::format(
        "{}: the time column '{}' is in {} (its name's suffix) and another column is named time_s; rename one of "
        "them (the time column, column 1, is converted to seconds and named time_s)",
        log.source(), name, unit));
  }
  std::vector<std::string> names = log.names();
  std::vector<Eigen::VectorXd> columns;
  for (const auto& n : names) columns.push_back(log.column(n));
  columns.front() *= *factor;
  names.front() = "time_s";
  MeasurementLog out(std::move(names), std::move(columns), log.source());
  out.SetRowLines(log.row_lines());
  out.SetSegmentStarts(log.segment_starts());
  for (const auto& note : log.notes()) out.AddNote(note);
  out.AddNote(fmt::format("{}: the time column '{}' is in {} (its name's suffix): converted to seconds (× {:g}) "
                          "and named time_s",
                          log.source(), name, unit, *factor));
  return out;
}

MeasurementLog ReadMeasurementLog(const std::string& path, const MeasurementLogOptions& options) {
  MeasurementLog log =
      WithTimeInSeconds(ReadTable(path, TableReadOptions{options.required_columns, "measurement log"}));
  if (log.rows() < options.min_rows) {
    throw std::invalid_argument(fmt::format(
        "{}: only {} data row(s), at least {} are needed; record a longer log", path, log.rows(),
        options.min_rows));
  }
  const Eigen::VectorXd& time = log.time();
  CheckTimeColumn(std::vector<double>(time.data(), time.data() + time.size()), log.row_lines(), path, log.names().front(), options);
  return log;
}

void WriteMeasurementLog(const MeasurementLog& log, const std::string& path) { WriteTable(log, path); }

}  // namespace mb

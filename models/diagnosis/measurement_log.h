// Measurement logs: Tables (engine/table.h, the file format) whose first column is the sample time [s], strictly
// increasing.
#pragma once

#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "engine/table.h"

namespace mb {

// A measurement log is a Table (engine/table.h) whose column 0 is the time [s]. A time column named in another
// time unit (time_ms, time_us: ColumnUnit) is converted to seconds when the log is read (WithTimeInSeconds).
using MeasurementLog = Table;

// What ReadMeasurementLog checks.
struct MeasurementLogOptions {
  // Columns that must be present (besides the time column, which is always column 0).
  std::vector<std::string> required_columns;
  // Fewer data rows than this is an error.
  Eigen::Index min_rows = 10;
  // A time step larger than max_gap_ratio × the median step is a gap (an error). <= 0 disables the check.
  double max_gap_ratio = 1.5;
  // Accept repeated time stamps (time must then only not decrease); IntakeMeasurementLog merges them.
  bool allow_repeated_times = false;
};

// The log with its time column (column 0) in seconds: a name whose suffix is another time unit (time_ms, time_us;
// ColumnUnit, UnitFactor of engine/units.h) has its values converted and is renamed time_s, with a note
// (MeasurementLog::notes); any other log is returned as it is (a name without a unit is taken as seconds). Throws
// std::invalid_argument when the time must be renamed and another column is named time_s already.
MeasurementLog WithTimeInSeconds(MeasurementLog log);

// Reads a CSV measurement log (format above) into a MeasurementLog, validating as it goes; the time in seconds
// (WithTimeInSeconds) before it is checked.
// Throws std::runtime_error when the file cannot be opened, and std::invalid_argument, with the file,
// the 1-based line number, the column name and a fix, for: an empty file or header, an empty or
// repeated column name, a missing required column (the message lists the columns present), a row
// with a different number of cells, a non-numeric cell, NaN or Inf, a time that does not increase,
// a gap (reports the time and line where each gap starts — up to five — and the median step),
// (unless options.allow_repeated_times) a repeated time,
// fewer than min_rows rows. Parsing uses std::from_chars: 24,841 rows × 6 columns read in ~30 ms
// (Release, on a loaded 2-core machine).
MeasurementLog ReadMeasurementLog(const std::string& path, const MeasurementLogOptions& options = {});

// How users' logs are taken in (compare, fit, improve): as loggers make them, jittered, with repeated rows
// and gaps. Steps are judged against the median of the positive time steps.
struct MeasurementIntakeOptions {
  std::vector<std::string> required_columns;  // besides the time column
  Eigen::Index min_rows = 10;
  // Steps within ±jitter_tolerance × the median step are uniform; a segment with a step outside is either noisy
  // stamps on a regular clock or irregular sampling (below).
  double jitter_tolerance = 0.01;
  // Noisy stamps on a regular clock: the stamps minus a straight line fitted against the sample index stay within
  // ±stamp_noise_bound × the fitted step and do not drift. 0 = never (every non-uniform segment is resampled).
  double stamp_noise_bound = 0.5;
  // Such bounded stamps are accurate (the samples taken when stamped) when some column is rougher on the fitted clock
  // than on the stamps by more than this factor (its squared second differences); else the stamps are noisy.
  double smoother_on_stamps = 2.0;
  // A step above gap_ratio × the median step is a gap: the log is split there into segments.
  double gap_ratio = 5.0;
  // Segments with fewer rows than this are dropped (a note says so): too short to filter or differentiate.
  Eigen::Index min_segment_rows = 16;
};

// Takes a log in as users' loggers write it, each step with a note (MeasurementLog::notes):
//  1. rows with the same time stamp are merged into one (the mean of each column);
//  2. a step above gap_ratio × the median step is a gap: the log is split into segments there
//     (MeasurementLog::segment_starts) — a warning, not an error; nothing is interpolated across a gap; segments
//     shorter than min_segment_rows are dropped;
//  3. a segment whose steps are not uniform (jitter beyond ±jitter_tolerance) is one of two cases, told apart by the
//     line t0 + k·T fitted to its stamps against the sample index k (least squares):
//     - noisy stamps on a regular clock (a logger stamping on arrival, USB or Ethernet): the residual stays within
//       ±stamp_noise_bound × T and does not drift (von Neumann's ratio Σ(Δr)²/Σr² at least 1; about 2 for
//       independent stamp noise). The fitted clock t_k = t0 + k·T replaces the stamps and the samples are kept as
//       logged (Lab Streaming Layer's dejitter): interpolating at noisy stamps adds noise in proportion to the
//       signal's slope. Unless the samples were taken at their stamps (a sampling loop with scheduling jitter
//       that stamps each sample when it takes it): bounded stamps fit both stories, the signals tell them apart —
//       a smooth column sampled at its stamps is smoother against them than against the fitted clock, where its
//       slope times each time error enters its second differences. When some column is smoother on the stamps by
//       more than smoother_on_stamps (the column farthest from 1 decides), every column is interpolated
//       (linearly) onto the fitted clock, each instant within the jitter of its own sample;
//     - irregular sampling with accurate stamps (a polled sensor: the residual wanders, each step's error stays in
//       the stamps that follow): every column is resampled onto the uniform grid t_0 + k·Δt, Δt = the median step,
//       by linear interpolation.
//     Each segment is fitted and judged on its own; the note says which case was found, with the step and the
//     residual stamp jitter.
// The time is first converted to seconds (WithTimeInSeconds); the log's own notes are kept, before the intake's.
// A log already uniform, without repeats or gaps, passes unchanged. Throws as ReadMeasurementLog (bad cells, a
// time that decreases, too few rows), and std::invalid_argument when no segment has min_segment_rows rows.
MeasurementLog IntakeMeasurementLog(const std::string& path, const MeasurementIntakeOptions& options = {});
// The same on a log in memory whose time does not decrease.
MeasurementLog IntakeMeasurementLog(const MeasurementLog& raw, const MeasurementIntakeOptions& options = {});

// The unit written as the suffix of a column name (the text after the last '_' of names such as position_m,
// angle_rev, iq_A, torque_Nm, velocity_rad_s → "rad/s", acceleration_m_s2 → "m/s^2"), normalised to the
// diagram connectors' spelling: "m", "mm", "um", "cm", "rad", "rev", "deg", "N", "N·m", "A", "mA", "V", "s", "ms",
// "us", "m/s", "rev/s", …; "" when the name carries none of these.
std::string ColumnUnit(std::string_view column_name);

// Writes a MeasurementLog as CSV (header row, then rows; each number in the shortest form that reads
// back exactly, std::to_chars). Throws std::runtime_error when the file cannot be written.
void WriteMeasurementLog(const MeasurementLog& log, const std::string& path);

}  // namespace mb

#pragma once
// Measurement: a log read for a diagram (read, map connectors, derive motion). What compare, fit and improve share:
// the log with velocity and acceleration derived from the position (zero-phase low-pass + central differences, the
// EMPS benchmark's IDIM-LS), the measured columns a diagram's connectors are read from (their "measurement" names
// or --map), and the experiment mode that decides which columns are filtered.

#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/diagram.h"
#include "engine/simulator.h"
#include "models/diagnosis/measurement_log.h"

namespace mb {

/// Columns compare derives when the log lacks them: velocity and acceleration from the position column,
/// zero-phase low-pass + central differences (the EMPS benchmark's IDIM-LS).
inline constexpr const char* kDerivedVelocityColumn = "velocity_m_s";
inline constexpr const char* kDerivedAccelerationColumn = "acceleration_m_s2";

/// The same for any position column: velocity_<u>_s and acceleration_<u>_s2, <u> the position's unit from its name
/// (ColumnUnit: m, rad, rev or deg; m when the name carries none), e.g. velocity_rev_s for angle_rev.
std::string DerivedVelocityColumn(const std::string& position_column);
std::string DerivedAccelerationColumn(const std::string& position_column);
/// The unit token of a position column's name ("m", "rad", "rev", "deg"; "m" when it carries none).
std::string PositionUnitToken(const std::string& position_column);

/// Takes a measurement log in (IntakeMeasurementLog: repeated time stamps merged, jitter resampled, gaps split into
/// segments, each with a note on the log) and adds the derived velocity/acceleration columns (if absent and the
/// position column exists). Columns named in `filter_columns` (those present) are passed through the same zero-phase
/// low-pass as the position — IDIM-LS's parallel filtering, so that an equation-error residual compares force
/// and motion in the same band. Filters and derivatives run per segment. @throws as IntakeMeasurementLog.
/// Columns named in `held_columns` are zero-order-held commands: each sample is first replaced by the held signal's
/// mean over the sample period centred on its instant (HeldSignalAtSampleInstants), with a note.
MeasurementLog ReadMeasurementWithDerivatives(const std::string& path, const std::string& position_column,
                                              double derivative_cutoff_hz,
                                              const std::vector<std::string>& filter_columns = {},
                                              const std::vector<std::string>& held_columns = {});

/// The measured columns a diagram's output connectors are compared with (their "measurement" names, or the
/// --map override).
std::vector<std::string> OutputColumns(const nlohmann::json& diagram,
                                       const std::map<std::string, std::string>& column_map);

/// A measured column as a simulator input (time_s and the column). @throws as MeasurementLog::column.
InputSeries SeriesOf(const MeasurementLog& log, const std::string& column);

/// Feeds `run --input connector=FILE[:COLUMN]` specs. @throws std::invalid_argument on a malformed spec.
void FeedInputsFromFiles(const Diagram& diagram, const std::vector<std::string>& specs, Simulator* sim);

/// How the measured outputs behave between their samples (MATLAB iddata's InterSample property).
enum class Intersample {
  kFirstOrderHold,  ///< "foh": a sample is the signal's value at its instant (a sensor: load cell, measured current)
  kZeroOrderHold,   ///< "zoh": a sample is held until the next (a logged command: a force or current reference)
};

/// "foh" or "zoh". @throws std::invalid_argument naming both for anything else.
Intersample ParseIntersample(const std::string& text);
/// "foh" or "zoh".
const char* IntersampleName(Intersample intersample);

/// How a diagram is read against a measurement log: what compare, fit and improve share.
struct MeasurementSettings {
  std::map<std::string, std::string> column_map;  ///< connector → column overrides (--map)
  std::string position_column = "position_m";      ///< measured position [m], source of velocity/acceleration
  double derivative_cutoff_hz = 100.0;             ///< zero-phase low-pass before differentiating [Hz]
  /// The measured outputs of an equation-error diagram: "zoh" when the log holds the command the drive applied over
  /// the next sample (EMPS's force_N = gtau·vir, a controller's logged force), so that they are compared half a
  /// sample later, where the motion's central differences see them (HeldSignalAtSampleInstants). Simulation mode
  /// compares measured positions and ignores it.
  Intersample intersample = Intersample::kFirstOrderHold;
};

/// The diagram's experiment.mode: "equation_error" or "simulation" (the default).
std::string ExperimentMode(const nlohmann::json& diagram);

/// Reads `path` for `diagram`: ReadMeasurementWithDerivatives, and in equation-error mode the measured outputs
/// through the derivative low-pass too (IDIM-LS's parallel filtering), held first when `settings.intersample` is zoh. @throws as ReadMeasurementLog (naming the
/// file, line and column).
MeasurementLog ReadMeasurementFor(const nlohmann::json& diagram, const std::string& path,
                                  const MeasurementSettings& settings);

}  // namespace mb

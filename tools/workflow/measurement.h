#pragma once
// Measurement: a log read for a diagram (read, map connectors, derive motion). What compare, fit and improve share:
// the log with velocity and acceleration derived from the position (zero-phase low-pass + central differences, the
// EMPS benchmark's IDIM-LS), the measured columns a diagram's connectors are read from (their "measurement" names
// or --map), and the experiment mode that decides which columns are filtered.

#include <map>
#include <string>
#include <vector>

#include <Eigen/Core>

#include <nlohmann/json.hpp>

#include "engine/diagram.h"
#include "engine/experiment_mode.h"
#include "engine/simulator.h"
#include "models/diagnosis/measurement_log.h"

namespace mb {

/// Columns compare derives when the log lacks them: velocity and acceleration from the position column,
/// zero-phase low-pass + central differences (the EMPS benchmark's IDIM-LS).
/// The position in metres as a diagram's connector reads it by default: added as an alias when --position-column names
/// a column in another length unit (position_mm, converted to metres), unless the log has it.
inline constexpr const char* kMetresPositionColumn = "position_m";
inline constexpr const char* kDerivedVelocityColumn = "velocity_m_s";
inline constexpr const char* kDerivedAccelerationColumn = "acceleration_m_s2";

/// The same for any position column: velocity_<u>_s and acceleration_<u>_s2, <u> the position's unit from its name
/// (ColumnUnit: rad, rev or deg; m for m, mm, um, cm and when the name carries none; a unit of no motion quantity
/// as it is), e.g. velocity_rev_s for angle_rev, velocity_m_s for position_mm, velocity_V_s for x_V.
std::string DerivedVelocityColumn(const std::string& position_column);
std::string DerivedAccelerationColumn(const std::string& position_column);
/// The unit token of a position column's name ("m", "rad", "rev", "deg"; "m" for mm, um, cm and when it carries
/// none; a unit of no motion quantity, such as V for a voltage standing for the position, as it is).
std::string PositionUnitToken(const std::string& position_column);

/// Units of the position column, from its name's suffix (ColumnUnit): a linear position in mm, um or cm is converted
/// to metres when the log is read (the column keeps its name, its values are in m, a note says so), as the blocks'
/// linear ports are in m; a rotary one stays in rad, rev or deg (engine/units.h: a rotary axis uses the blocks in
/// its own unit). The factor to metres: 1e-3 for position_mm, 1 for position_m, angle_rev and a name without a unit.
double PositionToMetres(const std::string& position_column);

/// The default derivative cut-off [Hz], automatic: a log sampled at f_s is read with
/// min(kAutomaticCutoffHz, kAutomaticCutoffShare · f_s) — 100 Hz from 500 Hz up (EMPS, 1 kHz: unchanged), 20 Hz at
/// 100 Hz — with a note when that is below 100 Hz. A cut-off of exactly 100 Hz is taken as this default.
inline constexpr double kAutomaticCutoffHz = 100.0;
inline constexpr double kAutomaticCutoffShare = 0.2;

/// The cut-off a log sampled every `sample_period` [s] is filtered and differentiated with: `cutoff_hz` as chosen, or
/// for the default kAutomaticCutoffHz the automatic cut-off above. The model output's filter and the diagnosis'
/// regressor filter must use the same one (parallel filtering): DerivativeCutoffHz(settings, log). @throws
/// std::invalid_argument naming `source`, the Nyquist frequency and a cut-off to pass when a chosen cut-off is not
/// in (0, Nyquist), or when sample_period <= 0.
double DerivativeCutoffHz(double cutoff_hz, double sample_period, const std::string& source);

/// The same for a log of these time stamps [s] and this position (nullptr: none): the automatic cut-off then also comes
/// down for a coarse encoder, to where its quantization is at most a tenth of the derived acceleration
/// (QuantizationLimitedCutoff, models/diagnosis/quantization_floor.h; quantization_share, optional, receives that
/// share). A chosen cut-off is kept as chosen. @throws as above.
double DerivativeCutoffHz(double cutoff_hz, const Eigen::VectorXd& time, const Eigen::VectorXd* position,
                          const std::string& source, double* quantization_share = nullptr);

/// Takes a measurement log in (IntakeMeasurementLog: time in seconds, repeated time stamps merged, jitter resampled or
/// noisy stamps put on their fitted clock, gaps split into segments, each with a note on the log), converts the
/// position column to metres when its name says mm, um or cm (PositionToMetres), and adds the derived
/// velocity/acceleration columns (if absent and the position column exists), low-passed at
/// DerivativeCutoffHz(derivative_cutoff_hz, median step) (the default follows the sample rate, with a note).
/// Columns named in `filter_columns` (those present) are passed through the same zero-phase low-pass as the
/// position — IDIM-LS's parallel filtering, so that an equation-error residual compares force and motion in the same
/// band. Filters and derivatives run per segment. @throws as IntakeMeasurementLog and DerivativeCutoffHz.
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
  /// zero-phase low-pass before differentiating [Hz]; the default follows the sample rate (kAutomaticCutoffHz)
  double derivative_cutoff_hz = kAutomaticCutoffHz;
  /// The measured outputs of an equation-error diagram: "zoh" when the log holds the command the drive applied over
  /// the next sample (EMPS's force_N = gtau·vir, a controller's logged force), so that they are compared half a
  /// sample later, where the motion's central differences see them (HeldSignalAtSampleInstants). Simulation mode
  /// compares measured positions and ignores it.
  Intersample intersample = Intersample::kFirstOrderHold;
  /// The diagnosis proposes every pair of its grammar, not only the products the catalogue named before it
  /// (CatalogueOptions::every_pair).
  bool every_pair = false;
};

/// The cut-off a log read with `settings` (ReadMeasurementFor) was filtered and differentiated with: what compare, fit
/// and improve pass to ModelComparison::set_output_filter and DiagnosisOptions::regressor_filter_hz. @throws as
/// DerivativeCutoffHz above.
double DerivativeCutoffHz(const MeasurementSettings& settings, const MeasurementLog& log);

/// The diagram's experiment.mode (simulation when absent; DiagramDocument::Mode).
ExperimentMode ModeOf(const nlohmann::json& diagram);

/// Reads `path` for `diagram`: ReadMeasurementWithDerivatives, and in equation-error mode the measured outputs
/// through the derivative low-pass too (IDIM-LS's parallel filtering), held first when `settings.intersample` is zoh. @throws as ReadMeasurementLog (naming the
/// file, line and column).
MeasurementLog ReadMeasurementFor(const nlohmann::json& diagram, const std::string& path,
                                  const MeasurementSettings& settings);

}  // namespace mb

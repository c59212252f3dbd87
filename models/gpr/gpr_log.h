#pragma once
// TISO-GPR on measurement logs (models/diagnosis/measurement_log.h): select the training samples of
// a DOB log, fit a model to them with a provenance that names the log, and predict along a log.
// What `motionblocks fit-gpr` and `motionblocks predict-gpr` call (target mb_gpr_log).

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "models/diagnosis/measurement_log.h"
#include "models/gpr/gpr_fit.h"
#include "models/gpr/gpr_model.h"

namespace mb {

/// Reads a GP training or prediction table (engine/table.h) as people have it: no time column needed, rows in any
/// order, scans that restart at t = 0 concatenated, pandas' default to_csv (an unnamed index column first, dropped).
/// @throws as ReadTable, naming the file, line and column; a missing column lists those present.
Table ReadGprTable(const std::string& path, const std::vector<std::string>& required_columns);

/// The position and velocity columns a model reads by default: those it was trained on (its provenance), else
/// "position_m" and "velocity_m_s". An explicit non-empty `position` or `velocity` wins.
std::pair<std::string, std::string> GprInputColumns(const GprModel& model, const std::string& position = "",
                                                    const std::string& velocity = "");

/// Which samples of a log train the model.
struct GprTrainingSelection {
  std::string position_column = "position_m";      ///< x [m]
  std::string velocity_column = "velocity_m_s";    ///< ẋ [m/s]
  std::string disturbance_column;                  ///< d, e.g. the DOB estimate [N]; required
  /// Keep only samples with window->min ≤ x ≤ window->max [m] (the paper trains on a
  /// position window and checks extrapolation outside it, Fig. 6).
  std::optional<GprRange> window;
  /// Keep every downsample-th sample of those in the window (1 = all; the paper's exact GP needed
  /// N ≈ 2,000, the weight-space solver takes every sample).
  int downsample = 1;
};

/// The selected samples, in log order, and a one-line description of where they came from.
struct GprTrainingData {
  Eigen::VectorXd x;     ///< [m]
  Eigen::VectorXd xdot;  ///< [m/s]
  Eigen::VectorXd d;     ///< disturbance, the log's unit
  /// "<source> (position: <col>, velocity: <col>, disturbance: <col>[, window [a, b] m]
  /// [, downsampled by <n>]; N = <count> of <rows> rows)" — recorded as the model's provenance.
  std::string description;
};

/// Picks the columns and applies the window and the downsampling.
/// @throws std::invalid_argument naming the log's source for an empty disturbance column name, a
/// missing column (listing those present), downsample < 1, a window with min ≥ max or a non-finite
/// bound, or fewer than 2 samples left (with the window and the log's position range).
GprTrainingData SelectGprTrainingData(const MeasurementLog& log, const GprTrainingSelection& selection);

/// SelectGprTrainingData, then FitGpr (gpr_fit.h) with options.source set to the description (the
/// model's provenance then names the file, the columns, the window, the downsampling and N; FitGpr
/// records the date, N, solver and library version) and accept_one_velocity set (a table of one scan
/// velocity trains). The provenance records the position and velocity columns (predict-gpr's defaults).
/// @throws as SelectGprTrainingData and FitGpr.
GprModel FitGprToLog(const MeasurementLog& log, const GprTrainingSelection& selection,
                     GprFitOptions options);

/// A copy of `log` (every column, time first) with three columns appended: "mean", the posterior
/// mean d̂(x, ẋ) (GprModel::PredictPosteriorMean, eq. 22/24), "std", the latent posterior
/// standard deviation (√ eq. 23), at each row's position and velocity, and "extrapolated": 1 where
/// the row lies outside what the model was trained on (GprExtrapolates: x outside x_range() or ẋ
/// outside xdot_range(), or either not finite), else 0. Such rows are handled as GprModel documents
/// (ẋ clamped, x not): their mean and std are the model's, not an estimate backed by data.
/// @throws std::invalid_argument naming the log's source for a missing position/velocity column
/// (listing those present) or a log that already has a "mean", "std" or "extrapolated" column.
/// Whether (x [m], ẋ [m/s]) lies outside the model's trained ranges (x_range(), xdot_range(), bounds
/// included in the range) or is not finite: a prediction there extrapolates.
bool GprExtrapolates(const GprModel& model, double x, double xdot) noexcept;

/// The name of PredictGprOnLog's extrapolation column (0/1).
inline constexpr const char* kGprExtrapolatedColumn = "extrapolated";

MeasurementLog PredictGprOnLog(const GprModel& model, const MeasurementLog& log,
                               const std::string& position_column = "position_m",
                               const std::string& velocity_column = "velocity_m_s");

}  // namespace mb

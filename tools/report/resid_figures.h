#pragma once
// The residual analysis views of compare's and improve's reports, as MATLAB's `resid`: the residual's
// autocorrelation and its cross-correlation with the input, each with its 99 % band and a sentence saying whether the
// residual is white and independent of the input (numerics and source: tools/workflow/residual_analysis.h).

#include <filesystem>
#include <optional>
#include <string>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "engine/experiment_mode.h"
#include "models/diagnosis/measurement_log.h"
#include "tools/report/report.h"

namespace mb {

/// A signal resid correlates the residual with: its name as the report says it, and its N values.
struct ResidInput {
  std::string name;  ///< e.g. "velocity (velocity_m_s)" or "command (u_V)"
  Eigen::VectorXd values;
};

/// The input of `resid`: in equation-error mode (the output is the force, the inputs the motion) the velocity derived
/// from `position_column` — what friction and most missing effects follow; in simulation mode the first input connector
/// of `diagram` (built against `base_directory`) whose measurement column `log` holds, else that velocity. None when
/// neither is in the log (or the input is constant). Never throws: a diagram that cannot be built falls back to the
/// velocity.
std::optional<ResidInput> ChooseResidInput(ExperimentMode mode, const nlohmann::json& diagram,
                                           const std::filesystem::path& base_directory, const MeasurementLog& log,
                                           const std::string& position_column);

/// Adds `resid`'s two figures to `report` (PNG names `prefix`resid_autocorrelation.png and
/// `prefix`resid_cross_correlation.png in `out`): the autocorrelation of `residual` (N samples of the log `log`, the
/// output's unit) for lags 0…25 and, with an `input`, the input–residual cross-correlation for lags −25…25, each with
/// the ±2.58/√N band and, under it, DescribeWhiteness / DescribeIndependence. With `before` (improve's residual of
/// step 0) its autocorrelation is drawn too, for comparison; the words are about `residual`. A residual too short
/// (≤ 50 samples) or constant becomes a note instead. @throws std::runtime_error if a figure's CSV cannot be written.
void AddResidFigures(HtmlReport* report, const std::filesystem::path& out, const std::string& prefix,
                     const MeasurementLog& log, const Eigen::VectorXd& residual, const Eigen::VectorXd* before,
                     const std::optional<ResidInput>& input);

}  // namespace mb

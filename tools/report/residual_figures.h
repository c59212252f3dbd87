#pragma once
// The residual figures that compare and improve share (gnuplot, report.h): the model against the measurement, the
// residual against time, position, velocity and acceleration (the views of DIAGNOSIS.md: a slope against
// acceleration is a mass mismatch, a shape against velocity the friction law, a period against position cogging),
// and the residual's position-domain periodogram.

#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "models/diagnosis/diagnosis.h"
#include "models/diagnosis/measurement_log.h"
#include "tools/report/report.h"
#include "tools/workflow/comparison.h"

namespace mb {

/// A vector's entries as a std::vector (a figure's series).
std::vector<double> ToStd(const Eigen::VectorXd& v);

/// compare's views of one output: measured vs model, and `residual` (measured − model after the fit, the
/// output's unit) against time, position (`position_column`, if logged), the derived velocity (with the binned mean:
/// the friction shape) and acceleration; with a diagnosis that found position peaks, the position periodogram.
void AddResidualFigures(HtmlReport* report, const std::filesystem::path& out, const MeasurementLog& log,
                        const ComparedOutput& before, const Eigen::VectorXd& residual_after,
                        const DiagnosisResult* diagnosis, const std::string& position_column);

/// improve's views of one record (`record` names it in the titles; `prefix` starts the PNG names): measured vs the
/// model before and after, and the residual before and after against time, position and velocity on the same axes.
void AddBeforeAfterFigures(HtmlReport* report, const std::filesystem::path& out, const std::string& prefix,
                           const std::string& record, const MeasurementLog& log, const ComparedOutput& before,
                           const ComparedOutput& after, const std::string& position_column);

}  // namespace mb

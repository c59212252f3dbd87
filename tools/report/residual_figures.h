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

/// The evidence for the `k`-th effect of `compared.diagnosis` (compare's ranking): its partial residual — the diagnosed
/// residual less the diagnosis's whole correction (PredictCorrection) plus this effect's own fitted contribution, the
/// output's unit — against the axis on which that contribution is most nearly a function (the largest share of its
/// variance held by 64-bin means: position folded over the effect's "period", time folded over 1/"frequency_hz",
/// velocity, acceleration, the logged command, the model output, time; a folded axis is preferred unless another
/// explains 5 % more), as dots, with the binned means of the partial residual and of the fitted contribution drawn over
/// them; y shows the middle 99.8 % of the partial residual. PNG name `file`. @throws std::invalid_argument if the
/// effect's regressors cannot be rebuilt on compared.signals (BuildEffectRegressors) or there is no diagnosis.
Figure EffectEvidenceFigure(const DiagnosedComparison& compared, std::size_t k, const std::string& unit,
                            const std::string& position_unit, const std::string& file);

/// improve's views of one record (`record` names it in the titles; `prefix` starts the PNG names): measured vs the
/// model before and after, and the residual before and after against time, position and velocity on the same axes.
void AddBeforeAfterFigures(HtmlReport* report, const std::filesystem::path& out, const std::string& prefix,
                           const std::string& record, const MeasurementLog& log, const ComparedOutput& before,
                           const ComparedOutput& after, const std::string& position_column);

}  // namespace mb

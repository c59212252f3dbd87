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
/// the friction shape) and acceleration. (The position periodogram is with the ranked effects: AddEffectEvidence.)
void AddResidualFigures(HtmlReport* report, const std::filesystem::path& out, const MeasurementLog& log,
                        const ComparedOutput& before, const Eigen::VectorXd& residual_after,
                        const std::string& position_column);

/// The share and confidence of a ranked effect in words: its share of the remaining held-out residual (score) and
/// the cumulative share, then each coefficient of the final joint fit with its 95 % interval (± 1.96 × its standard
/// deviation, DiagnosedEffect::coefficient_std) and whether the interval holds zero, e.g. "Share: 9.1 % of the
/// remaining held-out residual (cumulative 12.4 %). Coefficients, 95 % intervals: cos1 = 0.52 ± 0.03, sin1 = −0.01
/// ± 0.03 (holds 0); 1 of 2 significant."
std::string EffectShareAndConfidence(const DiagnosedEffect& effect);

/// compare's evidence for every ranked effect of `compared.diagnosis`, in the order they are applied k = 1, 2, …
/// (EffectsInApplicationOrder, tools/workflow/suggest.h: the order of compare's table): a paragraph
/// "k. effect: description", its share and confidence (EffectShareAndConfidence) and its evidence figure
/// (EffectEvidenceFigure, PNG effect_<k>.png, element id FigureId: "fig-effect_<k>"), or a warning saying why there is
/// none; then, when the diagnosis searched position periods, the position periodogram (PositionPeriodogramFigure,
/// "position_periodogram.png") with a sentence naming what it marks. `unit`: the output's; `position_unit` as
/// PositionUnitToken. Nothing without a diagnosis.
void AddEffectEvidence(HtmlReport* report, const std::filesystem::path& out, const DiagnosedComparison& compared,
                       const std::string& unit, const std::string& position_unit);

/// The position-domain periodogram of the diagnosed residual (compared.signals: residual against the low-passed
/// position) as the diagnosis searched it (effect_proposal.cc, default CatalogueOptions): the residual less the base's
/// corrections and the friction-law replacements (their final joint-fit coefficients), only the samples moving
/// faster than dead_band_fraction × max |v| (all when fewer than a quarter move), periods up to the travel /
/// min_position_cycles, log x; marked: each ranked effect's "period" and the strongest peak of the diagnosis's own
/// periodogram (DiagnosisResult::position_peaks, the one its notes name). PNG `file`. @throws std::invalid_argument if
/// there is no diagnosis or the periodogram cannot be computed (LombScarglePeriodogram).
Figure PositionPeriodogramFigure(const DiagnosedComparison& compared, const std::string& position_unit,
                                 const std::string& file);

/// The amplitude spectral density √PSD [unit/√Hz] of two residuals of the same record (improve: `before` = step 0's
/// refit, `after` = the last accepted step) against frequency [Hz], by WelchPowerSpectrum (signal_processing.h: Hann
/// segments of min(N, 1024) samples, 50 % overlap) at the median time step of `time`; 0 Hz left out, y logarithmic,
/// each label with its residual's RMS. A record with gaps is taken as uniformly sampled. PNG `file`.
/// @throws std::invalid_argument on a length mismatch or as WelchPowerSpectrum (N < 8).
Figure ResidualSpectrumFigure(const Eigen::VectorXd& time, const Eigen::VectorXd& before, const Eigen::VectorXd& after,
                              const std::string& unit, const std::string& file);

/// Two residuals' distributions on shared bins.
struct ResidualHistogram {
  std::vector<double> edges;               ///< bins + 1 increasing edges over [min, max] of both's finite values
  std::vector<std::size_t> before, after;  ///< samples per bin [edges[i], edges[i+1]) (the top edge in the last bin)
};

/// Counts `before` and `after` on `bins` uniform bins spanning both's finite values (a constant residual: one unit
/// around it); non-finite values are counted nowhere. @throws std::invalid_argument if bins is 0 or neither has a
/// finite value.
ResidualHistogram HistogramOfResiduals(const Eigen::VectorXd& before, const Eigen::VectorXd& after, std::size_t bins);

/// The histogram as a figure: two "steps" series (before, after) at the bins' left edges and, last, the right edge
/// with the last count again; x the residual [unit], y samples per bin. PNG `file`.
Figure ResidualHistogramFigure(const ResidualHistogram& histogram, const std::string& unit, const std::string& file);

/// The evidence for `compared.diagnosis->effects[k]` (titled with its number in compare's table): its partial residual — the diagnosed
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

/// improve's before/after distribution and spectrum of a record's residual (`prefix`residual_spectrum.png,
/// `prefix`residual_histogram.png: ResidualSpectrumFigure, ResidualHistogramFigure with √N bins, 10 to 100), each
/// series toggled in the chart; a record too short for either gets a warning instead.
void AddResidualSpectrumAndHistogram(HtmlReport* report, const std::filesystem::path& out, const std::string& prefix,
                                     const std::string& record, const MeasurementLog& log,
                                     const ComparedOutput& before, const ComparedOutput& after);

}  // namespace mb

// The evidence in compare's and improve's reports (tools/report/residual_figures.h, improve_report.h, issue 27 items 2
// and 3): improve's residual spectrum and distribution before/after hold the numbers computed here independently (the
// spectrum's rows are Welch's, its peak where the sinusoid is, its area the variance; the histogram's counts sum to
// the samples), the step table links to each step's plots; compare gives every ranked effect its evidence chart (a
// delay against its regressor, the lagged model output less the model output; a change in time against time) with
// its share and confidence, and the periodogram marks what the text names.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <limits>
#include <numbers>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include <fmt/format.h>

#include "models/diagnosis/effect_catalogue.h"
#include "models/diagnosis/signal_processing.h"
#include "tests/tools/report/report_test_files.h"
#include "tools/report/chart_data.h"
#include "tools/report/improve_report.h"
#include "tools/report/report.h"
#include "tools/report/residual_figures.h"

namespace mb {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using ::testing::HasSubstr;
using ::testing::StartsWith;

constexpr double kPi = std::numbers::pi;

using report_test::Count;
using report_test::EmbeddedCharts;
using report_test::Folder;
using report_test::Read;

// The chart whose title contains `title`, or null.
json ChartTitled(const json& charts, const std::string& title) {
  for (const auto& c : charts) {
    if (c["title"].get<std::string>().find(title) != std::string::npos) return c;
  }
  return nullptr;
}

Eigen::VectorXd Times(Eigen::Index n, double step) {
  return Eigen::VectorXd::LinSpaced(n, 0.0, step * static_cast<double>(n - 1));
}

Eigen::VectorXd Noise(Eigen::Index n, double sigma, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, sigma);
  Eigen::VectorXd v(n);
  for (Eigen::Index i = 0; i < n; ++i) v(i) = normal(rng);
  return v;
}

TEST(ResidualSpectrumFigure, HoldsWelchsDensityWithThePeakAtTheSinusoidAndTheVarianceAsItsArea) {
  const Eigen::Index n = 8192;
  const double step = 1e-3, f0 = 50.0, amplitude = 0.5;
  const Eigen::VectorXd t = Times(n, step);
  const Eigen::VectorXd before = amplitude * (2.0 * kPi * f0 * t.array()).sin().matrix() + Noise(n, 0.01, 1);
  const Eigen::VectorXd after = Noise(n, 0.01, 2);
  const Figure f = ResidualSpectrumFigure(t, before, after, "N", "residual_spectrum.png");
  ASSERT_EQ(f.series.size(), 2u);
  EXPECT_TRUE(f.log_y);
  EXPECT_EQ(f.xlabel, "frequency [Hz]");
  EXPECT_EQ(f.ylabel, "amplitude spectral density [N/√Hz]");
  // The rows are √ of Welch's density at each frequency but 0 Hz.
  const PowerSpectrum p = WelchPowerSpectrum(before, step);
  ASSERT_EQ(f.series[0].x.size(), static_cast<std::size_t>(p.frequency_hz.size() - 1));
  for (std::size_t i = 0; i < f.series[0].x.size(); ++i) {
    const auto k = static_cast<Eigen::Index>(i + 1);
    ASSERT_NEAR(f.series[0].x[i], p.frequency_hz(k), 1e-9 * p.frequency_hz(k));  // the median step: 1 ms ± rounding
    ASSERT_NEAR(f.series[0].y[i], std::sqrt(p.density(k)), 1e-12 * (1.0 + std::sqrt(p.density(k))));
  }
  // Independently of Welch's code: the tallest bin is at f0 (within a bin of 1000/1024 Hz), Σ ASD²·Δf is the variance
  // of the sinusoid and the noise (A²/2 + σ²), and the after curve lies far under the before one at f0.
  const auto peak = std::max_element(f.series[0].y.begin(), f.series[0].y.end()) - f.series[0].y.begin();
  EXPECT_NEAR(f.series[0].x[static_cast<std::size_t>(peak)], f0, 1.0);
  const double df = f.series[0].x[1] - f.series[0].x[0];
  double area = 0.0;
  for (double y : f.series[0].y) area += y * y * df;
  EXPECT_NEAR(area, amplitude * amplitude / 2.0 + 1e-4, 0.05 * amplitude * amplitude / 2.0);
  EXPECT_LT(f.series[1].y[static_cast<std::size_t>(peak)], 1e-2 * f.series[0].y[static_cast<std::size_t>(peak)]);
  EXPECT_THAT(f.series[0].label, HasSubstr("before (RMS 0.35"));
  // The chart holds the same rows (display precision) with both series in each.
  const json chart = ChartJson(f, "residual_spectrum.full.csv", 2000);
  ASSERT_EQ(chart["data"].size(), f.series[0].x.size());
  for (std::size_t i = 0; i < f.series[0].x.size(); ++i) {
    const json& row = chart["data"][i];
    ASSERT_NEAR(row[0].get<double>(), f.series[0].x[i], 1e-6 * f.series[0].x[i]);
    ASSERT_NEAR(row[1].get<double>(), f.series[0].y[i], 1e-6 * f.series[0].y[i]);
    ASSERT_NEAR(row[2].get<double>(), f.series[1].y[i], 1e-6 * f.series[1].y[i]);
  }
  EXPECT_TRUE(chart["logy"].get<bool>());
}

TEST(HistogramOfResiduals, CountsEverySampleOnceOnSharedBinsAndTheChartsRowsSumToTheSamples) {
  const Eigen::Index n = 5000;
  const Eigen::VectorXd before = Noise(n, 1.0, 3);
  Eigen::VectorXd after = Noise(n, 0.2, 4);
  after(17) = std::numeric_limits<double>::quiet_NaN();  // counted nowhere
  const std::size_t bins = 70;
  const ResidualHistogram h = HistogramOfResiduals(before, after, bins);
  ASSERT_EQ(h.edges.size(), bins + 1);
  ASSERT_EQ(h.before.size(), bins);
  ASSERT_EQ(h.after.size(), bins);
  EXPECT_DOUBLE_EQ(h.edges.front(), before.minCoeff());  // σ = 1 reaches further than σ = 0.2 either way
  EXPECT_DOUBLE_EQ(h.edges.back(), before.maxCoeff());
  std::size_t sum_before = 0, sum_after = 0;
  for (std::size_t i = 0; i < bins; ++i) {
    sum_before += h.before[i];
    sum_after += h.after[i];
  }
  EXPECT_EQ(sum_before, static_cast<std::size_t>(n));
  EXPECT_EQ(sum_after, static_cast<std::size_t>(n - 1));
  // Counted independently: the samples in one bin in the middle.
  const std::size_t b = bins / 2;
  std::size_t in_bin = 0;
  for (Eigen::Index i = 0; i < n; ++i) in_bin += (before(i) >= h.edges[b] && before(i) < h.edges[b + 1]) ? 1u : 0u;
  EXPECT_EQ(h.before[b], in_bin);

  const Figure f = ResidualHistogramFigure(h, "N", "residual_histogram.png");
  ASSERT_EQ(f.series.size(), 2u);
  EXPECT_EQ(f.series[0].style, "steps");
  const json chart = ChartJson(f, "residual_histogram.full.csv", 2000);
  EXPECT_EQ(chart["steps"], json::array({true, true}));
  EXPECT_EQ(chart["markers"], json::array({false, false}));
  ASSERT_EQ(chart["data"].size(), bins + 1);  // a row per left edge, and the right edge
  double rows_before = 0.0, rows_after = 0.0;
  for (std::size_t i = 0; i < bins; ++i) {
    rows_before += chart["data"][i][1].get<double>();
    rows_after += chart["data"][i][2].get<double>();
  }
  EXPECT_EQ(rows_before, static_cast<double>(n));
  EXPECT_EQ(rows_after, static_cast<double>(n - 1));
  EXPECT_THROW(HistogramOfResiduals(before, after, 0), std::invalid_argument);
}

// A comparison whose residual holds three known effects, a delay, a change of mass at t = 2 s and a position ripple,
// with the diagnosis that found them (no base parameters refit).
DiagnosedComparison ThreeEffects() {
  const Eigen::Index n = 4000;
  const double step = 1e-3;
  DiagnosisSignals s;
  s.time = Times(n, step);
  const Eigen::ArrayXd w = 2.0 * kPi * 1.0 * s.time.array();
  s.position = (0.05 * w.sin()).matrix();
  s.velocity = (0.05 * 2.0 * kPi * w.cos()).matrix();
  s.acceleration = (-0.05 * 4.0 * kPi * kPi * w.sin()).matrix();
  s.model_output = 2.0 * s.acceleration + 5.0 * s.velocity;
  DiagnosisResult d;
  const auto add = [&](const std::string& name, std::map<std::string, double> parameters, Eigen::VectorXd c,
                       Eigen::VectorXd sd, double score) {
    DiagnosedEffect e;
    e.effect = name;
    e.parameters = std::move(parameters);
    e.column_names = BuildEffectRegressors({e.effect, e.parameters}, s).column_names;
    e.coefficients = std::move(c);
    e.coefficient_std = std::move(sd);
    e.score = score;
    e.cumulative_share = (d.effects.empty() ? 0.0 : d.effects.back().cumulative_share) + score;
    e.selection_order = static_cast<int>(d.effects.size());
    e.description = "a test effect";
    d.effects.push_back(e);
  };
  add("time_delay", {{"delay", 0.004}}, Eigen::VectorXd::Constant(1, 1.0), Eigen::VectorXd::Constant(1, 0.02), 0.5);
  add("mass_change", {{"change_time", 2.0}}, Eigen::VectorXd::Constant(1, 0.05), Eigen::VectorXd::Constant(1, 0.01),
      0.2);
  add("position_periodic", {{"period", 0.01}, {"harmonics", 1}}, Eigen::Vector2d(0.3, 0.0), Eigen::Vector2d(0.01, 0.02),
      0.1);
  PeriodogramPeak peak;
  peak.period = 0.01;
  peak.power = 0.1;
  d.position_peaks = {peak};
  DiagnosedComparison compared;
  compared.base.columns = Eigen::MatrixXd(n, 0);
  s.residual = Noise(n, 0.01, 5);
  compared.signals = s;
  s.residual += PredictCorrection(d, s, compared.base);
  compared.signals = s;
  compared.diagnosis = d;
  return compared;
}

TEST(EffectEvidenceFigure, ADelayIsSeenAgainstItsRegressorTheLaggedModelOutputLessTheModelOutput) {
  const DiagnosedComparison compared = ThreeEffects();
  const Figure f = EffectEvidenceFigure(compared, 0, "N", "m", "effect_1.png");
  EXPECT_THAT(f.xlabel, StartsWith("its regressor ŷ(t − d) − ŷ(t) [N]"));
  EXPECT_THAT(f.title, HasSubstr("1. time_delay: 50.0 %"));
  ASSERT_EQ(f.series.size(), 3u);
  EXPECT_EQ(f.series[0].style, "dots");
  // The fitted delay against its own regressor is the line of slope 1 (its coefficient) through 0.
  const Series& fit = f.series[2];
  ASSERT_GT(fit.x.size(), 10u);
  const double span = f.y_range->second - f.y_range->first;
  for (std::size_t i = 0; i < fit.x.size(); ++i) ASSERT_NEAR(fit.y[i], fit.x[i], 0.05 * span);
  // The regressor: ŷ(t − d) − ŷ(t) on the samples.
  const Eigen::VectorXd lagged = ShiftedInTime(compared.signals.time, compared.signals.model_output, 0.004) -
                                 compared.signals.model_output;
  ASSERT_EQ(f.series[0].x.size(), static_cast<std::size_t>(lagged.size()));
  EXPECT_DOUBLE_EQ(f.series[0].x[1234], lagged(1234));
}

TEST(EffectEvidenceFigure, AChangeInTimeIsSeenAgainstTimeAsARecordWithItsInstantMarked) {
  const DiagnosedComparison compared = ThreeEffects();
  const Figure f = EffectEvidenceFigure(compared, 1, "N", "m", "effect_2.png");
  EXPECT_EQ(f.xlabel, "time [s]");
  EXPECT_EQ(f.x_link, "time");
  ASSERT_EQ(f.series.size(), 2u);
  EXPECT_EQ(f.series[0].style, "lines");
  EXPECT_EQ(f.series[1].label, "fitted mass_change");
  ASSERT_EQ(f.x_marks.size(), 1u);
  EXPECT_DOUBLE_EQ(f.x_marks[0].first, 2.0);
  EXPECT_EQ(f.x_marks[0].second, "change_time 2 s");
  // The fit is the record of 0.05·a·H(t − 2 s): zero before, 0.05·a after.
  const DiagnosisSignals& s = compared.signals;
  for (Eigen::Index i : {100, 1500, 2500, 3900}) {
    const double expected = s.time(i) < 2.0 ? 0.0 : 0.05 * s.acceleration(i);
    EXPECT_NEAR(f.series[1].y[static_cast<std::size_t>(i)], expected, 1e-9) << "t = " << s.time(i);
  }
}

TEST(EffectEvidenceFigure, ARippleIsSeenAgainstPositionFoldedOverItsPeriod) {
  const Figure f = EffectEvidenceFigure(ThreeEffects(), 2, "N", "m", "effect_3.png");
  EXPECT_THAT(f.xlabel, StartsWith("position modulo the period 10 mm"));
}

TEST(EffectShareAndConfidence, GivesTheShareAndEachCoefficientsIntervalAndWhetherItHoldsZero) {
  const DiagnosisResult d = *ThreeEffects().diagnosis;
  EXPECT_EQ(EffectShareAndConfidence(d.effects[0]),
            "Share: 50.0 % of the remaining held-out residual explained (cumulative 50.0 %). Coefficient of the final "
            "joint fit, 95 % interval: time_delay = 1 ± 0.039; significant.");
  EXPECT_EQ(EffectShareAndConfidence(d.effects[2]),
            "Share: 10.0 % of the remaining held-out residual explained (cumulative 80.0 %). Coefficients of the final "
            "joint fit, 95 % intervals: cos1 = 0.3 ± 0.02, sin1 = 0 ± 0.039 (holds 0); 1 of 2 significant.");
}

// The evidence follows compare's table (EffectsInApplicationOrder: the order the selection chose them), not the order of
// DiagnosisResult::effects, and each chart is of its own effect.
TEST(AddEffectEvidence, FollowsTheTablesOrderNotTheResultsOrder) {
  const fs::path dir = Folder("mb_effect_evidence_order");
  DiagnosedComparison compared = ThreeEffects();
  auto& effects = compared.diagnosis->effects;  // time_delay 50 %, mass_change 70 %, position_periodic 80 %
  std::rotate(effects.begin(), effects.begin() + 2, effects.end());  // position_periodic first in the result
  HtmlReport report("evidence", InteractiveCharts{});
  AddEffectEvidence(&report, dir, compared, "N", "m");
  report.Write(dir / "report.html");
  const std::string page = Read(dir / "report.html");
  const auto first = page.find("1. time_delay:"), second = page.find("2. mass_change:"),
             third = page.find("3. position_periodic:");
  ASSERT_NE(first, std::string::npos);
  ASSERT_NE(second, std::string::npos);
  ASSERT_NE(third, std::string::npos);
  EXPECT_LT(first, second);
  EXPECT_LT(second, third);
  // effect_3's chart is the ripple's: against position folded over its period.
  const auto chart3 = page.find("id=\"fig-effect_3\"");
  ASSERT_NE(chart3, std::string::npos);
  EXPECT_GT(chart3, third);
  const Figure ripple = EffectEvidenceFigure(compared, 0, "N", "m", "effect_3.png");
  EXPECT_EQ(ripple.xlabel.rfind("position modulo", 0), 0u) << ripple.xlabel;
  EXPECT_EQ(ripple.title.rfind("3. position_periodic:", 0), 0u) << ripple.title;
}

TEST(AddEffectEvidence, EveryRankedEffectHasItsChartItsShareAndConfidenceAndThePeriodogramMarksThePeriods) {
  const fs::path dir = Folder("mb_effect_evidence");
  const DiagnosedComparison compared = ThreeEffects();
  HtmlReport report("evidence", InteractiveCharts{});
  AddEffectEvidence(&report, dir, compared, "N", "m");
  report.Write(dir / "report.html");
  const std::string page = Read(dir / "report.html");
  for (int k = 1; k <= 3; ++k) {
    EXPECT_EQ(Count(page, fmt::format("id=\"fig-effect_{}\"", k)), 1u) << "no evidence chart for effect " << k;
  }
  EXPECT_EQ(Count(page, "Share: "), 3u);
  EXPECT_THAT(page, HasSubstr("time_delay = 1 ± 0.039; significant."));
  EXPECT_EQ(Count(page, "id=\"fig-position_periodogram\""), 1u);
  EXPECT_THAT(page, HasSubstr("Marked: position_periodic 10 mm; strongest peak (notes) 10 mm."));
  const json charts = EmbeddedCharts(page);
  ASSERT_EQ(charts.size(), 4u) << "three evidence charts and the periodogram";
  const json periodogram = ChartTitled(charts, "Position-domain periodogram");
  ASSERT_FALSE(periodogram.is_null());
  ASSERT_EQ(periodogram["marks"].size(), 2u);
  EXPECT_DOUBLE_EQ(periodogram["marks"][0][0].get<double>(), 0.01);
  EXPECT_EQ(periodogram["marks"][0][1], "position_periodic 10 mm");
  // The ripple's period is a peak of the plotted curve: the tallest point within ±10 % of it is near the top.
  double near = 0.0, tallest = 0.0;
  for (const auto& row : periodogram["data"]) {
    const double period = row[0].get<double>(), power = row[1].get<double>();
    tallest = std::max(tallest, power);
    if (std::abs(period - 0.01) < 0.001) near = std::max(near, power);
  }
  EXPECT_GT(near, 0.5 * tallest);
  for (const auto& c : charts) EXPECT_GT(c["data"].size(), 10u) << c["title"];
}

// An improve of three steps (the input refit, an accepted delay, a refused ripple) on a record of 3000 samples.
ImproveResult ThreeSteps(const MeasurementLog& log) {
  const Eigen::Index n = log.rows();
  const Eigen::VectorXd measured = log.column("force_N");
  const auto step = [&](bool accepted, const std::string& effect, double error, unsigned seed) {
    ImproveStep s;
    s.accepted = accepted;
    s.effect = effect;
    s.verdict = accepted ? "accepted: the held-out error fell" : "refused: no held-out gain";
    ComparedOutput out{"force", "force_N", "N", measured, measured - error * Noise(n, 1.0, seed), 0.0, 0.0};
    s.training.after = {out};
    s.training.before = {out};
    s.rmse_train = error;
    return s;
  };
  ImproveResult r;
  r.steps = {step(true, "", 1.0, 6), step(true, "time_delay", 0.3, 7), step(false, "position_periodic", 0.31, 8)};
  r.stop_reason = "test";
  return r;
}

TEST(WriteImproveReport, ShowsTheResidualsSpectrumAndDistributionBeforeAndAfterAndLinksEachStepToItsPlots) {
  const fs::path dir = Folder("mb_improve_evidence");
  const Eigen::Index n = 3000;
  const Eigen::VectorXd t = Times(n, 1e-3);
  const MeasurementLog log({"time_s", "force_N"}, {t, (2.0 * kPi * t.array()).sin().matrix()}, "record.csv");
  const ImproveResult result = ThreeSteps(log);
  WriteImproveReport(result, log, nullptr, "improve", dir, "position_m", dir);
  const std::string page = Read(dir / "report.html");
  // The step table's first cells link to each step's plots, which are there.
  for (const std::string id : {"before-after", "step-1", "step-2"}) {
    EXPECT_EQ(Count(page, "href=\"#" + id + "\""), 1u) << id;
    EXPECT_EQ(Count(page, "id=\"" + id + "\""), 1u) << id;
  }
  for (const std::string id : {"fig-residual_spectrum", "fig-residual_histogram", "fig-step_1_residual",
                               "fig-step_2_residual", "fig-model_vs_measurement"}) {
    EXPECT_EQ(Count(page, "id=\"" + id + "\""), 1u) << id;
  }
  const json charts = EmbeddedCharts(page);
  const json spectrum = ChartTitled(charts, "amplitude spectrum");
  ASSERT_FALSE(spectrum.is_null());
  EXPECT_EQ(spectrum["labels"].size(), 3u);  // frequency, before, after: each toggled
  // The histogram's rows count every sample of each residual once (√3000 ≈ 54 bins).
  const json histogram = ChartTitled(charts, "distribution");
  ASSERT_FALSE(histogram.is_null());
  const json& rows = histogram["data"];
  ASSERT_EQ(rows.size(), 55u);
  double before = 0.0, after = 0.0;
  for (std::size_t i = 0; i + 1 < rows.size(); ++i) {
    before += rows[i][1].get<double>();
    after += rows[i][2].get<double>();
  }
  EXPECT_EQ(before, static_cast<double>(n));
  EXPECT_EQ(after, static_cast<double>(n));
  // Step 2's plot compares the refused step with step 1, the last accepted before it.
  const json step2 = ChartTitled(charts, "Step 2:");
  ASSERT_FALSE(step2.is_null());
  EXPECT_EQ(step2["labels"], json::array({"time [s]", "before this step", "after (refused)"}));
}

}  // namespace
}  // namespace mb

// tools/report/frequency_figures.h: compare's frequency view on a record made by a generator of its own (a mass–
// spring–damper integrated by RK4 here, driven by a 0.5–50 Hz multi-sine, no block of the project involved): with the
// true parameters the measured response (H1) and the equation-error model's agree where the coherence is high, and
// the linearised model is drawn; with the mass doubled the view says where and by how much they part.

#include "tools/report/frequency_figures.h"

#include <cmath>
#include <numbers>
#include <random>
#include <regex>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "tests/tools/report/report_test_files.h"

namespace mb {
namespace {

using ::testing::HasSubstr;
using report_test::Folder;
using report_test::Read;

constexpr double kMass = 2.0, kDamping = 30.0, kStiffness = 4000.0;  // resonance 7.1 Hz
constexpr double kTs = 1e-3;

// time_s, position_m, velocity_m_s, acceleration_m_s2, force_N (with 0.05 N of noise) at 1 kHz for 24 s.
MeasurementLog GeneratedLog() {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> phase(0.0, 2.0 * std::numbers::pi);
  std::normal_distribution<double> noise(0.0, 0.05);
  std::vector<double> hz, phases;
  for (double f = 0.5; f <= 50.0; f += 0.37) hz.push_back(f), phases.push_back(phase(rng));
  const auto force = [&](double t) {
    double sum = 0.0;
    for (std::size_t i = 0; i < hz.size(); ++i) sum += 2.0 * std::sin(2.0 * std::numbers::pi * hz[i] * t + phases[i]);
    return sum;
  };
  const auto accel = [&](double t, double x, double v) { return (force(t) - kDamping * v - kStiffness * x) / kMass; };
  const Eigen::Index n = 24000;
  Eigen::VectorXd time(n), x(n), v(n), a(n), f(n);
  double xs = 0.0, vs = 0.0;
  const int substeps = 10;
  const double h = kTs / substeps;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double t = static_cast<double>(i) * kTs;
    time(i) = t, x(i) = xs, v(i) = vs, a(i) = accel(t, xs, vs), f(i) = force(t) + noise(rng);
    for (int s = 0; s < substeps; ++s) {  // RK4 to the next sample
      const double ts = t + s * h;
      const double k1x = vs, k1v = accel(ts, xs, vs);
      const double k2x = vs + 0.5 * h * k1v, k2v = accel(ts + 0.5 * h, xs + 0.5 * h * k1x, vs + 0.5 * h * k1v);
      const double k3x = vs + 0.5 * h * k2v, k3v = accel(ts + 0.5 * h, xs + 0.5 * h * k2x, vs + 0.5 * h * k2v);
      const double k4x = vs + h * k3v, k4v = accel(ts + h, xs + h * k3x, vs + h * k3v);
      xs += h / 6.0 * (k1x + 2 * k2x + 2 * k3x + k4x);
      vs += h / 6.0 * (k1v + 2 * k2v + 2 * k3v + k4v);
    }
  }
  return MeasurementLog({"time_s", "position_m", "velocity_m_s", "acceleration_m_s2", "force_N"}, {time, x, v, a, f});
}

// force = M·a + b·v + k·x, an equation-error model (motion in, force out).
nlohmann::json Model(double mass) {
  const auto gain = [](const std::string& name, double g) {
    return nlohmann::json{{"name", name}, {"type", "gain"}, {"parameters", {{"gain", g}}}};
  };
  const auto link = [](const std::string& from, const std::string& to_element, const std::string& to) {
    return nlohmann::json{{"startConnector", from}, {"endElement", to_element}, {"endConnector", to}};
  };
  return {{"schemaVersion", "1.0"},
          {"name", "msd_inverse"},
          {"experiment", {{"mode", "equation_error"}}},
          {"connectors",
           {{{"name", "position"}, {"kind", "input"}, {"unit", "m"}, {"measurement", "position_m"}},
            {{"name", "velocity"}, {"kind", "input"}, {"unit", "m/s"}, {"measurement", "velocity_m_s"}},
            {{"name", "acceleration"}, {"kind", "input"}, {"unit", "m/s^2"}, {"measurement", "acceleration_m_s2"}},
            {{"name", "force"}, {"kind", "output"}, {"unit", "N"}, {"measurement", "force_N"}}}},
          {"elements",
           {gain("inertia", mass), gain("damping", kDamping), gain("stiffness", kStiffness),
            {{"name", "total"}, {"type", "sum"}, {"parameters", {{"signs", "+++"}}}}}},
          {"connections",
           {link("acceleration", "inertia", "u"), link("velocity", "damping", "u"), link("position", "stiffness", "u"),
            {{"startElement", "inertia"}, {"startConnector", "y"}, {"endElement", "total"}, {"endConnector", "u1"}},
            {{"startElement", "damping"}, {"startConnector", "y"}, {"endElement", "total"}, {"endConnector", "u2"}},
            {{"startElement", "stiffness"}, {"startConnector", "y"}, {"endElement", "total"}, {"endConnector", "u3"}},
            {{"startElement", "total"}, {"startConnector", "y"}, {"endConnector", "force"}}}}};
}

struct Gaps {
  double median_db = NAN, worst_db = NAN;
  std::string text;
};

// The report's sentence on the gains, read back.
Gaps FrequencyView(double mass, const std::string& folder) {
  const MeasurementLog log = GeneratedLog();
  const Eigen::VectorXd model = mass * log.column("acceleration_m_s2") + kDamping * log.column("velocity_m_s") +
                                kStiffness * log.column("position_m");
  const ComparedOutput output{"force", "force_N", "N", log.column("force_N"), model, 0.0, 0.0};
  const auto out = Folder(folder);
  HtmlReport report("frequency view");
  AddFrequencyResponseFigures(&report, out, ExperimentMode::kEquationError, Model(mass), ".", log, output);
  report.Write(out / "report.html");
  Gaps gaps;
  gaps.text = Read(out / "report.html") + Read(out / "plot" / "frequency_response_gain.gp");  // page and curves
  std::smatch m;
  if (std::regex_search(gaps.text, m, std::regex(R"(by ([0-9.e+-]+) dB \(median\) and by ([0-9.e+-]+) dB at most)"))) {
    gaps.median_db = std::stod(m[1]);
    gaps.worst_db = std::stod(m[2]);
  }
  std::filesystem::remove_all(out);
  return gaps;
}

TEST(FrequencyResponseFigures, TheTrueModelAgreesWithTheMeasuredResponseWhereTheCoherenceIsHigh) {
  const Gaps gaps = FrequencyView(kMass, "mb_frequency_true");
  EXPECT_THAT(gaps.text, HasSubstr("Welch's H1 estimates from position (position_m) to force_N"));
  EXPECT_THAT(gaps.text, HasSubstr("The linearised model (0 continuous states"));
  EXPECT_THAT(gaps.text, HasSubstr("model, linearised"));  // the gain figure's third curve
  ASSERT_FALSE(std::isnan(gaps.median_db)) << gaps.text;
  EXPECT_LT(gaps.median_db, 0.5);
}

TEST(FrequencyResponseFigures, ADoubledMassShowsAsTheModelRespondingMoreAboveTheResonance) {
  const Gaps gaps = FrequencyView(2.0 * kMass, "mb_frequency_heavy");
  ASSERT_FALSE(std::isnan(gaps.worst_db)) << gaps.text;
  EXPECT_LT(gaps.worst_db, -4.0);  // toward −6 dB where M s² dominates
  EXPECT_THAT(gaps.text, HasSubstr("the model responds more than the stage"));
}

TEST(FrequencyResponseFigures, ALogWithoutTheInputsColumnSaysSo) {
  const MeasurementLog log({"time_s", "force_N"}, {Eigen::VectorXd::LinSpaced(100, 0.0, 0.099),
                                                   Eigen::VectorXd::Ones(100)});
  const ComparedOutput output{"force", "force_N", "N", log.column("force_N"), log.column("force_N"), 0.0, 0.0};
  const auto out = Folder("mb_frequency_none");
  HtmlReport report("frequency view");
  AddFrequencyResponseFigures(&report, out, ExperimentMode::kEquationError, Model(kMass), ".", log, output);
  report.Write(out / "report.html");
  EXPECT_THAT(Read(out / "report.html"), HasSubstr("No frequency view: the log holds no column"));
  std::filesystem::remove_all(out);
}

}  // namespace
}  // namespace mb

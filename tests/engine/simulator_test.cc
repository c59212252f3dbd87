// Engine against closed forms: first- and second-order systems, a discrete filter against its difference
// equation, a mixed continuous/discrete loop, fixed-step vs CVODE agreement, sample-time boundaries.

#include <cmath>
#include <numbers>
#include <vector>

#include <gtest/gtest.h>

#include "engine/diagram_loader.h"
#include "tests/engine/test_util.h"

namespace mb {
namespace {

using nlohmann::json;
using testing::Build;
using testing::Connect;

// ẋ = −a·x, x(0) = 1  →  x(t) = e^{−a t}.
json FirstOrder(const json& solver, double a = 2.0) {
  return {{"schemaVersion", "1.0"},
          {"defaultExperiment", {{"startTime", 0.0}, {"stopTime", 2.0}, {"stepSize", 0.01}}},
          {"solver", solver},
          {"elements",
           {{{"name", "x"}, {"type", "integrator"}, {"parameters", {{"initial_condition", 1.0}}}},
            {{"name", "k"}, {"type", "gain"}, {"parameters", {{"gain", -a}}}}}},
          {"connections", {Connect("x.y", "k.u"), Connect("k.y", "x.u")}},
          {"log", {"x.y"}}};
}

double MaxErrorFirstOrder(const SimulationResult& r, double a) {
  const auto& x = r.log.Column("x.y");
  double worst = 0.0;
  for (std::size_t i = 0; i < x.size(); ++i) worst = std::max(worst, std::abs(x[i] - std::exp(-a * r.log.time[i])));
  return worst;
}

TEST(SimulatorTest, FirstOrderRk4MatchesExponential) {
  const Diagram d = Build(FirstOrder({{"type", "rk4"}, {"step", 1e-3}}));
  const auto r = Simulator(d).Run();
  ASSERT_EQ(r.log.time.size(), 201u);
  EXPECT_NEAR(r.log.time.back(), 2.0, 1e-12);
  EXPECT_LT(MaxErrorFirstOrder(r, 2.0), 1e-11);  // RK4 global error ~ h^4
}

TEST(SimulatorTest, FirstOrderEulerIsFirstOrderAccurate) {
  const auto e1 = MaxErrorFirstOrder(Simulator(Build(FirstOrder({{"type", "euler"}, {"step", 1e-3}}))).Run(), 2.0);
  const auto e2 = MaxErrorFirstOrder(Simulator(Build(FirstOrder({{"type", "euler"}, {"step", 5e-4}}))).Run(), 2.0);
  EXPECT_NEAR(e1 / e2, 2.0, 0.05);  // halving h halves the error
}

TEST(SimulatorTest, FirstOrderCvodeMeetsTolerance) {
  for (const char* method : {"bdf", "adams"}) {
    const Diagram d = Build(FirstOrder({{"type", "cvode"}, {"method", method}, {"rtol", 1e-8}, {"atol", 1e-10}}));
    const auto r = Simulator(d).Run();
    EXPECT_LT(MaxErrorFirstOrder(r, 2.0), 1e-6) << method;
    EXPECT_EQ(r.solver_name, "cvode");
    EXPECT_GT(r.solver_stats.steps, 0);
  }
}

// Undamped oscillator ẍ = −ω²x, x(0) = 1: x = cos ωt.
TEST(SimulatorTest, SecondOrderOscillatorMatchesCosine) {
  const double w = 3.0;
  json j = {{"schemaVersion", "1.0"},
            {"defaultExperiment", {{"stopTime", 5.0}, {"stepSize", 0.05}}},
            {"solver", {{"type", "cvode"}, {"rtol", 1e-9}, {"atol", 1e-12}}},
            {"elements",
             {{{"name", "v"}, {"type", "integrator"}},
              {{"name", "x"}, {"type", "integrator"}, {"parameters", {{"initial_condition", 1.0}}}},
              {{"name", "k"}, {"type", "gain"}, {"parameters", {{"gain", -w * w}}}}}},
            {"connections", {Connect("x.y", "k.u"), Connect("k.y", "v.u"), Connect("v.y", "x.u")}},
            {"log", {"x.y"}}};
  const auto r = Simulator(Build(j)).Run();
  const auto& x = r.log.Column("x.y");
  for (std::size_t i = 0; i < x.size(); ++i) EXPECT_NEAR(x[i], std::cos(w * r.log.time[i]), 1e-6);
}

// Discrete first-order filter y[k+1] = a·y[k] + b·u[k] with a unit delay in a loop, Ts = 0.1 s.
TEST(SimulatorTest, DiscreteFilterMatchesDifferenceEquation) {
  const double a = 0.8, b = 0.5;
  json j = {{"schemaVersion", "1.0"},
            {"defaultExperiment", {{"stopTime", 2.0}}},
            {"elements",
             {{{"name", "u"}, {"type", "constant"}, {"parameters", {{"value", 1.0}}}},
              {{"name", "bu"}, {"type", "gain"}, {"parameters", {{"gain", b}}}},
              {{"name", "ay"}, {"type", "gain"}, {"parameters", {{"gain", a}}}},
              {{"name", "add"}, {"type", "sum"}},
              {{"name", "z"}, {"type", "unit_delay"}, {"sampleTime", {0.1, 0.0}}}}},
            {"connections",
             {Connect("u.y", "bu.u"), Connect("z.y", "ay.u"), Connect("bu.y", "add.u1"), Connect("ay.y", "add.u2"),
              Connect("add.y", "z.u")}},
            {"log", {"z.y"}}};
  const auto r = Simulator(Build(j)).Run();
  ASSERT_EQ(r.log.time.size(), 21u);  // log step defaults to the fastest period
  double y = 0.0;
  for (std::size_t k = 0; k < r.log.time.size(); ++k) {
    EXPECT_NEAR(r.log.time[k], 0.1 * static_cast<double>(k), 1e-12);
    EXPECT_NEAR(r.log.Column("z.y")[k], y, 1e-12) << "k = " << k;
    y = a * y + b * 1.0;
  }
}

// Sampled integrator loop: a continuous plant ẋ = u, u held by a discrete controller u[k] = −K·x(t_k) at Ts.
// Exact solution on the grid: x[k+1] = (1 − K·Ts)·x[k].
TEST(SimulatorTest, MixedContinuousDiscreteLoopMatchesZohDiscretisation) {
  const double K = 4.0, Ts = 0.05;
  for (const char* solver : {"rk4", "cvode"}) {
    json j = {{"schemaVersion", "1.0"},
              {"defaultExperiment", {{"stopTime", 1.0}, {"stepSize", Ts}}},
              {"solver", {{"type", solver}, {"step", 1e-3}, {"rtol", 1e-10}, {"atol", 1e-12}}},
              {"elements",
               {{{"name", "x"}, {"type", "integrator"}, {"parameters", {{"initial_condition", 1.0}}}},
                {{"name", "ctrl"}, {"type", "gain"}, {"parameters", {{"gain", -K}}}},
                {{"name", "hold"}, {"type", "unit_delay"}, {"sampleTime", Ts}}}},
              // The unit delay adds one sample of latency: u[k] = −K x[k−1].
              {"connections", {Connect("x.y", "ctrl.u"), Connect("ctrl.y", "hold.u"), Connect("hold.y", "x.u")}},
              {"log", {"x.y"}}};
    const auto r = Simulator(Build(j)).Run();
    double x_prev = 1.0, x = 1.0;  // x[-1] := x0, since the delay starts at 0: u[0] = 0
    double u = 0.0;
    const auto& xs = r.log.Column("x.y");
    for (std::size_t k = 0; k < xs.size(); ++k) {
      EXPECT_NEAR(xs[k], x, 1e-8) << solver << " k = " << k;
      const double next = x + Ts * u;
      u = -K * x;
      x_prev = x;
      x = next;
    }
    (void)x_prev;
  }
}

TEST(SimulatorTest, FixedStepAndCvodeAgreeOnNonlinearLoop) {
  auto diagram = [](const json& solver) {
    return json{{"schemaVersion", "1.0"},
                {"defaultExperiment", {{"stopTime", 3.0}, {"stepSize", 0.01}}},
                {"solver", solver},
                {"elements",
                 {{{"name", "v"}, {"type", "integrator"}, {"parameters", {{"initial_condition", 1.0}}}},
                  {{"name", "x"}, {"type", "integrator"}},
                  {{"name", "kx"}, {"type", "gain"}, {"parameters", {{"gain", -10.0}}}},
                  {{"name", "kv"}, {"type", "gain"}, {"parameters", {{"gain", -0.5}}}},
                  {{"name", "acc"}, {"type", "sum"}}}},
                {"connections",
                 {Connect("x.y", "kx.u"), Connect("v.y", "kv.u"), Connect("kx.y", "acc.u1"), Connect("kv.y", "acc.u2"),
                  Connect("acc.y", "v.u"), Connect("v.y", "x.u")}},
                {"log", {"x.y"}}};
  };
  const auto a = Simulator(Build(diagram({{"type", "rk4"}, {"step", 1e-3}}))).Run();
  const auto b = Simulator(Build(diagram({{"type", "cvode"}, {"rtol", 1e-9}, {"atol", 1e-12}}))).Run();
  ASSERT_EQ(a.log.time.size(), b.log.time.size());
  for (std::size_t i = 0; i < a.log.time.size(); ++i) {
    EXPECT_NEAR(a.log.Column("x.y")[i], b.log.Column("x.y")[i], 1e-7);
  }
}

TEST(SimulatorTest, DiscreteOnlyDiagramRunsAndRespectsOffset) {
  // A unit delay with offset 0.05 s in a 0.1 s period: its state changes only at 0.05, 0.15, …
  json j = {{"schemaVersion", "1.0"},
            {"defaultExperiment", {{"stopTime", 0.3}, {"stepSize", 0.05}}},
            {"elements",
             {{{"name", "one"}, {"type", "constant"}, {"parameters", {{"value", 1.0}}}},
              {{"name", "z"}, {"type", "unit_delay"}, {"sampleTime", {0.1, 0.05}}}}},
            {"connections", {Connect("one.y", "z.u")}},
            {"log", {"z.y"}}};
  const auto r = Simulator(Build(j)).Run();
  // t = 0, .05, .1, …, .3: the first hit (0.05) outputs the initial condition, the second (0.15) the input.
  const std::vector<double> expected = {0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0};
  ASSERT_EQ(r.log.Column("z.y").size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) EXPECT_EQ(r.log.Column("z.y")[i], expected[i]) << i;
}

// A log step that differs from the sample period by rounding (a step taken from a measured time column) must
// neither skip a hit nor log a block one sample late, however long the run: a counter (unit delay + 1) at 1 kHz,
// logged on a grid of (1 + 2e-13) ms over 20 s, where the two grids drift 4e-12 s apart.
TEST(SimulatorTest, NoHitIsSkippedWhenTheLogGridDriftsByRounding) {
  const double ts = 1e-3;
  json j = {{"schemaVersion", "1.0"},
            {"defaultExperiment", {{"stopTime", 20.0}, {"stepSize", ts * (1.0 + 2e-13)}}},
            {"elements",
             {{{"name", "one"}, {"type", "constant"}, {"parameters", {{"value", 1.0}}}},
              {{"name", "next"}, {"type", "sum"}, {"parameters", {{"signs", "++"}}}},
              {{"name", "count"}, {"type", "unit_delay"}, {"sampleTime", {ts, 0.0}}}}},
            {"connections", {Connect("one.y", "next.u1"), Connect("count.y", "next.u2"), Connect("next.y", "count.u")}},
            {"log", {"count.y"}}};
  const auto r = Simulator(Build(j)).Run();
  const auto& count = r.log.Column("count.y");
  ASSERT_GE(count.size(), 19999u);
  for (std::size_t i = 0; i < count.size(); ++i) {
    ASSERT_EQ(count[i], static_cast<double>(i)) << "t = " << r.log.time[i];
  }
}

// A mode change at a major step (a step block switching at 0.2 s) is seen by a discrete block sampling at
// that same instant: outputs after the event iteration are recomputed with the hits of that step.
TEST(SimulatorTest, DiscreteBlockSamplesValueAfterModeChangeAtSameInstant) {
  json j = {{"schemaVersion", "1.0"},
            {"defaultExperiment", {{"stopTime", 0.4}, {"stepSize", 0.1}}},
            {"elements",
             {{{"name", "s"}, {"type", "step"}, {"parameters", {{"time", 0.2}, {"initial", 0.0}, {"final", 1.0}}}},
              {{"name", "h"}, {"type", "zero_order_hold"}, {"sampleTime", 0.1}}}},
            {"connections", {Connect("s.y", "h.u")}},
            {"log", {"h.y"}}};
  const auto r = Simulator(Build(j)).Run();
  const std::vector<double> expected = {0.0, 0.0, 1.0, 1.0, 1.0};
  ASSERT_EQ(r.log.Column("h.y").size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) EXPECT_EQ(r.log.Column("h.y")[i], expected[i]) << i;
}

// A continuous state driven by a discrete block: CVODE is reinitialised at every sample hit, which resets its
// own step counter; the reported steps must count the steps of every segment.
TEST(SimulatorTest, CvodeStepCountSurvivesReinitialisation) {
  json j = {{"schemaVersion", "1.0"},
            {"defaultExperiment", {{"stopTime", 1.0}, {"stepSize", 0.1}}},
            {"solver", {{"type", "cvode"}}},
            {"elements",
             {{{"name", "s"}, {"type", "step"}, {"parameters", {{"time", 0.0}, {"initial", 0.0}, {"final", 1.0}}}},
              {{"name", "h"}, {"type", "zero_order_hold"}, {"sampleTime", 0.1}},
              {{"name", "x"}, {"type", "integrator"}}}},
            {"connections", {Connect("s.y", "h.u"), Connect("h.y", "x.u")}},
            {"log", {"x.y"}}};
  const auto r = Simulator(Build(j)).Run();
  EXPECT_NEAR(r.log.Column("x.y").back(), 1.0, 1e-6);
  ASSERT_GT(r.solver_stats.reinitialisations, 5);
  EXPECT_GE(r.solver_stats.steps, r.solver_stats.reinitialisations - 1);
}

TEST(SimulatorTest, MetricsComputedFromLog) {
  json j = FirstOrder({{"type", "rk4"}, {"step", 1e-3}});
  j["metrics"] = {{{"name", "x_rmse"}, {"type", "rmse"}, {"signal", "x.y"}, {"unit", ""}},
                  {{"name", "x_final"}, {"type", "final"}, {"signal", "x.y"}},
                  {{"name", "x_max"}, {"type", "max_abs"}, {"signal", "x.y"}, {"from", 1.0}}};
  const auto r = Simulator(Build(j)).Run();
  EXPECT_NEAR(r.metrics.at("x_final"), std::exp(-4.0), 1e-9);
  EXPECT_NEAR(r.metrics.at("x_max"), std::exp(-2.0), 1e-9);
  double sum_sq = 0.0;
  for (double t : r.log.time) sum_sq += std::exp(-4.0 * t);
  EXPECT_NEAR(r.metrics.at("x_rmse"), std::sqrt(sum_sq / 201.0), 1e-9);
}

TEST(SimulatorTest, ExternalInputIsInterpolatedLinearly) {
  json j = {{"schemaVersion", "1.0"},
            {"defaultExperiment", {{"stopTime", 1.0}, {"stepSize", 0.25}}},
            {"connectors", {{{"name", "u"}, {"kind", "input"}}, {{"name", "y"}, {"kind", "output"}}}},
            {"elements", {{{"name", "g"}, {"type", "gain"}, {"parameters", {{"gain", 2.0}}}}}},
            {"connections", {{{"startConnector", "u"}, {"endElement", "g"}, {"endConnector", "u"}},
                             {{"startElement", "g"}, {"startConnector", "y"}, {"endConnector", "y"}}}}};
  const Diagram d = Build(j);
  Simulator sim(d);
  EXPECT_THROW(sim.Run(), std::runtime_error);  // required input not set
  sim.SetInput("u", {{0.0, 1.0}, {0.0, 10.0}});
  const auto r = sim.Run();
  const std::vector<double> expected = {0.0, 5.0, 10.0, 15.0, 20.0};
  for (std::size_t i = 0; i < expected.size(); ++i) EXPECT_NEAR(r.log.Column("y")[i], expected[i], 1e-12);
  EXPECT_THROW(sim.SetInput("nope", {{0.0}, {1.0}}), std::invalid_argument);
  EXPECT_THROW(sim.SetInput("u", {{0.0, 0.0}, {1.0, 2.0}}), std::invalid_argument);
}

// A smooth reference logged at 100 Hz into a diagram that runs at 1 kHz: linear interpolation errs by up to h²·|ẍ|/8
// between the samples, the cubic Hermite (the connector's "interpolation": "cubic") by O(h⁴); both pass through the
// samples.
TEST(SimulatorTest, ACubicInputFollowsASmoothSignalBetweenItsSamples) {
  const auto run = [](const char* interpolation) {
    json j = {{"schemaVersion", "1.0"},
              {"defaultExperiment", {{"stopTime", 1.0}, {"stepSize", 0.001}}},
              {"connectors", {{{"name", "u"}, {"kind", "input"}, {"interpolation", interpolation}},
                              {{"name", "y"}, {"kind", "output"}}}},
              {"elements", {{{"name", "g"}, {"type", "gain"}, {"parameters", {{"gain", 1.0}}}}}},
              {"connections", {{{"startConnector", "u"}, {"endElement", "g"}, {"endConnector", "u"}},
                               {{"startElement", "g"}, {"startConnector", "y"}, {"endConnector", "y"}}}}};
    const Diagram d = Build(j);
    Simulator sim(d);
    InputSeries series;
    for (int k = 0; k <= 100; ++k) {
      series.time.push_back(0.01 * k);
      series.values.push_back(std::sin(2.0 * std::numbers::pi * 0.01 * k));
    }
    sim.SetInput("u", series);
    const auto r = sim.Run();
    double worst = 0.0;
    for (std::size_t i = 20; i + 20 < r.log.time.size(); ++i) {  // away from the first and last intervals
      worst = std::max(worst, std::abs(r.log.Column("y")[i] - std::sin(2.0 * std::numbers::pi * r.log.time[i])));
    }
    return worst;
  };
  const double linear = run("linear"), cubic = run("cubic");
  EXPECT_NEAR(linear, std::pow(2.0 * std::numbers::pi * 0.01, 2) / 8.0, 2e-5);  // h²·max|ẍ|/8
  EXPECT_LT(cubic, 0.05 * linear) << "linear " << linear << ", cubic " << cubic;
  json bad = {{"schemaVersion", "1.0"},
              {"connectors", {{{"name", "u"}, {"kind", "input"}, {"interpolation", "spline"}}}},
              {"elements", {{{"name", "g"}, {"type", "gain"}, {"parameters", {{"gain", 1.0}}}}}},
              {"connections", {{{"startConnector", "u"}, {"endElement", "g"}, {"endConnector", "u"}}}}};
  try {
    Build(bad);
    FAIL() << "an unknown interpolation was accepted";
  } catch (const DiagramError& e) {
    EXPECT_NE(std::string(e.what()).find("/connectors/0/interpolation: 'spline' is not an interpolation"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace mb

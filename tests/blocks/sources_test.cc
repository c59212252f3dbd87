// Sources: step (value on both sides, located by CVODE, seen by a sampler at its own instant), sine (closed
// form, sampled form), from_file (linear and zoh interpolation, hold outside the range, file errors).

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

#include "tests/blocks/block_test_util.h"

namespace mb {
namespace {

using nlohmann::json;
using testing::Build;
using testing::BuildError;
using testing::Connect;
using testing::Element;
using testing::MakeDiagram;
using ::testing::HasSubstr;

TEST(StepTest, OutputsInitialBeforeAndFinalFromTheStepTime) {
  const json j = MakeDiagram({Element("s", "step", {{"time", 0.3}, {"initial", -2.0}, {"final", 5.0}})}, json::array(),
                             {"s.y"}, 1.0, 0.1);
  const auto r = Simulator(Build(j)).Run();
  const auto& y = r.log.Column("s.y");
  ASSERT_EQ(y.size(), 11u);
  for (std::size_t i = 0; i < y.size(); ++i) {
    EXPECT_EQ(y[i], r.log.time[i] >= 0.3 - 1e-12 ? 5.0 : -2.0) << "t = " << r.log.time[i];
  }
}

TEST(StepTest, CvodeStopsAtTheStepTime) {
  // ∫ step: x(t) = final·(t − T) for t ≥ T. A step time off every grid shows the solver located it.
  const double T = 0.7337;
  const json j = MakeDiagram({Element("s", "step", {{"time", T}, {"final", 2.0}}), Element("x", "integrator")},
                             {Connect("s.y", "x.u")}, {"x.y"}, 2.0, 0.5,
                             {{"type", "cvode"}, {"rtol", 1e-10}, {"atol", 1e-12}});
  const auto r = Simulator(Build(j)).Run();
  const auto& x = r.log.Column("x.y");
  EXPECT_NEAR(x[1], 0.0, 1e-12);            // t = 0.5
  EXPECT_NEAR(x[2], 2.0 * (1.0 - T), 1e-9);  // t = 1.0
  EXPECT_NEAR(x.back(), 2.0 * (2.0 - T), 1e-9);
  EXPECT_GE(r.solver_stats.roots_found, 1);
}

TEST(StepTest, SamplerAfterTheLocatedStepReadsTheFinalValue) {
  // The step at 0.25 s lies between the sampler's hits; CVODE locates it (the integrator gives the diagram
  // continuous states), so the hit at 0.3 s reads the final value.
  const json j = MakeDiagram({Element("s", "step", {{"time", 0.25}}), Element("x", "integrator"),
                              Element("h", "zero_order_hold", json::object(), {0.1, 0.0})},
                             {Connect("s.y", "h.u"), Connect("s.y", "x.u")}, {"h.y", "s.y"}, 0.4, 0.05,
                             {{"type", "cvode"}, {"rtol", 1e-10}, {"atol", 1e-12}});
  const auto r = Simulator(Build(j)).Run();
  const std::vector<double> held = {0, 0, 0, 0, 0, 0, 1, 1, 1};    // t = 0, 0.05, …, 0.4
  const std::vector<double> step = {0, 0, 0, 0, 0, 1, 1, 1, 1};
  EXPECT_EQ(r.log.Column("h.y"), held);
  EXPECT_EQ(r.log.Column("s.y"), step);
}

TEST(StepTest, FixedStepSolverSwitchesWithinOneIntegrationStep) {
  const double T = 0.7337, h = 1e-3;
  const json j = MakeDiagram({Element("s", "step", {{"time", T}}), Element("x", "integrator")},
                             {Connect("s.y", "x.u")}, {"x.y"}, 1.0, 0.5, {{"type", "rk4"}, {"step", h}});
  const auto r = Simulator(Build(j)).Run();
  EXPECT_NEAR(r.log.Column("x.y").back(), 1.0 - T, h);
}

// switched_gain: 0 before its time, gain·u from it on (a payload picked up: its mass times the acceleration).
TEST(SwitchedGainTest, ZeroBeforeTheTimeThenGainTimesTheInput) {
  const json j = MakeDiagram({Element("u", "constant", {{"value", 3.0}}),
                              Element("g", "switched_gain", {{"gain", 31.0}, {"time", 0.45}})},
                             {Connect("u.y", "g.u")}, {"g.y"}, 1.0, 0.05);
  const auto r = Simulator(Build(j)).Run();
  const auto& y = r.log.Column("g.y");
  for (std::size_t i = 0; i < y.size(); ++i) {
    EXPECT_EQ(y[i], r.log.time[i] >= 0.45 - 1e-12 ? 93.0 : 0.0) << "t = " << r.log.time[i];
  }
}

// With an off_time it is a window: gain·u from time until off_time, 0 before and after (a payload carried and set
// down), each switch a located event (CVODE stops at both); an off_time not after the time is refused.
TEST(SwitchedGainTest, AnOffTimeMakesAWindow) {
  const json j = MakeDiagram({Element("u", "constant", {{"value", 3.0}}),
                              Element("g", "switched_gain", {{"gain", 31.0}, {"time", 0.25}, {"off_time", 0.65}})},
                             {Connect("u.y", "g.u")}, {"g.y"}, 1.0, 0.05);
  const auto r = Simulator(Build(j)).Run();
  const auto& y = r.log.Column("g.y");
  for (std::size_t i = 0; i < y.size(); ++i) {
    const double t = r.log.time[i];
    EXPECT_EQ(y[i], t >= 0.25 - 1e-12 && t < 0.65 - 1e-12 ? 93.0 : 0.0) << "t = " << t;
  }
  const json backwards = MakeDiagram({Element("u", "constant", {{"value", 3.0}}),
                                      Element("g", "switched_gain", {{"gain", 1.0}, {"time", 0.5}, {"off_time", 0.5}})},
                                     {Connect("u.y", "g.u")}, {"g.y"}, 1.0, 0.05);
  EXPECT_THAT(BuildError(backwards), HasSubstr("off_time 0.5 s must lie after time 0.5 s"));
}

// clock: y = t (Simulink's Clock); through an integrator, t²/2.
TEST(ClockTest, OutputsTheSimulationTime) {
  const json j = MakeDiagram({Element("c", "clock"), Element("x", "integrator")}, {Connect("c.y", "x.u")},
                             {"c.y", "x.y"}, 1.0, 0.1);
  const auto r = Simulator(Build(j)).Run();
  const auto& y = r.log.Column("c.y");
  for (std::size_t i = 0; i < y.size(); ++i) EXPECT_DOUBLE_EQ(y[i], r.log.time[i]);
  EXPECT_NEAR(r.log.Column("x.y").back(), 0.5, 1e-6);
}

TEST(SineTest, MatchesClosedForm) {
  const double A = 1.5, f = 2.0, phi = 0.3, b = -0.25;
  const json j = MakeDiagram(
      {Element("s", "sine", {{"amplitude", A}, {"frequency_hz", f}, {"phase", phi}, {"bias", b}})}, json::array(),
      {"s.y"}, 1.0, 0.01);
  const auto r = Simulator(Build(j)).Run();
  const auto& y = r.log.Column("s.y");
  for (std::size_t i = 0; i < y.size(); ++i) {
    EXPECT_NEAR(y[i], A * std::sin(2.0 * std::numbers::pi * f * r.log.time[i] + phi) + b, 1e-12);
  }
}

TEST(SineTest, SampledSineHoldsBetweenHits) {
  const json j = MakeDiagram({Element("s", "sine", {{"frequency_hz", 1.0}}, {0.1, 0.0})}, json::array(), {"s.y"},
                             0.5, 0.05);
  const auto r = Simulator(Build(j)).Run();
  const auto& y = r.log.Column("s.y");
  for (std::size_t i = 0; i < y.size(); ++i) {
    const double hit = 0.1 * std::floor(r.log.time[i] / 0.1 + 1e-9);
    EXPECT_NEAR(y[i], std::sin(2.0 * std::numbers::pi * hit), 1e-12) << "t = " << r.log.time[i];
  }
}

TEST(SineTest, RejectsNegativeFrequency) {
  const json j = MakeDiagram({Element("s", "sine", {{"frequency_hz", -1.0}})}, json::array(), {"s.y"}, 1.0, 0.1);
  EXPECT_THAT(BuildError(j), HasSubstr("/elements/0/parameters/frequency_hz: must be >= 0"));
}

// A temporary folder with a CSV file, removed at the end of the test.
class FromFileTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = std::filesystem::temp_directory_path() /
           ("mb_from_file_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    std::filesystem::create_directories(dir_);
    std::ofstream(dir_ / "profile.csv") << "time_s,position_m,force_N\n0.1,0,1\n0.3,2,3\n0.4,-1,5\n";
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  json Diagram(const json& parameters, const json& solver = {{"type", "rk4"}, {"step", 1e-3}}) const {
    return MakeDiagram({Element("f", "from_file", parameters)}, json::array(), {"f.y"}, 0.5, 0.05, solver);
  }
  SignalLog Run(const json& parameters) const {
    return Simulator(BuildDiagram(Diagram(parameters), dir_, "test.json")).Run().log;
  }

  std::filesystem::path dir_;
};

TEST_F(FromFileTest, LinearInterpolationHoldsOutsideTheRange) {
  const auto log = Run({{"file", "profile.csv"}, {"column", "position_m"}, {"time_column", "time_s"}});
  // t = 0, 0.05, …, 0.5
  const std::vector<double> expected = {0, 0, 0, 0.5, 1.0, 1.5, 2.0, 0.5, -1.0, -1.0, -1.0};
  ASSERT_EQ(log.Column("f.y").size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) EXPECT_NEAR(log.Column("f.y")[i], expected[i], 1e-12) << i;
}

TEST_F(FromFileTest, ZeroOrderHoldKeepsTheLatestSample) {
  const auto log = Run({{"file", "profile.csv"}, {"column", "force_N"}, {"interpolation", "zoh"}});
  const std::vector<double> expected = {1, 1, 1, 1, 1, 1, 3, 3, 5, 5, 5};
  ASSERT_EQ(log.Column("f.y").size(), expected.size());
  for (std::size_t i = 0; i < expected.size(); ++i) EXPECT_EQ(log.Column("f.y")[i], expected[i]) << i;
}

TEST_F(FromFileTest, ZeroOrderHoldJumpsAreLocatedByCvode) {
  // ∫ zoh(force): 1·(0.3 − 0) + 3·(0.4 − 0.3) + 5·(0.5 − 0.4) = 1.1 at t = 0.5.
  json j = MakeDiagram({Element("f", "from_file", {{"file", "profile.csv"}, {"column", "force_N"},
                                                   {"interpolation", "zoh"}}),
                        Element("x", "integrator")},
                       {Connect("f.y", "x.u")}, {"x.y"}, 0.5, 0.25,
                       {{"type", "cvode"}, {"rtol", 1e-10}, {"atol", 1e-12}});
  const auto r = Simulator(BuildDiagram(j, dir_, "test.json")).Run();
  EXPECT_NEAR(r.log.Column("x.y").back(), 1.1, 1e-9);
  EXPECT_GE(r.solver_stats.roots_found, 2);
}

TEST_F(FromFileTest, ErrorsNameTheFileColumnAndFix) {
  EXPECT_THAT(BuildError(Diagram({{"file", "profile.csv"}, {"column", "speed"}}), dir_.string()),
              ::testing::AllOf(HasSubstr("profile.csv"), HasSubstr("speed"), HasSubstr("position_m")));
  EXPECT_THAT(BuildError(Diagram({{"file", "missing.csv"}, {"column", "x"}}), dir_.string()),
              HasSubstr("missing.csv"));
  EXPECT_THAT(BuildError(Diagram({{"file", "profile.csv"}, {"column", "force_N"}, {"interpolation", "cubic"}}),
                         dir_.string()),
              HasSubstr("interpolation must be \"linear\" or \"zoh\", got \"cubic\""));
  EXPECT_THAT(BuildError(Diagram({{"file", "profile.csv"}, {"column", "force_N"}, {"time_column", "force_N"}}),
                         dir_.string()),
              HasSubstr("time_column \"force_N\" is not the first column"));
  EXPECT_THAT(BuildError(Diagram({{"column", "force_N"}}), dir_.string()),
              HasSubstr("missing required parameter 'file'"));
}

}  // namespace
}  // namespace mb

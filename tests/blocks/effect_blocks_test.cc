// The blocks `compare --suggest` inserts for a diagnosed missing effect: transport_delay, time_periodic,
// velocity_dependent_ripple, position_dependent_force — each against its header's equation.

#include <cmath>
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

using testing::kTwoPi;

// Output at hit n = u[n − k] for a whole number of samples; the first input is held before the start.
TEST(TransportDelayTest, WholeSampleDelayOfASampledSine) {
  const double ts = 1e-3, delay = 4e-3;
  const json j = MakeDiagram({Element("s", "sine", {{"frequency_hz", 3.0}}), Element("d", "transport_delay",
                                                                                     {{"delay", delay}}, {ts, 0.0})},
                             Connect("s.y", "d.u"), {"d.y"}, 0.2, ts);
  const auto r = Simulator(Build(j)).Run();
  const auto& y = r.log.Column("d.y");
  for (std::size_t i = 0; i < y.size(); ++i) {
    const double t = r.log.time[i];
    const double expected = t < delay - 1e-12 ? 0.0 : std::sin(kTwoPi * 3.0 * (t - delay));
    EXPECT_NEAR(y[i], expected, 1e-9) << "t = " << t;
  }
}

// A fractional delay interpolates linearly between the two stored samples around t − d.
TEST(TransportDelayTest, FractionalDelayInterpolatesLinearly) {
  const double ts = 1e-3, delay = 2.5e-3;
  const json j = MakeDiagram({Element("s", "sine", {{"frequency_hz", 2.0}, {"bias", 1.0}}),
                              Element("d", "transport_delay", {{"delay", delay}}, {ts, 0.0})},
                             Connect("s.y", "d.u"), {"d.y"}, 0.1, ts);
  const auto r = Simulator(Build(j)).Run();
  const auto& y = r.log.Column("d.y");
  auto u = [](double t) { return 1.0 + std::sin(kTwoPi * 2.0 * std::max(t, 0.0)); };
  for (std::size_t i = 3; i < y.size(); ++i) {
    const double t = r.log.time[i];
    const double expected = 0.5 * u(t - 2e-3) + 0.5 * u(t - 3e-3);
    EXPECT_NEAR(y[i], expected, 1e-9) << "t = " << t;
  }
  EXPECT_NEAR(y[0], 1.0, 1e-12);  // the first sample, held
}

TEST(TransportDelayTest, NeedsASampleTimeAndANonNegativeDelay) {
  EXPECT_THAT(BuildError(MakeDiagram({Element("d", "transport_delay", {{"delay", 0.01}})}, json::array(), json::array(),
                                     0.1, 1e-3)),
              HasSubstr("sampleTime"));
  EXPECT_THAT(BuildError(MakeDiagram({Element("d", "transport_delay", {{"delay", -0.01}}, {1e-3, 0.0})}, json::array(),
                                     json::array(), 0.1, 1e-3)),
              HasSubstr("delay"));
}

TEST(TimePeriodicTest, MatchesItsFourierSeries) {
  const json j = MakeDiagram({Element("p", "time_periodic",
                                      {{"frequency_hz", 7.0}, {"harmonics", 2}, {"cos_coefficients", {0.5, -0.2}},
                                       {"sin_coefficients", {1.0, 0.1}}})},
                             json::array(), {"p.y"}, 0.5, 1e-3);
  const auto r = Simulator(Build(j)).Run();
  const auto& y = r.log.Column("p.y");
  for (std::size_t i = 0; i < y.size(); ++i) {
    const double w = kTwoPi * 7.0 * r.log.time[i];
    EXPECT_NEAR(y[i], 0.5 * std::cos(w) + std::sin(w) - 0.2 * std::cos(2 * w) + 0.1 * std::sin(2 * w), 1e-12);
  }
  EXPECT_THAT(BuildError(MakeDiagram({Element("p", "time_periodic", {{"harmonics", 2}, {"cos_coefficients", {1.0}}})},
                                     json::array(), json::array(), 0.1, 1e-3)),
              HasSubstr("cos_coefficients has 1 entries"));
}

// y = |v|·(a cos(2π(x − x₀)/P) + b sin(…)) along x = 0.01 sin(2πt): reversals at t = 0.25 s and 0.75 s.
TEST(VelocityDependentRippleTest, AmplitudeScalesWithSpeedInBothDirections) {
  const double period = 4e-3, a = 3.0, b = -2.0, x0 = 1e-3;
  const json j = MakeDiagram(
      {Element("x", "sine", {{"amplitude", 0.01}, {"frequency_hz", 1.0}}),
       Element("v", "sine", {{"amplitude", 0.01 * kTwoPi}, {"frequency_hz", 1.0}, {"phase", std::numbers::pi / 2}}),
       Element("r", "velocity_dependent_ripple",
               {{"period", period}, {"cos_coefficients", {a}}, {"sin_coefficients", {b}}, {"position_offset", x0}})},
      {Connect("x.y", "r.x"), Connect("v.y", "r.v")}, {"r.y"}, 1.0, 1e-3);
  const auto r = Simulator(Build(j)).Run();
  const auto& y = r.log.Column("r.y");
  for (std::size_t i = 0; i < y.size(); ++i) {
    const double t = r.log.time[i];
    const double x = 0.01 * std::sin(kTwoPi * t), v = 0.01 * kTwoPi * std::cos(kTwoPi * t);
    const double th = kTwoPi * (x - x0) / period;
    EXPECT_NEAR(y[i], std::abs(v) * (a * std::cos(th) + b * std::sin(th)), 1e-9) << "t = " << t;
  }
}

// f = Σ_j c_j ξ^j, ξ = (x − x₀)/h: a hardening spring k₁(x − x₀) + k₃(x − x₀)³ with c_1 = k₁h, c_3 = k₃h³.
TEST(PositionDependentForceTest, HardeningSpringAsPolynomialInTheNormalisedPosition) {
  const double x0 = 0.1, h = 0.09, k1 = 30.0, k3 = 3000.0;
  const json j = MakeDiagram(
      {Element("x", "sine", {{"amplitude", 0.08}, {"frequency_hz", 1.0}, {"bias", x0}}),
       Element("f", "position_dependent_force",
               {{"center", x0}, {"half_range", h}, {"coefficients", {k1 * h, 0.0, k3 * h * h * h}}})},
      {Connect("x.y", "f.x")}, {"f.f"}, 1.0, 1e-3);
  const auto r = Simulator(Build(j)).Run();
  const auto& f = r.log.Column("f.f");
  for (std::size_t i = 0; i < f.size(); ++i) {
    const double d = 0.08 * std::sin(kTwoPi * r.log.time[i]);
    EXPECT_NEAR(f[i], k1 * d + k3 * d * d * d, 1e-9) << "t = " << r.log.time[i];
  }
}

TEST(PositionDependentForceTest, RefusesANonPositiveHalfRange) {
  const json j = MakeDiagram({Element("x", "constant", {{"value", 0.0}}),
                              Element("f", "position_dependent_force", {{"half_range", 0.0}})},
                             {Connect("x.y", "f.x")}, {"f.f"}, 1.0, 1e-3);
  EXPECT_THAT(BuildError(j), HasSubstr("half_range"));
}

}  // namespace
}  // namespace mb

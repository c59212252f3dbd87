// The blocks `compare --suggest` inserts for a diagnosed missing effect: transport_delay, time_periodic,
// velocity_dependent_ripple, position_dependent_inertia, position_dependent_force, ramped_gain (linear and
// exponential), speed_dependent_saturation — each against its header's equation (position_dependent_inertia against
// the energy balance).

#include <algorithm>
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

// A vibration whose frequency drifts (drifting_vibration's block): φ = 2π(f t + ½ ḟ t²), its instantaneous frequency
// f + ḟ t — 3 Hz at the start, 11 Hz after 2 s at 4 Hz/s.
TEST(TimePeriodicTest, ADriftingFrequencyIntegratesItsPhase) {
  const double f0 = 3.0, rate = 4.0;
  const json j = MakeDiagram({Element("p", "time_periodic",
                                      {{"frequency_hz", f0}, {"frequency_rate", rate}, {"cos_coefficients", {0.0}},
                                       {"sin_coefficients", {2.0}}})},
                             json::array(), {"p.y"}, 2.0, 1e-3);
  const auto r = Simulator(Build(j)).Run();
  const auto& y = r.log.Column("p.y");
  for (std::size_t i = 0; i < y.size(); ++i) {
    const double t = r.log.time[i];
    EXPECT_NEAR(y[i], 2.0 * std::sin(kTwoPi * (f0 * t + 0.5 * rate * t * t)), 1e-9) << "t = " << t;
  }
  // The zero crossings in the last 0.25 s come at the drifted frequency (≈ 2 × 10.5 Hz × 0.25 s), not at 3 Hz's rate.
  int crossings = 0;
  for (std::size_t i = 1; i < y.size(); ++i) crossings += r.log.time[i] > 1.75 && (y[i - 1] < 0.0) != (y[i] < 0.0);
  EXPECT_NEAR(crossings, 2.0 * 10.5 * 0.25, 1.0);
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

// position_dependent_inertia is the force of the kinetic energy T = ½M(x)·v²: the power it takes, y·v, is the rate at
// which T changes, dT/dt (energy, not the header's formula: a wrong v² term — its sign, its ½, a harmonic's slope —
// breaks the balance wherever the axis moves).
TEST(PositionDependentInertiaTest, ItsPowerIsTheRateOfChangeOfTheKineticEnergy) {
  const double period = 0.04, x0 = 3e-3;
  const double a1 = 2.0, a2 = -0.5, b1 = 4.0, b2 = 1.0;  // [kg]
  const json j = MakeDiagram(
      {Element("x", "sine", {{"amplitude", 0.05}, {"frequency_hz", 1.0}, {"bias", 0.1}}),
       Element("v", "sine", {{"amplitude", 0.05 * kTwoPi}, {"frequency_hz", 1.0}, {"phase", std::numbers::pi / 2}}),
       Element("a", "sine",
               {{"amplitude", 0.05 * kTwoPi * kTwoPi}, {"frequency_hz", 1.0}, {"phase", std::numbers::pi}}),
       Element("m", "position_dependent_inertia",
               {{"period", period}, {"harmonics", 2}, {"cos_coefficients", {a1, a2}}, {"sin_coefficients", {b1, b2}},
                {"position_offset", x0}})},
      {Connect("x.y", "m.x"), Connect("v.y", "m.v"), Connect("a.y", "m.a")}, {"m.y"}, 1.0, 1e-3);
  const auto r = Simulator(Build(j)).Run();
  const auto& y = r.log.Column("m.y");
  const auto kinetic_energy = [&](double t) {
    const double x = 0.1 + 0.05 * std::sin(kTwoPi * t), v = 0.05 * kTwoPi * std::cos(kTwoPi * t);
    const double th = kTwoPi * (x - x0) / period;
    const double mass = a1 * std::cos(th) + b1 * std::sin(th) + a2 * std::cos(2 * th) + b2 * std::sin(2 * th);
    return 0.5 * mass * v * v;
  };
  double largest_power = 0.0;
  for (std::size_t i = 0; i < y.size(); ++i) {
    const double t = r.log.time[i], v = 0.05 * kTwoPi * std::cos(kTwoPi * t), h = 1e-6;
    const double rate = (kinetic_energy(t + h) - kinetic_energy(t - h)) / (2 * h);
    EXPECT_NEAR(y[i] * v, rate, 1e-5 * (1.0 + std::abs(rate))) << "t = " << t;
    largest_power = std::max(largest_power, std::abs(rate));
  }
  EXPECT_GT(largest_power, 1.0);  // [W]: the check had power to check
}

// inertia_table_1d, the same balance with M(x) a table: two segments of different slope and the clipped ends (M′ = 0
// beyond the breakpoints), the samples within 1e-5 m of a breakpoint left out (the slope jumps there).
TEST(InertiaTable1dTest, ItsPowerIsTheRateOfChangeOfTheKineticEnergy) {
  const std::vector<double> at = {0.07, 0.1, 0.13}, mass = {0.0, 3.0, 1.0};  // [m], [kg]
  const json j = MakeDiagram(
      {Element("x", "sine", {{"amplitude", 0.05}, {"frequency_hz", 1.0}, {"bias", 0.1}}),
       Element("v", "sine", {{"amplitude", 0.05 * kTwoPi}, {"frequency_hz", 1.0}, {"phase", std::numbers::pi / 2}}),
       Element("a", "sine",
               {{"amplitude", 0.05 * kTwoPi * kTwoPi}, {"frequency_hz", 1.0}, {"phase", std::numbers::pi}}),
       Element("m", "inertia_table_1d", {{"breakpoints", at}, {"table", mass}})},
      {Connect("x.y", "m.x"), Connect("v.y", "m.v"), Connect("a.y", "m.a")}, {"m.y"}, 1.0, 1e-3);
  const auto r = Simulator(Build(j)).Run();
  const auto& y = r.log.Column("m.y");
  const auto m_of = [&](double x) {
    if (x <= at.front()) return mass.front();
    if (x >= at.back()) return mass.back();
    const std::size_t k = x < at[1] ? 0 : 1;
    return mass[k] + (x - at[k]) / (at[k + 1] - at[k]) * (mass[k + 1] - mass[k]);
  };
  const auto position = [](double t) { return 0.1 + 0.05 * std::sin(kTwoPi * t); };
  const auto kinetic_energy = [&](double t) {
    const double v = 0.05 * kTwoPi * std::cos(kTwoPi * t);
    return 0.5 * m_of(position(t)) * v * v;
  };
  double largest_power = 0.0;
  int checked = 0;
  for (std::size_t i = 0; i < y.size(); ++i) {
    const double t = r.log.time[i], v = 0.05 * kTwoPi * std::cos(kTwoPi * t), h = 1e-7;
    if (std::any_of(at.begin(), at.end(), [&](double b) { return std::abs(position(t) - b) < 1e-5; })) continue;
    const double rate = (kinetic_energy(t + h) - kinetic_energy(t - h)) / (2 * h);
    EXPECT_NEAR(y[i] * v, rate, 1e-5 * (1.0 + std::abs(rate))) << "t = " << t;
    largest_power = std::max(largest_power, std::abs(rate));
    ++checked;
  }
  EXPECT_GT(checked, 900);
  EXPECT_GT(largest_power, 0.5);  // [W]: the check had power to check
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

// ramped_gain, shape "exponential": 0 before start_time, gain·(1 − exp(−(t − start_time)/T))·u after (a warm-up).
TEST(RampedGainTest, ExponentialShapeSettlesWithItsTimeConstant) {
  const double gain = -46.0, start = 0.2, T = 0.35;
  const json j = MakeDiagram({Element("u", "constant", {{"value", 0.15}}),
                              Element("g", "ramped_gain", {{"gain", gain}, {"start_time", start}, {"shape", "exponential"},
                                                           {"time_constant", T}})},
                             {Connect("u.y", "g.u")}, {"g.y"}, 2.0, 0.05);
  const auto r = Simulator(Build(j)).Run();
  const auto& y = r.log.Column("g.y");
  ASSERT_EQ(y.size(), 41u);
  for (std::size_t i = 0; i < y.size(); ++i) {
    const double t = r.log.time[i];
    EXPECT_NEAR(y[i], t < start ? 0.0 : gain * 0.15 * (1.0 - std::exp(-(t - start) / T)), 1e-12) << "t = " << t;
  }
  EXPECT_NEAR(y[11], gain * 0.15 * (1.0 - std::exp(-1.0)), 1e-12);  // t = start + T: 63 % of the change
}

TEST(RampedGainTest, LinearShapeIsTheDefaultAndEachShapeChecksItsTimes) {
  const json linear = MakeDiagram({Element("u", "constant", {{"value", 2.0}}),
                                   Element("g", "ramped_gain", {{"gain", 3.0}, {"start_time", 0.5}, {"end_time", 1.5}})},
                                  {Connect("u.y", "g.u")}, {"g.y"}, 2.0, 0.25);
  const auto r = Simulator(Build(linear)).Run();
  const auto& y = r.log.Column("g.y");
  for (std::size_t i = 0; i < y.size(); ++i) {
    EXPECT_NEAR(y[i], 6.0 * std::clamp(r.log.time[i] - 0.5, 0.0, 1.0), 1e-12) << "t = " << r.log.time[i];
  }
  // The exponential needs no end_time after its start, the ramp no time constant; each refuses its own bad value.
  const auto with = [](json parameters) {
    return MakeDiagram({Element("u", "constant", {{"value", 1.0}}), Element("g", "ramped_gain", std::move(parameters))},
                       {Connect("u.y", "g.u")}, {"g.y"}, 1.0, 0.5);
  };
  EXPECT_NO_THROW(Build(with({{"shape", "exponential"}, {"start_time", 2.0}, {"end_time", 1.0}})));
  EXPECT_THAT(BuildError(with({{"shape", "exponential"}, {"time_constant", 0.0}})),
              HasSubstr("shape \"exponential\" needs time_constant > 0 s"));
  EXPECT_THAT(BuildError(with({{"start_time", 2.0}, {"end_time", 1.0}})), HasSubstr("end_time 1 s must lie after"));
}

// speed_dependent_saturation: y = clamp(u, lower − k·v, upper − k·v) — the limit falls with the speed while the drive
// pushes in the direction of motion and rises while it brakes.
TEST(SpeedDependentSaturationTest, LimitsFallWithSpeedInTheDirectionOfMotion) {
  const double upper = 150.0, lower = -150.0, k = 225.0;
  const json j = MakeDiagram(
      {Element("u", "sine", {{"amplitude", 200.0}, {"frequency_hz", 1.0}}),
       Element("v", "sine", {{"amplitude", 0.2}, {"frequency_hz", 0.5}, {"phase", 0.3}}),
       Element("s", "speed_dependent_saturation", {{"upper", upper}, {"lower", lower}, {"speed_slope", k}})},
      {Connect("u.y", "s.u"), Connect("v.y", "s.v")}, {"s.y", "u.y", "v.y"}, 2.0, 1e-3);
  const auto r = Simulator(Build(j)).Run();
  const auto& y = r.log.Column("s.y");
  const auto& u = r.log.Column("u.y");
  const auto& v = r.log.Column("v.y");
  int limited_fast = 0;
  for (std::size_t i = 0; i < y.size(); ++i) {
    EXPECT_NEAR(y[i], std::clamp(u[i], lower - k * v[i], upper - k * v[i]), 1e-12) << "t = " << r.log.time[i];
    if (v[i] > 0.1 && u[i] > upper - k * v[i]) ++limited_fast;
  }
  EXPECT_GT(limited_fast, 0);  // the test passes through the speed-dependent part
  // At v = 0.2 m/s forward: pushing forward is limited to 150 − 45 = 105, braking to −150 − 45 = −195.
  const json at_speed = MakeDiagram(
      {Element("u", "constant", {{"value", 400.0}}), Element("w", "constant", {{"value", -400.0}}),
       Element("v", "constant", {{"value", 0.2}}),
       Element("p", "speed_dependent_saturation", {{"upper", upper}, {"lower", lower}, {"speed_slope", k}}),
       Element("b", "speed_dependent_saturation", {{"upper", upper}, {"lower", lower}, {"speed_slope", k}})},
      {Connect("u.y", "p.u"), Connect("v.y", "p.v"), Connect("w.y", "b.u"), Connect("v.y", "b.v")}, {"p.y", "b.y"},
      0.1, 0.1);
  const auto s = Simulator(Build(at_speed)).Run();
  EXPECT_NEAR(s.log.Column("p.y").front(), 105.0, 1e-12);
  EXPECT_NEAR(s.log.Column("b.y").front(), -195.0, 1e-12);
}

TEST(SpeedDependentSaturationTest, RefusesLimitsInTheWrongOrderAndANegativeSlope) {
  const auto with = [](json parameters) {
    return MakeDiagram({Element("u", "constant", {{"value", 1.0}}), Element("v", "constant", {{"value", 0.0}}),
                        Element("s", "speed_dependent_saturation", std::move(parameters))},
                       {Connect("u.y", "s.u"), Connect("v.y", "s.v")}, {"s.y"}, 1.0, 0.5);
  };
  EXPECT_THAT(BuildError(with({{"lower", 2.0}, {"upper", 1.0}})), HasSubstr("lower limit 2 is above upper limit 1"));
  EXPECT_THAT(BuildError(with({{"speed_slope", -1.0}})), HasSubstr("speed_slope"));
}

}  // namespace
}  // namespace mb

// Motion blocks: rigid_body (closed forms), pd_controller (continuous closed loop against the known
// second-order response, discrete forms against their recursions, errors) and friction (stick below the
// breakaway force, slide above it, reversals located at the velocity's zero crossings) and position_periodic
// (closed form with a position reference, coefficient-length errors).

#include <algorithm>
#include <cmath>
#include <functional>
#include <numbers>
#include <vector>

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

const json kCvode = {{"type", "cvode"}, {"rtol", 1e-10}, {"atol", 1e-12}};

TEST(RigidBodyTest, ConstantForceWithoutDamping) {
  const double M = 2.0, f = 3.0, x0 = 0.1, v0 = -0.4;
  const json j = MakeDiagram({Element("f", "constant", {{"value", f}}),
                              Element("body", "rigid_body", {{"mass", M}, {"x0", x0}, {"v0", v0}})},
                             {Connect("f.y", "body.f")}, {"body.x", "body.v"}, 1.0, 0.1);
  const auto r = Simulator(Build(j)).Run();
  for (std::size_t i = 0; i < r.log.time.size(); ++i) {
    const double t = r.log.time[i];
    EXPECT_NEAR(r.log.Column("body.x")[i], x0 + v0 * t + 0.5 * f / M * t * t, 1e-12);
    EXPECT_NEAR(r.log.Column("body.v")[i], v0 + f / M * t, 1e-12);
  }
}

TEST(RigidBodyTest, ConstantForceWithDampingReachesTerminalVelocity) {
  const double M = 0.2621, B = 3.0, f = 1.5, tau = M / B;
  const json j = MakeDiagram({Element("f", "constant", {{"value", f}}),
                              Element("body", "rigid_body", {{"mass", M}, {"damping", B}})},
                             {Connect("f.y", "body.f")}, {"body.x", "body.v"}, 0.5, 0.01, kCvode);
  const auto r = Simulator(Build(j)).Run();
  for (std::size_t i = 0; i < r.log.time.size(); ++i) {
    const double t = r.log.time[i], e = std::exp(-t / tau);
    EXPECT_NEAR(r.log.Column("body.v")[i], f / B * (1.0 - e), 1e-9);
    EXPECT_NEAR(r.log.Column("body.x")[i], f / B * (t - tau * (1.0 - e)), 1e-9);
  }
}

// With mass_input, (M + ΔM)·ẍ = f: a constant force on a body whose added mass steps from 0 to 3 kg at 0.5 s.
TEST(RigidBodyTest, AnAddedMassDividesTheForce) {
  const double M = 2.0, dm = 3.0, f = 3.0, t_c = 0.5;
  const json j = MakeDiagram({Element("f", "constant", {{"value", f}}),
                              Element("dm", "step", {{"time", t_c}, {"initial", 0.0}, {"final", dm}}),
                              Element("body", "rigid_body", {{"mass", M}, {"mass_input", true}})},
                             {Connect("f.y", "body.f"), Connect("dm.y", "body.added_mass")}, {"body.v"}, 1.0, 0.1,
                             kCvode);
  const auto r = Simulator(Build(j)).Run();
  for (std::size_t i = 0; i < r.log.time.size(); ++i) {
    const double t = r.log.time[i];
    const double v = t <= t_c ? f / M * t : f / M * t_c + f / (M + dm) * (t - t_c);
    EXPECT_NEAR(r.log.Column("body.v")[i], v, 1e-8) << "t = " << t;
  }
}

// A mass that varies along the travel, the plant taking M(x) on its mass input and position_dependent_inertia without
// its acceleration input giving −½M′(x)·v² as the force: no force from outside, so the kinetic energy ½(M + M(x))·v²
// stays (Lagrange). Either part alone, or a wrong sign or ½, breaks it where the mass changes.
TEST(RigidBodyTest, AScheduledMassWithItsKineticForceKeepsTheEnergy) {
  const double M = 5.0, v0 = 0.5, period = 0.1;
  const json j = MakeDiagram({Element("body", "rigid_body", {{"mass", M}, {"mass_input", true}, {"v0", v0}}),
                              Element("m", "position_dependent_inertia",
                                      {{"period", period}, {"harmonics", 2}, {"cos_coefficients", {3.0, 0.5}},
                                       {"sin_coefficients", {-1.0, 0.0}}, {"acceleration_input", false}}),
                              Element("load", "gain", {{"gain", -1.0}})},
                             {Connect("body.x", "m.x"), Connect("body.v", "m.v"), Connect("m.mass", "body.added_mass"),
                              Connect("m.y", "load.u"), Connect("load.y", "body.f")},
                             {"body.x", "body.v", "m.mass"}, 1.0, 1e-3, kCvode);
  const auto r = Simulator(Build(j)).Run();
  const double energy = 0.5 * (M + 3.5) * v0 * v0;  // M(0) = 3 + 0.5
  double fastest = v0;
  for (std::size_t i = 0; i < r.log.time.size(); ++i) {
    const double v = r.log.Column("body.v")[i];
    EXPECT_NEAR(0.5 * (M + r.log.Column("m.mass")[i]) * v * v, energy, 1e-6 * energy) << "t = " << r.log.time[i];
    fastest = std::max(fastest, v);
  }
  EXPECT_GT(r.log.Column("body.x").back(), 2.0 * period);  // the body crossed the mass's variation twice
  EXPECT_GT(fastest, 1.5 * v0);  // and the mass changed its speed: the check had power
}

TEST(RigidBodyTest, RejectsNonPositiveMassAndNegativeDamping) {
  auto body = [](const json& parameters) {
    return BuildError(MakeDiagram({Element("body", "rigid_body", parameters)}, json::array(), json::array(), 1, 0.1));
  };
  EXPECT_THAT(body({{"mass", 0.0}}), HasSubstr("rigid_body 'body': mass must be a positive, finite number of kg"));
  EXPECT_THAT(body({{"damping", -1.0}}), HasSubstr("/elements/0/parameters/damping: must be >= 0"));
}

// PD position loop on the paper's nominal plant (M_n = 0.2621 kg, B_n = 3 N·s/m): x/r = (K_d s + K_p)/(M s² +
// (B + K_d) s + K_p) for T_f → 0. Step response y = 1 + e^{−σt}(−cos ω_d t + C sin ω_d t) with
// σ = (B + K_d)/2M, ω_d = sqrt(K_p/M − σ²), and C from the initial slope y'(0+) = K_d/M: C = (K_d/M − σ)/ω_d.
TEST(PdControllerTest, ClosedLoopStepMatchesSecondOrderResponse) {
  const double M = 0.2621, B = 3.0, wn = 50.0, zeta = 0.7, r0 = 1e-3;
  const double kp = M * wn * wn, kd = 2.0 * zeta * wn * M - B, tf = 1e-6;
  const json j = MakeDiagram(
      {Element("r", "step", {{"time", 0.0}, {"final", r0}}), Element("e", "sum", {{"signs", "+-"}}),
       Element("pd", "pd_controller", {{"kp", kp}, {"kd", kd}, {"derivative_filter", tf}}),
       Element("body", "rigid_body", {{"mass", M}, {"damping", B}})},
      {Connect("r.y", "e.u1"), Connect("body.x", "e.u2"), Connect("e.y", "pd.e"), Connect("pd.u", "body.f")},
      {"body.x"}, 0.3, 0.005, {{"type", "cvode"}, {"rtol", 1e-8}, {"atol", 1e-12}});
  const auto r = Simulator(Build(j)).Run();
  const double sigma = (B + kd) / (2.0 * M), wd = std::sqrt(kp / M - sigma * sigma), C = (kd / M - sigma) / wd;
  double worst = 0.0;
  for (std::size_t i = 1; i < r.log.time.size(); ++i) {
    const double t = r.log.time[i];
    const double y = 1.0 + std::exp(-sigma * t) * (-std::cos(wd * t) + C * std::sin(wd * t));
    worst = std::max(worst, std::abs(r.log.Column("body.x")[i] / r0 - y));
  }
  // The derivative filter delays the derivative kick by ~T_f: a relative error of order K_d·T_f/M·ω_n.
  EXPECT_LT(worst, 1e-4);
}

// e = 1 from t = 0 on: d[0] = b, d[k] = a·d[k−1]; u[k] = K_p + d[k].
TEST(PdControllerTest, DiscreteFormsFollowTheirRecursions) {
  const double kp = 2.0, kd = 0.05, tf = 0.01, Ts = 0.005;
  struct Case {
    const char* method;
    double a, b;
  };
  for (const Case& c : {Case{"backward_euler", tf / (tf + Ts), kd / (tf + Ts)},
                        Case{"tustin", (2 * tf - Ts) / (2 * tf + Ts), 2 * kd / (2 * tf + Ts)}}) {
    const json j = MakeDiagram(
        {Element("e", "constant", {{"value", 1.0}}),
         Element("pd", "pd_controller", {{"kp", kp}, {"kd", kd}, {"derivative_filter", tf}, {"method", c.method}},
                 {Ts, 0.0})},
        {Connect("e.y", "pd.e")}, {"pd.u"}, 0.05, Ts);
    const auto r = Simulator(Build(j)).Run();
    double d = c.b;
    for (std::size_t k = 0; k < r.log.time.size(); ++k) {
      EXPECT_NEAR(r.log.Column("pd.u")[k], kp + d, 1e-12) << c.method << " k = " << k;
      d *= c.a;
    }
  }
}

TEST(PdControllerTest, BackwardEulerWithoutFilterIsABackwardDifference) {
  const double kd = 0.5, Ts = 0.01;
  // e = t (ramp) sampled at hits: u[k] = K_d (e[k] − e[k−1])/Ts = K_d for k ≥ 1, and 0 at k = 0 (e[0] = 0).
  const json j = MakeDiagram(
      {Element("one", "constant", {{"value", 1.0}}), Element("t", "integrator"),
       Element("pd", "pd_controller", {{"kd", kd}, {"derivative_filter", 0.0}}, {Ts, 0.0})},
      {Connect("one.y", "t.u"), Connect("t.y", "pd.e")}, {"pd.u"}, 0.1, Ts);
  const auto r = Simulator(Build(j)).Run();
  EXPECT_NEAR(r.log.Column("pd.u")[0], 0.0, 1e-12);
  for (std::size_t k = 1; k < r.log.time.size(); ++k) EXPECT_NEAR(r.log.Column("pd.u")[k], kd, 1e-9) << k;
}

TEST(PdControllerTest, ErrorsForImproperOrUnknownForms) {
  auto pd = [](const json& parameters, const json& sample_time = nullptr) {
    return BuildError(MakeDiagram({Element("pd", "pd_controller", parameters, sample_time)}, json::array(),
                                  json::array(), 1, 0.1));
  };
  EXPECT_THAT(pd({{"kd", 1.0}, {"derivative_filter", 0.0}}),
              HasSubstr("the continuous pd_controller needs derivative_filter > 0 s"));
  EXPECT_THAT(pd({{"method", "tustin"}, {"derivative_filter", 0.0}}, 0.001),
              HasSubstr("method \"tustin\" needs derivative_filter > 0 s"));
  EXPECT_THAT(pd({{"method", "tustin"}}), HasSubstr("give a sampleTime"));
  EXPECT_THAT(pd({{"method", "zoh"}}, 0.001), HasSubstr("method must be \"backward_euler\" or \"tustin\""));
  EXPECT_THAT(pd({{"derivative_filter", -1.0}}), HasSubstr("derivative_filter: must be >= 0"));
}

// A mass M with friction, pushed by a force source `force` (an element with output y):
// M·ẍ = f − F(v, f).
json FrictionDiagram(const json& force, const json& friction, double M, double stop, double step) {
  return MakeDiagram({force, Element("fr", "friction", friction), Element("net", "sum", {{"signs", "+-"}}),
                      Element("body", "rigid_body", {{"mass", M}})},
                     {Connect("force.y", "net.u1"), Connect("force.y", "fr.f_applied"), Connect("fr.f", "net.u2"),
                      Connect("net.y", "body.f"), Connect("body.v", "fr.v")},
                     {"body.x", "body.v", "fr.f"}, stop, step, kCvode);
}

TEST(FrictionTest, ForceBelowBreakawayLeavesTheMassAtRest) {
  const json friction = {{"coulomb", 1.0}, {"static", 1.5}, {"viscous", 0.2}};
  const auto r = Simulator(Build(FrictionDiagram(Element("force", "sine", {{"amplitude", 1.4}, {"frequency_hz", 2.0}}),
                                                 friction, 1.0, 1.0, 0.01)))
                     .Run();
  for (std::size_t i = 0; i < r.log.time.size(); ++i) {
    EXPECT_EQ(r.log.Column("body.x")[i], 0.0) << "t = " << r.log.time[i];
    EXPECT_EQ(r.log.Column("body.v")[i], 0.0);
    EXPECT_NEAR(r.log.Column("fr.f")[i], 1.4 * std::sin(4.0 * std::numbers::pi * r.log.time[i]), 1e-12);
  }
}

TEST(FrictionTest, ForceAboveBreakawaySlidesWithTheAnalyticAcceleration) {
  const double M = 0.5, f = 2.0, Fc = 1.0, Fs = 1.5;
  const auto r = Simulator(Build(FrictionDiagram(Element("force", "constant", {{"value", -f}}),
                                                 {{"coulomb", Fc}, {"static", Fs}}, M, 1.0, 0.1)))
                     .Run();
  const double a = (-f + Fc) / M;
  for (std::size_t i = 0; i < r.log.time.size(); ++i) {
    const double t = r.log.time[i];
    EXPECT_NEAR(r.log.Column("body.x")[i], 0.5 * a * t * t, 1e-9) << "t = " << t;
    EXPECT_NEAR(r.log.Column("fr.f")[i], -Fc, 1e-12);
  }
}

// Reference for a mass driven by f = A sin(ωt) against Coulomb friction F_c with breakaway F_s: piecewise
// closed forms between events, the events (zero velocity, breakaway) found by bisection to 1e-14 s.
struct CoulombReference {
  double M, A, w, Fc, Fs;

  // Velocity at t in a slip phase started at rest at t0 in direction s.
  double SlipVelocity(double t0, double s, double t) const {
    return (A / w * (std::cos(w * t0) - std::cos(w * t)) - s * Fc * (t - t0)) / M;
  }
  double SlipPosition(double x0, double t0, double s, double t) const {
    const double dt = t - t0;
    return x0 + (A / w * std::cos(w * t0) * dt - A / (w * w) * (std::sin(w * t) - std::sin(w * t0)) -
                 0.5 * s * Fc * dt * dt) / M;
  }
  // First t in (t0, t1] where g changes sign from its sign just after t0, or t1 + 1 if none.
  static double FirstRoot(const std::function<double(double)>& g, double t0, double t1) {
    const double dt = 1e-4;
    double lo = t0 + 1e-9;
    const bool positive = g(lo) > 0.0;
    for (double hi = lo + dt; hi <= t1 + dt; hi += dt) {
      if ((g(hi) > 0.0) != positive) {
        for (int it = 0; it < 100 && hi - lo > 1e-14; ++it) {
          const double mid = 0.5 * (lo + hi);
          ((g(mid) > 0.0) == positive ? lo : hi) = mid;
        }
        return hi;
      }
      lo = hi;
    }
    return t1 + 1.0;
  }
  // Mode (−1, 0, +1), velocity and position at each of `times`, and the event times.
  void Evaluate(const std::vector<double>& times, std::vector<int>* mode, std::vector<double>* v,
                std::vector<double>* x, std::vector<double>* events) const {
    double t0 = 0.0, x0 = 0.0;
    int s = 0;
    const double t_end = times.back();
    std::size_t i = 0;
    while (i < times.size()) {
      double t1;
      if (s == 0) {
        t1 = FirstRoot([&](double t) { return std::abs(A * std::sin(w * t)) - Fs; }, t0, t_end);
      } else {
        t1 = FirstRoot([&](double t) { return SlipVelocity(t0, s, t); }, t0, t_end);
      }
      for (; i < times.size() && times[i] < t1; ++i) {
        mode->push_back(s);
        v->push_back(s == 0 ? 0.0 : SlipVelocity(t0, s, times[i]));
        x->push_back(s == 0 ? x0 : SlipPosition(x0, t0, s, times[i]));
      }
      if (t1 > t_end) break;
      events->push_back(t1);
      if (s != 0) x0 = SlipPosition(x0, t0, s, t1);
      const double f = A * std::sin(w * t1);
      s = std::abs(f) <= Fs && s != 0 ? 0 : (f > 0.0 ? 1 : -1);
      t0 = t1;
    }
  }
};

TEST(FrictionTest, SineDrivenMassReversesAtTheVelocityZeroCrossings) {
  const CoulombReference ref{0.5, 3.0, 2.0 * std::numbers::pi, 1.0, 1.2};
  const double stop = 2.0;
  const auto r = Simulator(Build(FrictionDiagram(Element("force", "sine", {{"amplitude", ref.A}, {"frequency_hz", 1.0}}),
                                                 {{"coulomb", ref.Fc}, {"static", ref.Fs}}, ref.M, stop, 0.002)))
                     .Run();
  std::vector<int> mode;
  std::vector<double> v, x, events;
  ref.Evaluate(r.log.time, &mode, &v, &x, &events);
  ASSERT_EQ(mode.size(), r.log.time.size());
  // The motion reverses (both directions occur) and sticks in between when |f| < F_s at v = 0.
  EXPECT_GE(events.size(), 4u);
  EXPECT_NE(std::find(mode.begin(), mode.end(), 1), mode.end());
  EXPECT_NE(std::find(mode.begin(), mode.end(), -1), mode.end());
  for (std::size_t i = 0; i < r.log.time.size(); ++i) {
    const double t = r.log.time[i];
    double nearest = 1.0;
    for (double e : events) nearest = std::min(nearest, std::abs(t - e));
    if (nearest < 1e-6) continue;  // log point within the located event's tolerance: either side is right
    // The friction output shows the mode: ±F_c while slipping, the applied force while stuck.
    const double expected_f = mode[i] == 0 ? ref.A * std::sin(ref.w * t) : mode[i] * ref.Fc;
    EXPECT_NEAR(r.log.Column("fr.f")[i], expected_f, 1e-9) << "t = " << t;
    // A late or early switch of δ seconds would show as a velocity error of 2·F_c·δ/M.
    EXPECT_NEAR(r.log.Column("body.v")[i], v[i], 1e-6) << "t = " << t;
    EXPECT_NEAR(r.log.Column("body.x")[i], x[i], 1e-6) << "t = " << t;
  }
}

TEST(FrictionTest, ParameterErrors) {
  auto fr = [](const json& parameters) {
    return BuildError(MakeDiagram({Element("fr", "friction", parameters)}, json::array(), json::array(), 1, 0.1));
  };
  EXPECT_THAT(fr({{"coulomb", 2.0}, {"static", 1.0}}),
              HasSubstr("friction 'fr': static (breakaway) force 1.000000 N is below the Coulomb force 2.000000 N"));
  EXPECT_THAT(fr({{"stick_model", "lugre"}}), HasSubstr("stick_model must be \"karnopp\""));
  EXPECT_THAT(fr({{"viscous", -0.1}}), HasSubstr("/elements/0/parameters/viscous: must be >= 0"));
}

// regularization "tanh": F = tanh(v/v_reg)·(F_c + (F_s − F_c)e^{−(v/v_s)²}) + σv at every instant, no events.
TEST(FrictionTest, TanhRegularizationIsTheSmoothLawWithoutModes) {
  const double sigma = 0.2, Fc = 1.0, Fs = 1.5, vs = 0.005, vreg = 1e-3;
  const json j = MakeDiagram(
      {Element("v", "sine", {{"amplitude", 0.01}, {"frequency_hz", 1.0}}),
       Element("fr", "friction",
               {{"viscous", sigma}, {"coulomb", Fc}, {"static", Fs}, {"stribeck_velocity", vs},
                {"stick_model", "none"}, {"regularization", "tanh"}, {"regularization_velocity", vreg}})},
      {Connect("v.y", "fr.v")}, {"fr.f"}, 1.0, 1e-3);
  const auto r = Simulator(Build(j)).Run();
  for (std::size_t i = 0; i < r.log.time.size(); ++i) {
    const double v = 0.01 * std::sin(2.0 * std::numbers::pi * r.log.time[i]);
    const double expected = std::tanh(v / vreg) * (Fc + (Fs - Fc) * std::exp(-(v / vs) * (v / vs))) + sigma * v;
    EXPECT_NEAR(r.log.Column("fr.f")[i], expected, 1e-12) << "t = " << r.log.time[i];
  }
}

TEST(FrictionTest, TanhRegularizationNeedsNoStickAndAPositiveVelocity) {
  auto fr = [](const json& parameters) {
    return BuildError(MakeDiagram({Element("fr", "friction", parameters)}, json::array(), json::array(), 1, 0.1));
  };
  EXPECT_THAT(fr({{"regularization", "tanh"}}),
              HasSubstr("regularization \"tanh\" is a smooth law without stiction: set stick_model to \"none\""));
  EXPECT_THAT(fr({{"regularization", "tanh"}, {"stick_model", "none"}, {"regularization_velocity", 0.0}}),
              HasSubstr("regularization_velocity must be > 0 m/s with regularization \"tanh\", got 0"));
}

TEST(PositionPeriodicTest, MatchesTheFourierSeriesAboutItsPositionReference) {
  // x ramps at 0.01 m/s through several periods; y = Σ a_h cos(2πh(x − x₀)/P) + b_h sin(2πh(x − x₀)/P).
  const double P = 2.5e-3, x0 = 0.7e-3, v = 0.01;
  const std::vector<double> a = {0.02, -0.1, 0.12}, b = {0.86, -0.24, 0.1};
  const json j = MakeDiagram({Element("v", "constant", {{"value", v}}), Element("x", "integrator"),
                              Element("ripple", "position_periodic",
                                      {{"period", P}, {"harmonics", 3}, {"cos_coefficients", a},
                                       {"sin_coefficients", b}, {"position_offset", x0}})},
                             {Connect("v.y", "x.u"), Connect("x.y", "ripple.x")}, {"x.y", "ripple.y"}, 1.0, 0.01);
  const auto r = Simulator(Build(j)).Run();
  const auto& x = r.log.Column("x.y");
  const auto& y = r.log.Column("ripple.y");
  for (std::size_t i = 0; i < y.size(); ++i) {
    double expected = 0.0;
    for (int h = 1; h <= 3; ++h) {
      const double theta = 2.0 * std::numbers::pi * h * (x[i] - x0) / P;
      expected += a[static_cast<std::size_t>(h - 1)] * std::cos(theta) + b[static_cast<std::size_t>(h - 1)] * std::sin(theta);
    }
    EXPECT_NEAR(y[i], expected, 1e-12) << "x = " << x[i];
  }
}

TEST(PositionPeriodicTest, CoefficientVectorsMustHaveOneEntryPerHarmonic) {
  const json j = MakeDiagram({Element("x", "constant"),
                              Element("ripple", "position_periodic",
                                      {{"harmonics", 3}, {"cos_coefficients", {1.0, 2.0}}})},
                             {Connect("x.y", "ripple.x")}, {"ripple.y"}, 0.1, 0.1);
  EXPECT_THAT(BuildError(j), HasSubstr("cos_coefficients has 2 entries; give one per harmonic (3) or []"));
}

}  // namespace
}  // namespace mb

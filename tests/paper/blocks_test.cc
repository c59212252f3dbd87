// The paper's blocks: DOB recovery of constant and slow disturbances, strict causality of the DOB and F_gp,
// the Fig. 9 profile, the training scan, the linear-motor twin (quantisation, payload, cogging), and the
// validation errors users can trigger.

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "models/physics/cogging.h"
#include "tests/paper/paper_util.h"

namespace mb {
namespace {

using nlohmann::json;
using paper_testing::Connect;
using paper_testing::LoopWithInputs;
using paper_testing::RigidPlant;
using paper_testing::Series;
using paper_testing::kPi;

Diagram Build(const json& j) { return BuildDiagram(j, ".", "test.json"); }

SimulationResult RunHolding(const json& j, const InputSeries& d, double stop) {
  const Diagram diagram = Build(j);
  Simulator sim(diagram);
  const auto zero = Series([](double) { return 0.0; }, stop, 0.01);
  sim.SetInput("x_d", zero);
  sim.SetInput("v_d", zero);
  sim.SetInput("a_d", zero);
  sim.SetInput("d", d);
  return sim.Run();
}

TEST(DobTest, RecoversConstantInputDisturbance) {
  const double d0 = 0.8, stop = 1.0;
  const auto r = RunHolding(LoopWithInputs(RigidPlant(), 30.0, 16000.0, 90.0, stop, 1e-3),
                            Series([&](double) { return d0; }, stop, 0.01), stop);
  const auto& dhat = r.log.Column("dob.d_hat");
  // Sign convention: x = P(u_c + d) and u_c contains −d̂_d, so d̂_d → d.
  EXPECT_NEAR(dhat.back(), d0, 0.01 * d0);
  EXPECT_NEAR(r.log.Column("plant.x").back(), 0.0, 1e-9);  // the DOB removed the offset
}

TEST(DobTest, RecoversSlowSinusoidalInputDisturbance) {
  // With P = P_n, G_d→d̂ = Q (eq. 12); at 0.1 Hz and f_q = 60 Hz, |1 − Q| ≈ 2f/f_q = 0.3 %.
  const double amp = 0.5, f = 0.1, stop = 12.0;
  const auto r = RunHolding(LoopWithInputs(RigidPlant(), 60.0, 16000.0, 90.0, stop, 1e-3),
                            Series([&](double t) { return amp * std::sin(2.0 * kPi * f * t); }, stop, 1e-3), stop);
  const auto& dhat = r.log.Column("dob.d_hat");
  double worst = 0.0;
  for (std::size_t i = 0; i < r.log.time.size(); ++i) {
    if (r.log.time[i] < 2.0) continue;
    worst = std::max(worst, std::abs(dhat[i] - amp * std::sin(2.0 * kPi * f * r.log.time[i])));
  }
  EXPECT_LT(worst, 0.01 * amp);
}

TEST(DobTest, CommandDoesNotFeedThroughSoTheLoopIsNotAlgebraic) {
  const Diagram d = Build(LoopWithInputs(RigidPlant(), 30.0, 16000.0, 90.0, 0.01));
  const Block& dob = *d.blocks()[static_cast<std::size_t>(d.FindBlock("dob"))];
  EXPECT_TRUE(dob.input_ports()[0].direct_feedthrough);   // x
  EXPECT_FALSE(dob.input_ports()[1].direct_feedthrough);  // u_c
}

json SingleBlock(const json& element, double stop = 0.01) {
  return {{"schemaVersion", "1.0"},
          {"defaultExperiment", {{"stopTime", stop}, {"stepSize", 0.001}}},
          {"connectors", {{{"name", "in"}, {"kind", "input"}}}},
          {"elements", {element}},
          {"connections", {paper_testing::FromInput("in", element["name"].get<std::string>() + ".u")}},
          {"log", {element["name"].get<std::string>() + ".y"}}};
}

TEST(QFilterTest, ZohFormIsStrictlyProperAndMatchesItsDifferenceEquation) {
  json j = SingleBlock({{"name", "q"}, {"type", "q_filter"}, {"sampleTime", {0.001, 0.0}},
                        {"parameters", {{"cutoff_hz", 20.0}, {"relative_degree", 1}}}});
  const Diagram d = Build(j);
  EXPECT_FALSE(d.blocks()[0]->input_ports()[0].direct_feedthrough);
  Simulator sim(d);
  sim.SetInput("in", {{0.0, 1.0}, {1.0, 1.0}});
  const auto r = sim.Run();
  const double a = std::exp(-2.0 * kPi * 20.0 * 0.001);
  double y = 0.0;
  for (std::size_t k = 0; k < r.log.time.size(); ++k) {
    EXPECT_NEAR(r.log.Column("q.y")[k], y, 1e-12) << k;
    y = a * y + (1.0 - a) * 1.0;
  }
}

TEST(QFilterTest, ContinuousFormFollowsFirstOrderStep) {
  json j = SingleBlock({{"name", "q"}, {"type", "q_filter"}, {"parameters", {{"cutoff_hz", 5.0}, {"relative_degree", 1}}}},
                       0.1);
  j["solver"] = {{"type", "rk4"}, {"step", 1e-4}};
  const Diagram d = Build(j);
  Simulator sim(d);
  sim.SetInput("in", {{0.0, 1.0}, {1.0, 1.0}});
  const auto r = sim.Run();
  EXPECT_NEAR(r.log.Column("q.y").back(), 1.0 - std::exp(-2.0 * kPi * 5.0 * 0.1), 1e-9);
}

TEST(FGpTest, WeightedStrictlyProperLowPass) {
  json j = SingleBlock({{"name", "g"}, {"type", "f_gp"}, {"sampleTime", {0.001, 0.0}},
                        {"parameters", {{"weight", 0.5}, {"cutoff_hz", 50.0}}}});
  j["connections"][0]["endConnector"] = "mu";
  j["log"] = {"g.d_hat_g"};
  const Diagram d = Build(j);
  EXPECT_FALSE(d.blocks()[0]->input_ports()[0].direct_feedthrough);
  Simulator sim(d);
  sim.SetInput("in", {{0.0, 1.0}, {2.0, 2.0}});
  const auto r = sim.Run();
  const auto& y = r.log.Column("g.d_hat_g");
  EXPECT_EQ(y[0], 0.0);  // μ(0) enters only at the next sample
  const double a = std::exp(-2.0 * kPi * 50.0 * 0.001);
  EXPECT_NEAR(y[1], (1.0 - a) * 0.5 * 2.0, 1e-12);

  json bad = j;
  bad["elements"][0]["parameters"]["weight"] = 1.0;
  try {
    Build(bad);
    FAIL() << "α = 1 must be rejected";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("weight"), std::string::npos) << e.what();
  }
}

TEST(DobTest, UnknownDiscretizationIsReportedWithTheBlockName) {
  json j = LoopWithInputs(RigidPlant(), 30.0, 16000.0, 90.0, 0.01);
  j["elements"][6]["parameters"]["discretization"] = "bilinear";
  try {
    Build(j);
    FAIL() << "expected an error";
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("dob/discretization: discretization 'bilinear' is unknown"),
              std::string::npos)
        << e.what();
  }
}

TEST(TrajectoryTest, Figure9ProfileReaches600mmWithTheStatedVelocities) {
  const json j = {{"schemaVersion", "1.0"},
                  {"defaultExperiment", {{"stopTime", 3.0}, {"stepSize", 0.001}}},
                  {"elements", {{{"name", "r"}, {"type", "paper_trajectory"}}}},
                  {"log", {"r.position", "r.velocity", "r.acceleration"}}};
  const auto r = Simulator(Build(j)).Run();
  const auto& t = r.log.time;
  const auto& x = r.log.Column("r.position");
  const auto& v = r.log.Column("r.velocity");
  const auto& a = r.log.Column("r.acceleration");
  EXPECT_NEAR(x.back(), 0.6, 1e-12);
  for (std::size_t i = 0; i < t.size(); ++i) {
    if (t[i] > 0.25 && t[i] < 1.15) {
      EXPECT_NEAR(v[i], 0.15, 1e-12);
    }
    if (t[i] > 1.45 && t[i] < 2.35) {
      EXPECT_NEAR(v[i], 0.35, 1e-12);
    }
    if (t[i] > 2.65) {
      EXPECT_NEAR(v[i], 0.0, 1e-12);
    }
  }
  // Peak acceleration of a half-sine transition: Δv·π/(2T); the deceleration is the largest.
  double a_min = 0.0;
  for (double ai : a) a_min = std::min(a_min, ai);
  EXPECT_NEAR(a_min, -0.35 * kPi / 0.4, 1e-3);
  // Velocity is the derivative of position (central difference on the 1 ms grid).
  for (std::size_t i = 1; i + 1 < t.size(); i += 37) {
    EXPECT_NEAR((x[i + 1] - x[i - 1]) / 0.002, v[i], 2e-5) << t[i];
  }
}

TEST(TrajectoryTest, OverlappingTransitionsAreRejected) {
  json j = {{"schemaVersion", "1.0"},
            {"elements", {{{"name", "r"}, {"type", "paper_trajectory"},
                           {"parameters", {{"transition_starts", {0.0, 0.1, 2.4}}}}}}}};
  try {
    Build(j);
    FAIL();
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("transition 1 starts at"), std::string::npos) << e.what();
  }
}

TEST(ScanTest, StrokesCoverTheTravelAtEachVelocity) {
  const json j = {{"schemaVersion", "1.0"},
                  {"defaultExperiment", {{"stopTime", 12.0}, {"stepSize", 0.001}}},
                  {"elements", {{{"name", "s"}, {"type", "constant_velocity_scan"},
                                 {"parameters", {{"velocities", {0.1, 0.35}}, {"start_position", -0.35}}}}}},
                  {"log", {"s.position", "s.velocity", "s.constant_velocity"}}};
  const auto r = Simulator(Build(j)).Run();
  const auto& x = r.log.Column("s.position");
  const auto& v = r.log.Column("s.velocity");
  const auto& cv = r.log.Column("s.constant_velocity");
  double x_max = -1.0, x_min = 1.0;
  for (std::size_t i = 0; i < x.size(); ++i) {
    x_max = std::max(x_max, x[i]);
    x_min = std::min(x_min, x[i]);
    if (cv[i] == 1.0) {
      EXPECT_NEAR(std::abs(v[i]), v[i] > 0 ? 0.1 : 0.35, 1e-12) << r.log.time[i];
    }
  }
  EXPECT_NEAR(x_max, 0.35, 1e-9);
  EXPECT_NEAR(x_min, -0.35, 1e-9);
  EXPECT_NEAR(x.back(), -0.35, 1e-9);  // back at the start after two strokes
}

json OpenLoopPlant(const json& parameters, double force, double stop) {
  return {{"schemaVersion", "1.0"},
          {"defaultExperiment", {{"stopTime", stop}, {"stepSize", 0.001}}},
          {"solver", {{"type", "rk4"}, {"step", 1e-4}}},
          {"elements", {{{"name", "u"}, {"type", "constant"}, {"parameters", {{"value", force}}}},
                        {{"name", "plant"}, {"type", "linear_motor"}, {"parameters", parameters}}}},
          {"connections", {Connect("u.y", "plant.u")}},
          {"log", {"plant.x", "plant.x_true", "plant.velocity", "plant.disturbance"}}};
}

TEST(LinearMotorTest, RigidBodyWithPayloadMatchesClosedForm) {
  // (M + m_p) ẍ + B ẋ = F: ẋ(t) = (F/B)(1 − e^{−Bt/M'}).
  const json p = {{"mass", 0.2621}, {"payload_mass", 0.3}, {"damping", 3.0}, {"cogging_amplitude", 0.0},
                  {"cogging_amplitude_velocity", 0.0}, {"coulomb_friction", 0.0}, {"static_friction", 0.0},
                  {"viscous_squared", 0.0}, {"encoder_resolution", 0.0}};
  const auto r = Simulator(Build(OpenLoopPlant(p, 1.5, 0.5))).Run();
  const double m = 0.5621, tc = m / 3.0;
  EXPECT_NEAR(r.log.Column("plant.velocity").back(), 0.5 * (1.0 - std::exp(-0.5 / tc)), 1e-9);
  EXPECT_NEAR(r.log.Column("plant.x").back(), 0.5 * (0.5 - tc * (1.0 - std::exp(-0.5 / tc))), 1e-9);
}

TEST(LinearMotorTest, PayloadPickedUpMidRunMatchesClosedForm) {
  // M ẍ + B ẋ = F until t_p = 0.2 s, then (M + m_p) ẍ + B ẋ = F from the velocity reached: for CVODE (the
  // switch located as a zero crossing) and a fixed step that lands on t_p.
  const json p = {{"mass", 0.2621}, {"payload_mass", 0.3}, {"payload_time", 0.2}, {"damping", 3.0},
                  {"cogging_amplitude", 0.0}, {"cogging_amplitude_velocity", 0.0}, {"coulomb_friction", 0.0},
                  {"static_friction", 0.0}, {"viscous_squared", 0.0}, {"encoder_resolution", 0.0}};
  const double v_inf = 1.5 / 3.0;
  const double v_tp = v_inf * (1.0 - std::exp(-0.2 / (0.2621 / 3.0)));
  const double tc = 0.5621 / 3.0;
  const double v_end = v_inf + (v_tp - v_inf) * std::exp(-0.3 / tc);
  for (const json& solver : {json{{"type", "rk4"}, {"step", 1e-4}}, json{{"type", "cvode"}, {"rtol", 1e-10},
                                                                       {"atol", 1e-12}}}) {
    json diagram = OpenLoopPlant(p, 1.5, 0.5);
    diagram["solver"] = solver;
    const auto r = Simulator(Build(diagram)).Run();
    EXPECT_NEAR(r.log.Column("plant.velocity").back(), v_end, 1e-7) << solver.dump();
  }
  // Without payload_time the payload is on from the start (the existing closed form above).
}

TEST(LinearMotorTest, EncoderQuantisesAndCoggingIsPeriodicInThePolePitch) {
  const json p = {{"encoder_resolution", 0.2e-6}, {"coulomb_friction", 0.0}, {"static_friction", 0.0},
                  {"viscous_squared", 0.0}, {"cogging_amplitude_velocity", 0.0}};
  const auto r = Simulator(Build(OpenLoopPlant(p, 2.0, 0.3))).Run();
  const auto& xe = r.log.Column("plant.x");
  const auto& xt = r.log.Column("plant.x_true");
  for (std::size_t i = 0; i < xe.size(); ++i) {
    EXPECT_LE(xe[i], xt[i] + 1e-15);
    EXPECT_GT(xe[i], xt[i] - 0.2e-6);
    EXPECT_NEAR(std::remainder(xe[i], 0.2e-6), 0.0, 1e-15);
  }
  // d = α_0·shape(x) at zero velocity-dependence and friction: equal at x and x + τ.
  CoggingParameters c;
  c.amplitude = 0.5;
  c.harmonics = Eigen::Vector3d(1.0, 0.25, 0.1);
  c.phases = Eigen::Vector3d(0.0, 0.7, 1.9);
  const CoggingForce cog(c);
  EXPECT_NEAR(cog.Force(0.0123, 0.2), cog.Force(0.0123 + 0.0225, 0.2), 1e-12);
  EXPECT_NEAR(r.log.Column("plant.disturbance").back(), cog.Force(xt.back(), 0.0), 1e-12);
}

TEST(LinearMotorTest, NonPhysicalParametersAreReported) {
  const json p = {{"cogging_harmonics", {1.0, 0.2}}, {"cogging_phases", {0.0, 0.1, 0.2}}};
  try {
    Build(OpenLoopPlant(p, 0.0, 0.01));
    FAIL();
  } catch (const std::exception& e) {
    EXPECT_NE(std::string(e.what()).find("plant: cogging: give one phase per harmonic"), std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace mb

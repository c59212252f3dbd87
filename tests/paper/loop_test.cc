// The closed loop: the discrete loop against eq. 6/7 at low frequency, the quantisation floor with P = P_n,
// and the calibrated conventional diagram against the paper's 42 µm (Table 2).

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

#include <gtest/gtest.h>

#include "models/stability/stability.h"
#include "tests/paper/paper_util.h"

namespace mb {
namespace {

using nlohmann::json;
using paper_testing::FitSinusoid;
using paper_testing::LoopWithInputs;
using paper_testing::RigidPlant;
using paper_testing::Series;
using paper_testing::kPi;

const std::string kConventional = std::string(MB_SOURCE_DIR) + "/diagrams/paper/conventional.json";

// A mismatched plant (M = 1.3 M_n, B = 4 ≠ B_n) so that eq. 6/7 are not trivially 1 and 0.
PaperLoop MismatchedLoop() {
  PaperLoop l;
  l.mass = 1.3 * 0.2621;
  l.damping = 4.0;
  l.q_cutoff_hz = 30.0;
  l.kp = 16000.0;
  l.kd = 90.0;
  l.derivative_cutoff_hz = 300.0;
  return l;
}

SimulationResult RunSinusoid(double f, bool reference, double stop) {
  const PaperLoop l = MismatchedLoop();
  const Diagram d = BuildDiagram(LoopWithInputs(RigidPlant(l.mass, l.damping), l.q_cutoff_hz, l.kp, l.kd, stop),
                                 ".", "eq6_7.json");
  Simulator sim(d);
  const double w = 2.0 * kPi * f, amp = reference ? 1e-3 : 1.0;
  auto zero = [](double) { return 0.0; };
  if (reference) {
    sim.SetInput("x_d", Series([&](double t) { return amp * std::cos(w * t); }, stop));
    // The feedforward is held over each period: sample it mid-interval (t + Ts/2), as the diagrams do.
    const double h = 0.0005;
    sim.SetInput("v_d", Series([&](double t) { return -amp * w * std::sin(w * (t + h)); }, stop));
    sim.SetInput("a_d", Series([&](double t) { return -amp * w * w * std::cos(w * (t + h)); }, stop));
    sim.SetInput("d", Series(zero, stop, 0.01));
  } else {
    sim.SetInput("x_d", Series(zero, stop, 0.01));
    sim.SetInput("v_d", Series(zero, stop, 0.01));
    sim.SetInput("a_d", Series(zero, stop, 0.01));
    sim.SetInput("d", Series([&](double t) { return amp * std::cos(w * t); }, stop));
  }
  return sim.Run();
}

TEST(LoopTest, ReferenceResponseMatchesEq6AtLowFrequency) {
  for (double f : {1.0, 4.0}) {
    const auto r = RunSinusoid(f, /*reference=*/true, 2.0);
    // The tracking error e = (1 − G_xd→x)·x_d is the sensitive part of eq. 6.
    const auto e = FitSinusoid(r.log.time, r.log.Column("error.y"), 2.0 * kPi * f, 1.0) / 1e-3;
    const BodePoint b = ClosedLoopBode(MismatchedLoop(), {f}).front();
    const auto expected = 1.0 - b.xd_to_x_continuous;
    EXPECT_NEAR(std::abs(e) / std::abs(expected), 1.0, 0.05) << f << " Hz";
    EXPECT_NEAR(std::abs(std::arg(e / expected)), 0.0, 0.05) << f << " Hz";
    // And the sampled-loop formula (same filters as the blocks) is closer still.
    const auto expected_discrete = 1.0 - b.xd_to_x_discrete;
    EXPECT_NEAR(std::abs(e) / std::abs(expected_discrete), 1.0, 0.02) << f << " Hz";
  }
}

TEST(LoopTest, DisturbanceResponseMatchesEq7AtLowFrequency) {
  for (double f : {1.0, 4.0}) {
    const auto r = RunSinusoid(f, /*reference=*/false, 2.0);
    const auto x = FitSinusoid(r.log.time, r.log.Column("plant.x"), 2.0 * kPi * f, 1.0);
    const BodePoint b = ClosedLoopBode(MismatchedLoop(), {f}).front();
    EXPECT_NEAR(std::abs(x) / std::abs(b.d_to_x_continuous), 1.0, 0.05) << f << " Hz";
    EXPECT_NEAR(std::abs(std::arg(x / b.d_to_x_continuous)), 0.0, 0.05) << f << " Hz";
    EXPECT_NEAR(std::abs(x) / std::abs(b.d_to_x_discrete), 1.0, 0.02) << f << " Hz";
    // The DOB estimate follows eq. 12 (to within ωTs/2, since d is continuous here, not held as the discrete
    // formula assumes).
    const auto dhat = FitSinusoid(r.log.time, r.log.Column("dob.d_hat"), 2.0 * kPi * f, 1.0);
    EXPECT_NEAR(std::abs(dhat - b.d_to_dhat_discrete), 0.0, 0.02) << f << " Hz";
  }
}

std::vector<ParameterOverride> NominalNoDisturbance() {
  std::vector<ParameterOverride> o;
  for (const char* s : {"plant.cogging_amplitude=0", "plant.cogging_amplitude_velocity=0", "plant.coulomb_friction=0",
                        "plant.static_friction=0", "plant.viscous_squared=0", "plant.mass=0.2621",
                        "plant.damping=3"}) {
    o.push_back(ParameterOverride::Parse(s));
  }
  return o;
}

TEST(LoopTest, NominalPlantWithoutDisturbanceTracksAtTheQuantisationLevel) {
  const Diagram d = LoadDiagram(kConventional, NominalNoDisturbance());
  const auto r = Simulator(d).Run();
  const double q = 0.2e-6;
  EXPECT_LT(r.metrics.at("tracking_max_abs"), 3.0 * q);
  EXPECT_LT(r.metrics.at("tracking_rmse"), q);
  // And the error is the quantisation: with an ideal encoder it is far smaller.
  auto ideal = NominalNoDisturbance();
  ideal.push_back(ParameterOverride::Parse("plant.encoder_resolution=0"));
  const auto r0 = Simulator(LoadDiagram(kConventional, ideal)).Run();
  EXPECT_LT(r0.metrics.at("tracking_rmse"), 0.1 * q);
}

TEST(LoopTest, CalibratedConventionalLoopGivesThePapersTrackingError) {
  const auto r = Simulator(LoadDiagram(kConventional)).Run();
  const double rmse = r.metrics.at("tracking_rmse");
  EXPECT_GT(rmse, 0.75 * 42.048e-6);
  EXPECT_LT(rmse, 1.25 * 42.048e-6);
  // The payload case (section 5.3) is the same diagram with an override; a heavier carrier tracks worse.
  const auto rp =
      Simulator(LoadDiagram(kConventional, {ParameterOverride::Parse("plant.payload_mass=0.5")})).Run();
  EXPECT_GT(rp.metrics.at("tracking_rmse"), rmse);
}

// The same loop under CVODE (BDF, rtol 1e-8) instead of the diagram's RK4 at 0.25 ms: the two engines must
// agree on the paper's figure of merit (measured: 40.920 vs 40.921 µm).
TEST(LoopTest, CvodeAndRk4AgreeOnTheConventionalLoop) {
  std::ifstream in(kConventional);
  json j = json::parse(in);
  const std::filesystem::path dir = std::filesystem::path(kConventional).parent_path();
  const double rk4 = Simulator(BuildDiagram(j, dir, kConventional))
                         .Run()
                         .metrics.at("tracking_rmse");
  j["solver"] = {{"type", "cvode"}, {"method", "bdf"}, {"rtol", 1e-8}};
  const auto r = Simulator(BuildDiagram(j, dir, kConventional + " (solver: cvode)")).Run();
  EXPECT_NEAR(r.metrics.at("tracking_rmse"), rk4, 1e-3 * rk4);
  EXPECT_GT(r.solver_stats.steps, 0);
}

}  // namespace
}  // namespace mb

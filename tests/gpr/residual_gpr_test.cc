// The diagnosis's non-parametric fallback: a TISO-GPR scored on held-out blocks of the residual.
#include "models/gpr/residual_gpr.h"

#include <cmath>
#include <iostream>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>

#include <fmt/format.h>
#include <gtest/gtest.h>

namespace mb {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kPitch = 0.0225;  // [m]

// Back and forth over 0..0.2 m at 1 kHz for 12 s, the stroke speed changing from stroke to stroke, so that
// every block of the record covers positions and speeds the other blocks cover too.
DiagnosisSignals Motion() {
  const Eigen::Index n = 12000;
  DiagnosisSignals s;
  s.time = Eigen::VectorXd::LinSpaced(n, 0.0, 0.001 * static_cast<double>(n - 1));
  s.position.resize(n);
  s.velocity.resize(n);
  s.acceleration.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double t = s.time(i);
    const double w = 2.0 * kPi * 0.25;
    const double amp = 0.1 * (1.0 + 0.15 * std::sin(0.4 * t));
    s.position(i) = 0.1 + amp * std::sin(w * t);
    s.velocity(i) = amp * w * std::cos(w * t);
    s.acceleration(i) = -amp * w * w * std::sin(w * t);
  }
  s.residual = Eigen::VectorXd::Zero(n);
  return s;
}

Eigen::VectorXd Noise(Eigen::Index n, double sigma, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n01;
  Eigen::VectorXd e(n);
  for (auto& v : e) v = sigma * n01(rng);
  return e;
}

// A residual no single catalogue entry describes: a cogging shape with three harmonics plus a velocity-dependent
// hump that is neither viscous, Coulomb nor Stribeck. The GP must take most of it on held-out blocks.
TEST(ResidualGpr, LearnsWhatDependsOnPositionAndVelocity) {
  const DiagnosisSignals s = Motion();
  Eigen::VectorXd r(s.size());
  for (Eigen::Index i = 0; i < s.size(); ++i) {
    const double th = 2.0 * kPi * s.position(i) / kPitch;
    const double v = s.velocity(i);
    r(i) = 2.0 * std::sin(th) + 0.8 * std::cos(2.0 * th + 0.4) + 0.4 * std::sin(3.0 * th) +
           1.5 * std::exp(-std::pow((std::abs(v) - 0.08) / 0.03, 2.0));
  }
  const double noise = 0.3;
  r += Noise(s.size(), noise, 3);
  ResidualGprOptions options;
  options.period = kPitch;
  const ResidualGprResult g = FitResidualGpr(s, r, options);
  std::cout << g.description << "\n";
  EXPECT_TRUE(g.useful);
  EXPECT_EQ(g.kernel, GprKernel::kPeriodicSe);
  EXPECT_GT(g.heldout_share, 0.9);
  EXPECT_LT(g.heldout_rmse_after, 1.3 * noise);  // near the noise on data it did not see
  ASSERT_TRUE(g.model.has_value());
  EXPECT_LT(g.rmse_after, 1.2 * noise);
  EXPECT_NE(g.description.find("held-out"), std::string::npos);
  EXPECT_NE(g.description.find(fmt::format("PS, period {:.4g} mm", 1e3 * kPitch)), std::string::npos) << g.description;
  // The period in the position's own unit when it is not metres (a rotary axis in rad; issue 25).
  options.position_unit = "rad";
  options.max_training_samples = 3000;
  const ResidualGprResult in_rad = FitResidualGpr(s, r, options);
  EXPECT_NE(in_rad.description.find(fmt::format("PS, period {:.4g} rad", kPitch)), std::string::npos)
      << in_rad.description;
  const nlohmann::json j = g.ToJson();
  EXPECT_EQ(j.at("kernel"), "PS");
  EXPECT_DOUBLE_EQ(j.at("heldout_share").get<double>(), g.heldout_share);
}

// A velocity-only shape without a period: "DS" (SE + SE) is chosen and learns it.
TEST(ResidualGpr, WithoutAPeriodUsesTheSeKernel) {
  const DiagnosisSignals s = Motion();
  Eigen::VectorXd r(s.size());
  for (Eigen::Index i = 0; i < s.size(); ++i) r(i) = 1.5 * std::tanh(s.velocity(i) / 0.02) * std::abs(s.velocity(i)) / 0.1;
  r += Noise(s.size(), 0.2, 4);
  ResidualGprOptions options;
  options.max_training_samples = 3000;  // DS needs ~150 features here: keep the six fits quick under ASan
  options.restarts = 0;
  const ResidualGprResult g = FitResidualGpr(s, r, options);
  std::cout << g.description << "\n";
  EXPECT_EQ(g.kernel, GprKernel::kSeSe);
  EXPECT_TRUE(g.useful) << g.description;
  EXPECT_GT(g.heldout_share, 0.9) << g.description;
}

// A white residual: the fallback must say there is nothing left that depends on the motion state.
TEST(ResidualGpr, WhiteResidualIsNotUseful) {
  const DiagnosisSignals s = Motion();
  ResidualGprOptions options;
  options.period = kPitch;
  const ResidualGprResult g = FitResidualGpr(s, Noise(s.size(), 0.5, 5), options);
  EXPECT_FALSE(g.useful) << g.description;
  EXPECT_LT(g.heldout_share, 0.01);
  EXPECT_FALSE(g.model.has_value());
  EXPECT_NE(g.description.find("does not depend on the motion state"), std::string::npos) << g.description;
}

TEST(ResidualGpr, BadInputIsAClearError) {
  const DiagnosisSignals s = Motion();
  Eigen::VectorXd r = Noise(s.size(), 0.5, 6);
  ResidualGprOptions ps;
  ps.kernel = GprKernel::kPeriodicSe;  // without a period
  EXPECT_THROW(FitResidualGpr(s, r, ps), std::invalid_argument);
  EXPECT_THROW(FitResidualGpr(s, r.head(100)), std::invalid_argument);
  r(7) = std::nan("");
  try {
    FitResidualGpr(s, r);
    FAIL() << "expected std::invalid_argument";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("NaN"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace mb

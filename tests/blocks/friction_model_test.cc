// models/physics/friction.h and rigid_body.h: the friction curve, the stick force, the mode transitions.

#include <cmath>
#include <numbers>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "models/physics/cogging.h"
#include "models/physics/friction.h"
#include "models/physics/rigid_body.h"
#include "models/physics/stribeck.h"

namespace mb {
namespace {

using ::testing::HasSubstr;

const FrictionParameters kStribeck{0.5, 1.0, 1.5, 0.01};  // σ, F_c, F_s, v_s

// The hot-path shortcuts of the plant (issue 29): the Stribeck level skips exp(−r²) where it is 0 in double, and
// the cogging shape's SinCosBounded stands in for std::sin/std::cos up to 2048 rad: both give the formula.
TEST(FrictionModelTest, HotPathShortcutsGiveTheFormula) {
  for (const double v : {0.0, 0.01, 0.1, 0.13, 0.1365, 0.137, 0.2, 10.0, -0.137, -3.0}) {
    const double r = v / 0.005;
    EXPECT_EQ(StribeckLevel(0.1, 0.15, 0.005, v), 0.1 + (0.15 - 0.1) * std::exp(-r * r)) << v;
  }
  for (const double v : {0.0, 0.001, 0.019, 0.021999, 0.022, 0.0221, 0.5, -0.022, -0.03}) {  // tanh(v/1e-3)
    EXPECT_EQ(RegularizedFriction(kStribeck, 1e-3, v),
              std::tanh(v / 1e-3) * StribeckLevel(1.0, 1.5, 0.01, v) + 0.5 * v) << v;
  }
  CoggingParameters p;
  p.harmonics = Eigen::Vector3d(1.0, 0.25, 0.1);
  p.phases = Eigen::Vector3d(0.0, 0.7, 1.9);
  const CoggingForce cogging(p);
  const double k = 2.0 * std::numbers::pi / p.pole_pitch;
  for (double x = -7.5; x <= 7.5; x += 0.0123457) {  // beyond ±2048 rad at both ends: std::sin/std::cos there
    double expected = 0.0;
    for (int h = 1; h <= 3; ++h) expected += p.harmonics(h - 1) * std::sin(h * k * x + p.phases(h - 1));
    ASSERT_NEAR(cogging.Shape(x), expected, 1e-12) << x;
  }
}

TEST(FrictionModelTest, SlidingFrictionUsesTheModeNotTheVelocitySign) {
  EXPECT_DOUBLE_EQ(SlidingFriction(kStribeck, FrictionMode::kSlipPositive, 0.0), 1.5);  // F_s at v = 0
  EXPECT_DOUBLE_EQ(SlidingFriction(kStribeck, FrictionMode::kSlipNegative, 0.0), -1.5);
  EXPECT_NEAR(SlidingFriction(kStribeck, FrictionMode::kSlipPositive, 0.01), 1.0 + 0.5 * std::exp(-1.0) + 0.005,
              1e-15);
  // Slipping forward at a slightly negative velocity (just before the event): still the forward level.
  EXPECT_NEAR(SlidingFriction(kStribeck, FrictionMode::kSlipPositive, -1e-9), 1.5, 1e-8);
  const FrictionParameters coulomb{0.0, 1.0, 1.0, 0.0};
  EXPECT_DOUBLE_EQ(SlidingFriction(coulomb, FrictionMode::kSlipPositive, 100.0), 1.0);
  EXPECT_DOUBLE_EQ(SteadyStateFriction(kStribeck, -0.01), -(1.0 + 0.5 * std::exp(-1.0)) - 0.005);
  EXPECT_DOUBLE_EQ(SteadyStateFriction(kStribeck, 0.0), 0.0);
}

// One law: the regularised form is the sliding law with tanh(v/v_reg) for the mode, and the linear motor's Stribeck
// friction (models/physics/stribeck.h) is the same law plus b_2·v|v|.
TEST(FrictionModelTest, RegularizedFrictionIsTheSlidingLawWithATanhSign) {
  const double vreg = 1e-3;
  for (double v : {-0.02, -0.004, -1e-4, 0.0, 3e-4, 0.01, 0.05}) {
    const double s = std::tanh(v / vreg);
    const double expected = s * (1.0 + 0.5 * std::exp(-(v / 0.01) * (v / 0.01))) + 0.5 * v;
    EXPECT_NEAR(RegularizedFriction(kStribeck, vreg, v), expected, 1e-15) << v;
    if (v != 0.0) {
      EXPECT_NEAR(RegularizedFriction(kStribeck, vreg, v),
                  s * (SlidingFriction(kStribeck, FrictionMode::kSlipPositive, v) - 0.5 * v) + 0.5 * v, 1e-14);
    }
    const StribeckFriction motor({.coulomb = 1.0, .static_friction = 1.5, .stribeck_velocity = 0.01,
                                  .viscous_squared = 2.0, .regularization_velocity = vreg});
    const FrictionParameters no_viscous{0.0, 1.0, 1.5, 0.01};
    EXPECT_NEAR(motor.Force(v), RegularizedFriction(no_viscous, vreg, v) + 2.0 * v * std::abs(v), 1e-15) << v;
  }
  EXPECT_DOUBLE_EQ(StribeckLevel(1.0, 1.5, 0.0, 0.0), 1.0);  // v_s = 0: no hump
}

TEST(FrictionModelTest, StuckFrictionBalancesTheAppliedForceUpToBreakaway) {
  EXPECT_DOUBLE_EQ(FrictionForce(kStribeck, FrictionMode::kStuck, 0.0, 1.2), 1.2);
  EXPECT_DOUBLE_EQ(FrictionForce(kStribeck, FrictionMode::kStuck, 0.0, -3.0), -1.5);
}

TEST(FrictionModelTest, ModeTransitions) {
  using M = FrictionMode;
  const double tol = 1e-6;
  // Slipping forward, still moving forward: unchanged whatever the force.
  EXPECT_EQ(NextFrictionMode(kStribeck, M::kSlipPositive, 0.1, -10.0, true, tol), M::kSlipPositive);
  // v reached zero: stick if the force is below breakaway, else slip along the force.
  EXPECT_EQ(NextFrictionMode(kStribeck, M::kSlipPositive, -1e-12, 1.4, true, tol), M::kStuck);
  EXPECT_EQ(NextFrictionMode(kStribeck, M::kSlipPositive, -1e-12, -1.6, true, tol), M::kSlipNegative);
  EXPECT_EQ(NextFrictionMode(kStribeck, M::kSlipNegative, 0.0, 1.6, true, tol), M::kSlipPositive);
  // Stuck: breakaway by force, or by a velocity the stick cannot explain.
  EXPECT_EQ(NextFrictionMode(kStribeck, M::kStuck, 0.0, 1.49, true, tol), M::kStuck);
  EXPECT_EQ(NextFrictionMode(kStribeck, M::kStuck, 0.0, 1.5, true, tol), M::kSlipPositive);  // g = 0 switches
  EXPECT_EQ(NextFrictionMode(kStribeck, M::kSlipPositive, 0.0, 1.5, true, tol), M::kSlipPositive);  // no flip back
  EXPECT_EQ(NextFrictionMode({0.1, 0.0, 0.0, 0.0}, M::kStuck, 0.0, 0.0, true, tol), M::kStuck);  // no force, F_s = 0
  EXPECT_EQ(NextFrictionMode(kStribeck, M::kStuck, 0.0, -1.51, true, tol), M::kSlipNegative);
  EXPECT_EQ(NextFrictionMode(kStribeck, M::kStuck, 1e-9, 0.0, true, tol), M::kStuck);
  EXPECT_EQ(NextFrictionMode(kStribeck, M::kStuck, 0.2, 0.0, true, tol), M::kSlipPositive);
  // Slip-only model: the direction follows v.
  EXPECT_EQ(NextFrictionMode(kStribeck, M::kSlipPositive, -1e-12, 0.0, false, tol), M::kSlipNegative);
  EXPECT_EQ(NextFrictionMode(kStribeck, M::kSlipPositive, 0.0, 0.0, false, tol), M::kSlipPositive);
}

TEST(FrictionModelTest, ValidationMessages) {
  try {
    ValidateFrictionParameters({0.0, 2.0, 1.0, 0.0}, "friction 'f'");
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("friction 'f': static (breakaway) force 1.000000 N is below the Coulomb force"));
  }
  EXPECT_THROW(ValidateFrictionParameters({-1.0, 0.0, 0.0, 0.0}, "f"), std::invalid_argument);
  EXPECT_THROW(ValidateFrictionParameters({0.0, 0.0, 0.0, NAN}, "f"), std::invalid_argument);
  EXPECT_NO_THROW(ValidateFrictionParameters(kStribeck, "f"));
}

TEST(RigidBodyModelTest, AccelerationAndValidation) {
  const RigidBodyParameters body{0.2621, 3.0};
  EXPECT_DOUBLE_EQ(RigidBodyAcceleration(body, 1.0, 0.1), (1.0 - 0.3) / 0.2621);
  EXPECT_THROW(ValidateRigidBodyParameters({0.0, 0.0}, "b"), std::invalid_argument);
  EXPECT_THROW(ValidateRigidBodyParameters({1.0, -1.0}, "b"), std::invalid_argument);
  EXPECT_NO_THROW(ValidateRigidBodyParameters(body, "b"));
}

}  // namespace
}  // namespace mb

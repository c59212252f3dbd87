#include "models/gpr/sincos.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <gtest/gtest.h>

namespace mb {
namespace {

constexpr double kEps = std::numeric_limits<double>::epsilon();

// Dense sweep of the specified range, including the quarter-turn boundaries where the
// reduction switches polynomial and sign: within 2·eps of libm (measured: 1 eps).
TEST(SinCosBoundedTest, MatchesLibmOverTheSpecifiedRange) {
  constexpr int kSamples = 2'000'000;
  double worst_sin = 0.0;
  double worst_cos = 0.0;
  for (int i = 0; i <= kSamples; ++i) {
    const double theta = -kSinCosMaxAngle + 2.0 * kSinCosMaxAngle * i / kSamples;
    double s = 0.0;
    double c = 0.0;
    SinCosBounded(theta, &s, &c);
    worst_sin = std::max(worst_sin, std::abs(s - std::sin(theta)));
    worst_cos = std::max(worst_cos, std::abs(c - std::cos(theta)));
  }
  EXPECT_LE(worst_sin, 2.0 * kEps);
  EXPECT_LE(worst_cos, 2.0 * kEps);
}

TEST(SinCosBoundedTest, ExactAtTheQuarterTurnsWithinRounding) {
  constexpr double kPi = 3.14159265358979323846;
  const double angles[] = {0.0, kPi / 4, kPi / 2, 3 * kPi / 4, kPi, 3 * kPi / 2, 2 * kPi, -kPi / 2};
  for (double theta : angles) {
    double s = 0.0;
    double c = 0.0;
    SinCosBounded(theta, &s, &c);
    EXPECT_NEAR(s, std::sin(theta), 2.0 * kEps) << "theta " << theta;
    EXPECT_NEAR(c, std::cos(theta), 2.0 * kEps) << "theta " << theta;
    EXPECT_NEAR(s * s + c * c, 1.0, 4.0 * kEps) << "theta " << theta;
  }
}

}  // namespace
}  // namespace mb

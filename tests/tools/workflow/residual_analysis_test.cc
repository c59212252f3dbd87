// Residual analysis (tools/workflow/residual_analysis.h over the diagnosis's correlations): the autocorrelation and
// the input–residual cross-correlation scored against their 99 % bands, on cases whose answer is known: white noise stays inside the band, an AR(1)
// residual leaves lag 1 outside at its coefficient, a residual that follows the input three samples late shows lag +3.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>

#include "tools/workflow/residual_analysis.h"

namespace mb {
namespace {

using ::testing::HasSubstr;

Eigen::VectorXd WhiteNoise(Eigen::Index n, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal(0.0, 1.0);
  Eigen::VectorXd v(n);
  for (Eigen::Index i = 0; i < n; ++i) v(i) = normal(rng);
  return v;
}

TEST(ResidAutocorrelation, WhiteNoiseStaysInsideTheBand) {
  const Eigen::Index n = 20000;
  const ResidualCorrelation a = ResidAutocorrelation(WhiteNoise(n, 1) .array() + 3.0);  // the mean is removed
  ASSERT_EQ(a.lags.size(), 26u);
  EXPECT_EQ(a.lags.front(), 0);
  EXPECT_EQ(a.lags.back(), 25);
  EXPECT_DOUBLE_EQ(a.values[0], 1.0);
  EXPECT_NEAR(a.band, 2.58 / std::sqrt(20000.0), 1e-12);
  EXPECT_GT(a.ljung_box_p, 0.01);
  EXPECT_EQ(a.tested, 25u);
  EXPECT_LE(a.outside, 1u) << "at most 5 % of 25 lags outside a 99 % band";
  EXPECT_TRUE(a.within_band());
  EXPECT_THAT(DescribeWhiteness(a, 1e-3), HasSubstr("The residual is white"));
}

TEST(ResidAutocorrelation, WhiteNoiseOverManySeedsLeavesAboutOnePercentOutside) {
  std::size_t outside = 0, tested = 0;
  for (unsigned seed = 0; seed < 40; ++seed) {
    const ResidualCorrelation a = ResidAutocorrelation(WhiteNoise(4000, 100 + seed));
    outside += a.outside;
    tested += a.tested;
  }
  const double share = static_cast<double>(outside) / static_cast<double>(tested);
  EXPECT_LE(share, 0.05) << outside << " of " << tested;  // ≥ 95 % inside
  EXPECT_NEAR(share, 0.01, 0.01);                          // the band is a 99 % band
}

TEST(ResidAutocorrelation, AnAr1ResidualLeavesLagOneOutsideAtItsCoefficient) {
  const Eigen::Index n = 20000;
  const Eigen::VectorXd w = WhiteNoise(n, 2);
  Eigen::VectorXd e(n);
  e(0) = w(0);
  for (Eigen::Index i = 1; i < n; ++i) e(i) = 0.5 * e(i - 1) + w(i);
  const ResidualCorrelation a = ResidAutocorrelation(e, 10);
  ASSERT_EQ(a.lags.size(), 11u);
  EXPECT_NEAR(a.values[1], 0.5, 0.02);   // ρ(1) = φ
  EXPECT_NEAR(a.values[2], 0.25, 0.02);  // ρ(2) = φ²
  EXPECT_GT(std::abs(a.values[1]), a.band);
  EXPECT_EQ(a.strongest_lag, 1);
  EXPECT_FALSE(a.within_band());
  EXPECT_LT(a.ljung_box_p, 1e-6);
  EXPECT_THAT(DescribeWhiteness(a, 1e-3),
              HasSubstr("The residual is not white: "));
  EXPECT_THAT(DescribeWhiteness(a, 1e-3), HasSubstr("at lag 1 sample = 1 ms"));
}

TEST(ResidAutocorrelation, AnAlternatingSignalHasTheExactBiasedEstimate) {
  Eigen::VectorXd e(100);
  for (Eigen::Index i = 0; i < 100; ++i) e(i) = i % 2 ? -1.0 : 1.0;  // mean 0
  const ResidualCorrelation a = ResidAutocorrelation(e, 3);
  EXPECT_NEAR(a.values[1], -99.0 / 100.0, 1e-12);  // (1/N) Σ over N − τ products, normalised by R(0) = 1
  EXPECT_NEAR(a.values[2], 98.0 / 100.0, 1e-12);
  EXPECT_NEAR(a.values[3], -97.0 / 100.0, 1e-12);
}

TEST(ResidCrossCorrelation, AnIndependentInputStaysInsideTheBand) {
  const ResidualCorrelation c = ResidCrossCorrelation(WhiteNoise(20000, 3), WhiteNoise(20000, 4));
  ASSERT_EQ(c.lags.size(), 51u);
  EXPECT_EQ(c.lags.front(), -25);
  EXPECT_EQ(c.lags.back(), 25);
  EXPECT_EQ(c.tested, 51u);
  EXPECT_LE(c.outside, 2u);
  EXPECT_TRUE(c.within_band());
  EXPECT_THAT(DescribeIndependence(c, "velocity", 1e-3), HasSubstr("independent of the velocity"));
}

TEST(ResidCrossCorrelation, AResidualThatFollowsTheInputThreeSamplesLateShowsLagPlusThree) {
  const Eigen::Index n = 20000;
  const Eigen::VectorXd u = WhiteNoise(n, 5), w = WhiteNoise(n, 6);
  Eigen::VectorXd e = w;
  for (Eigen::Index i = 3; i < n; ++i) e(i) += 0.3 * u(i - 3);  // ε(t) = w(t) + 0.3 u(t − 3)
  const ResidualCorrelation c = ResidCrossCorrelation(u, e);
  EXPECT_EQ(c.strongest_lag, 3);
  // ρ(3) = 0.3 / √(1 + 0.09)
  EXPECT_NEAR(c.strongest, 0.3 / std::sqrt(1.09), 0.02);
  EXPECT_GT(c.strongest, c.band);
  EXPECT_EQ(c.values[25 - 3] > c.band, false) << "the residual does not lead the input";
  EXPECT_THAT(DescribeIndependence(c, "command", 1e-3),
              HasSubstr("The residual depends on the command: "));
  EXPECT_THAT(DescribeIndependence(c, "command", 1e-3), HasSubstr("the residual after the input"));
}

TEST(ResidCorrelation, RefusesWhatCannotBeCorrelated) {
  const Eigen::VectorXd noise = WhiteNoise(100, 7);
  EXPECT_THROW(ResidAutocorrelation(noise, 0), std::invalid_argument);
  EXPECT_THROW(ResidAutocorrelation(noise, 99), std::invalid_argument);  // N ≤ M + 1
  try {
    ResidAutocorrelation(Eigen::VectorXd::Constant(100, 2.0));
    FAIL() << "a constant residual was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("the residual is constant"));
  }
  Eigen::VectorXd with_nan = noise;
  with_nan(5) = std::nan("");
  EXPECT_THROW(ResidAutocorrelation(with_nan), std::invalid_argument);
  EXPECT_THROW(ResidCrossCorrelation(WhiteNoise(99, 8), noise), std::invalid_argument);  // lengths differ
  EXPECT_THROW(ResidCrossCorrelation(Eigen::VectorXd::Zero(100), noise), std::invalid_argument);
}

}  // namespace
}  // namespace mb

#include "models/diagnosis/periodogram.h"

#include <chrono>
#include <cmath>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

namespace mb {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

// Back-and-forth motion over 0..0.2 m at varying speed, 1 kHz, n samples.
Eigen::VectorXd Motion(Eigen::Index n) {
  Eigen::VectorXd x(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double t = 1e-3 * static_cast<double>(i);
    x(i) = 0.1 + 0.1 * std::sin(kTwoPi * 0.15 * t + 0.3 * std::sin(kTwoPi * 0.05 * t));
  }
  return x;
}

TEST(Periodogram, RecoversPeriodAndShareOfVariance) {
  const Eigen::Index n = 20000;
  const Eigen::VectorXd x = Motion(n);
  std::mt19937 rng(11);
  std::normal_distribution<double> n01;
  const double period = 2.5e-3;
  Eigen::VectorXd r(n);
  for (Eigen::Index i = 0; i < n; ++i) r(i) = 0.5 * std::sin(kTwoPi * x(i) / period + 0.4) + 0.5 * n01(rng) + 3.0;
  const auto start = std::chrono::steady_clock::now();
  const Periodogram pg = PositionPeriodogram(x, r);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  ASSERT_FALSE(pg.peaks.empty());
  EXPECT_NEAR(pg.best().period, period, 1e-3 * period);
  // Variance shares: sinusoid 0.125, noise 0.25 → power 1/3.
  EXPECT_NEAR(pg.best().power, 1.0 / 3.0, 0.02);
  EXPECT_NEAR(pg.best().amplitude, 0.5, 0.01);
  EXPECT_NEAR(pg.best().power, LombScarglePower(x, r, pg.best().period), 0.005);
  EXPECT_TRUE(pg.best().significant);
  EXPECT_LT(pg.best().false_alarm_probability, 1e-10);
  // The reported curve peaks there too, and is a share in [0, 1].
  Eigen::Index k = 0;
  EXPECT_NEAR(pg.power.maxCoeff(&k), pg.best().power, 0.02);
  EXPECT_NEAR(pg.periods(k), period, 0.01 * period);
  EXPECT_GE(pg.power.minCoeff(), 0.0);
  EXPECT_LE(pg.power.maxCoeff(), 1.0);
  // Automatic bounds: 4 × median |Δx| .. span/2.
  EXPECT_NEAR(pg.max_period, 0.5 * (x.maxCoeff() - x.minCoeff()), 1e-12);
  EXPECT_LT(seconds, 2.0);  // sanitizer build; ~20 ms in Release
}

TEST(Periodogram, FlagsHarmonicsAndKeepsThemListed) {
  const Eigen::Index n = 20000;
  const Eigen::VectorXd x = Motion(n);
  std::mt19937 rng(2);
  std::normal_distribution<double> n01;
  const double period = 4e-3;
  Eigen::VectorXd r(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double th = kTwoPi * x(i) / period;
    r(i) = std::sin(th) + 0.4 * std::sin(3.0 * th + 1.0) + 0.2 * n01(rng);
  }
  const Periodogram pg = PositionPeriodogram(x, r);
  ASSERT_GE(pg.peaks.size(), 2u);
  EXPECT_NEAR(pg.peaks[0].period, period, 1e-3 * period);
  EXPECT_EQ(pg.peaks[0].harmonic_of, -1);
  EXPECT_NEAR(pg.peaks[1].period, period / 3.0, 1e-3 * period);
  EXPECT_EQ(pg.peaks[1].harmonic_of, 0);
  EXPECT_EQ(pg.peaks[1].harmonic_order, 3);
  EXPECT_TRUE(pg.peaks[1].significant);
}

TEST(Periodogram, WhiteNoiseHasNoSignificantPeak) {
  const Eigen::Index n = 10000;
  const Eigen::VectorXd x = Motion(n);
  std::mt19937 rng(9);
  std::normal_distribution<double> n01;
  Eigen::VectorXd r(n);
  for (auto& v : r) v = n01(rng);
  const Periodogram pg = PositionPeriodogram(x, r);
  ASSERT_FALSE(pg.peaks.empty());
  EXPECT_FALSE(pg.best().significant) << "FAP " << pg.best().false_alarm_probability;
  EXPECT_GT(pg.best().false_alarm_probability, 0.01);
  EXPECT_LT(pg.best().power, 0.005);
}

TEST(Periodogram, TimeDomainFindsAVibrationFrequency) {
  const Eigen::Index n = 10000;
  Eigen::VectorXd t = Eigen::VectorXd::LinSpaced(n, 0.0, 1e-3 * static_cast<double>(n - 1));
  std::mt19937 rng(4);
  std::normal_distribution<double> n01;
  Eigen::VectorXd r(n);
  for (Eigen::Index i = 0; i < n; ++i) r(i) = 0.3 * std::cos(kTwoPi * 37.3 * t(i)) + 0.3 * n01(rng);
  const Periodogram pg = TimePeriodogram(t, r);
  EXPECT_NEAR(1.0 / pg.best().period, 37.3, 0.01);
  EXPECT_NEAR(pg.min_period, 4e-3, 1e-9);
}

TEST(Periodogram, BaluevFalseAlarmProbabilityLimits) {
  EXPECT_NEAR(BaluevFalseAlarmProbability(0.0, 1000, 0.01, 1.0), 1.0, 1e-12);
  EXPECT_LT(BaluevFalseAlarmProbability(0.1, 1000, 0.01, 1.0), 1e-10);
  const double small = BaluevFalseAlarmProbability(0.01, 1000, 0.01, 1.0);
  const double large = BaluevFalseAlarmProbability(0.02, 1000, 0.01, 1.0);
  EXPECT_GT(small, large);  // decreasing in power
}

TEST(Periodogram, RejectsBadInput) {
  const Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(100, 0.0, 1.0);
  EXPECT_THROW(LombScarglePeriodogram(x, Eigen::VectorXd::Ones(100)), std::invalid_argument);  // constant
  EXPECT_THROW(LombScarglePeriodogram(x, Eigen::VectorXd::Ones(99)), std::invalid_argument);
  PeriodogramOptions o;
  o.min_period = 0.6;
  o.max_period = 0.5;
  EXPECT_THROW(LombScarglePeriodogram(x, x.array().sin().matrix(), o), std::invalid_argument);
}

}  // namespace
}  // namespace mb

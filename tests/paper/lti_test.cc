// LTI filters and the paper's filter designs against closed forms: ZOH and Tustin of first-order filters,
// the binomial Q-filter's DC gain and strict properness, Q∘P_n⁻¹'s zero at DC, the velocity estimator's l1 norm.

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "models/stability/dob_design.h"
#include "models/stability/lti.h"
#include "tests/paper/paper_util.h"

namespace mb {
namespace {

using paper_testing::kPi;

TEST(LtiTest, ZohOfFirstOrderLowPassMatchesClosedForm) {
  // ω/(s + ω) → (1 − e^{−ωT}) z⁻¹ / (1 − e^{−ωT} z⁻¹).
  const double w = 2.0 * kPi * 10.0, ts = 1e-3, a = std::exp(-w * ts);
  const DiscreteTf d = Discretize(BinomialLowPass(10.0, 1), ts, Discretization::kZeroOrderHold);
  ASSERT_EQ(d.order(), 1);
  EXPECT_EQ(d.b(0), 0.0);
  EXPECT_NEAR(d.b(1), 1.0 - a, 1e-14);
  EXPECT_NEAR(d.a(1), -a, 1e-14);
  EXPECT_TRUE(d.strictly_proper());
}

// ω^n/(s + ω)^n at 100 Hz and Ts = 1 ms (a q_filter or f_gp of high relative degree): the ZOH equivalent's step
// response equals the continuous one at the samples, 1 − e^{−ωt} Σ_{m<n} (ωt)^m/m!, and its n poles sit at
// p = e^{−ωTs}, so a(z⁻¹) = (1 − p z⁻¹)^n. The Taylor exponential this replaced was off from n = 5 and unstable at
// n = 8 (issue 11; SciPy's cont2discrete agrees with the closed form).
TEST(LtiTest, ZohOfHighRelativeDegreeMatchesClosedForm) {
  const double w = 2.0 * kPi * 100.0, ts = 1e-3, p = std::exp(-w * ts);
  for (int n = 5; n <= 8; ++n) {
    const DiscreteTf d = Discretize(BinomialLowPass(100.0, n), ts, Discretization::kZeroOrderHold);
    ASSERT_EQ(d.order(), n);
    double binomial = 1.0;  // C(n, k)
    for (int k = 0; k <= n; ++k) {
      EXPECT_NEAR(d.a(k), binomial * std::pow(-p, k), 1e-10 * binomial) << "n = " << n << ", a_" << k;
      binomial = binomial * (n - k) / (k + 1);
    }
    EXPECT_LT(d.SpectralRadius(), 1.0) << n;
    const Eigen::VectorXd h = ImpulseResponse(d, 40);
    double step = 0.0;
    for (int k = 0; k < 40; ++k) {
      step += h(k);
      const double wt = w * ts * k;
      double series = 0.0, term = 1.0;
      for (int m = 0; m < n; ++m) {
        series += term;
        term *= wt / (m + 1);
      }
      EXPECT_NEAR(step, 1.0 - std::exp(-wt) * series, 1e-10) << "n = " << n << ", k = " << k;
    }
  }
}

TEST(LtiTest, TustinOfFirstOrderLowPassMatchesClosedForm) {
  // ω/(s + ω) → ωT(1 + z⁻¹) / ((2 + ωT) − (2 − ωT) z⁻¹).
  const double w = 2.0 * kPi * 10.0, ts = 1e-3;
  const DiscreteTf d = Discretize(BinomialLowPass(10.0, 1), ts, Discretization::kTustin);
  const double n = 2.0 + w * ts;
  EXPECT_NEAR(d.b(0), w * ts / n, 1e-14);
  EXPECT_NEAR(d.b(1), w * ts / n, 1e-14);
  EXPECT_NEAR(d.a(1), -(2.0 - w * ts) / n, 1e-14);
}

TEST(LtiTest, BinomialQFilterHasUnitDcGainAndRepeatedPole) {
  for (int n = 1; n <= 4; ++n) {
    for (auto method : {Discretization::kZeroOrderHold, Discretization::kTustin}) {
      const DiscreteTf q = Discretize(BinomialLowPass(40.0, n), 1e-3, method);
      EXPECT_NEAR(q.DcGain(), 1.0, 1e-10) << n << ToString(method);
      EXPECT_EQ(q.order(), n);
    }
    // ZOH poles are e^{−ωT} (repeated n times): a(z⁻¹) = (1 − p z⁻¹)^n, so a_1 = −n p.
    const DiscreteTf q = Discretize(BinomialLowPass(40.0, n), 1e-3, Discretization::kZeroOrderHold);
    const double p = std::exp(-2.0 * kPi * 40.0 * 1e-3);
    EXPECT_NEAR(q.a(1), -n * p, 1e-9);
    EXPECT_NEAR(q.a(n), std::pow(-p, n), 1e-9);
    // The roots of a polynomial with an n-fold root are only ~eps^(1/n) accurate.
    EXPECT_NEAR(q.SpectralRadius(), p, 0.01);
    // A binomial low-pass has a non-negative impulse response, so ‖Q‖₁ = Q(1) = 1.
    EXPECT_NEAR(L1Norm(q), 1.0, 1e-9);
  }
}

TEST(LtiTest, QNominalInverseBlocksDcAndMatchesContinuousAtLowFrequency) {
  const ContinuousTf c = QNominalInverse(30.0, 2, 0.2621, 3.0);
  const DiscreteTf d = Discretize(c, 1e-3, Discretization::kTustin);
  EXPECT_NEAR(d.DcGain(), 0.0, 1e-9);
  for (double f : {0.5, 2.0, 5.0}) {
    const double w = 2.0 * kPi * f;
    const auto hc = c.FrequencyResponse(w), hd = d.FrequencyResponse(w);
    // Tustin's frequency warping: relative error ≈ (ωT)²/12.
    EXPECT_NEAR(std::abs(hd - hc) / std::abs(hc), 0.0, 2e-3) << f;
  }
  // Well below the cut-off it is M_n s² + B_n s: |1 − Q| ≈ 2f/f_q = 3.3 % at 0.5 Hz.
  const std::complex<double> s(0.0, 2.0 * kPi * 0.5);
  const auto hc = c.Evaluate(s);
  EXPECT_NEAR(std::abs(hc - (0.2621 * s * s + 3.0 * s)) / std::abs(hc), 0.0, 0.04);
  EXPECT_THROW(QNominalInverse(30.0, 1, 0.2621, 3.0), std::invalid_argument);
}

TEST(LtiTest, VelocityEstimatorDifferentiatesARampAndHasClosedFormL1Norm) {
  const double ts = 1e-3, fc = 100.0, a = std::exp(-2.0 * kPi * fc * ts);
  const DiscreteTf f = VelocityEstimatorFilter(fc, ts);
  double state[1] = {0.0};
  double v = 0.0;
  for (int k = 0; k < 200; ++k) {
    const double x = 0.3 * k * ts;  // 0.3 m/s ramp
    v = FilterOutput(f, x, state);
    FilterUpdate(f, x, state);
  }
  EXPECT_NEAR(v, 0.3, 1e-9);
  EXPECT_NEAR(L1Norm(f), 2.0 * (1.0 - a) / ts, 1e-6);
}

TEST(LtiTest, SteadyStateStartHasNoTransient) {
  const DiscreteTf f = Discretize(QNominalInverse(30.0, 2, 0.2621, 3.0), 1e-3, Discretization::kTustin);
  double state[2];
  FilterSteadyState(f, -0.35, state);
  for (int k = 0; k < 10; ++k) {
    EXPECT_NEAR(FilterOutput(f, -0.35, state), 0.0, 1e-9);
    FilterUpdate(f, -0.35, state);
  }
}

TEST(LtiTest, ImpulseResponseAndErrors) {
  const DiscreteTf f = Discretize(BinomialLowPass(10.0, 1), 1e-3, Discretization::kZeroOrderHold);
  const Eigen::VectorXd h = ImpulseResponse(f, 3);
  EXPECT_EQ(h(0), 0.0);
  EXPECT_NEAR(h(2) / h(1), -f.a(1), 1e-15);
  DiscreteTf integrator{Eigen::Vector2d(0.0, 1.0), Eigen::Vector2d(1.0, -1.0), 1e-3};
  try {
    L1Norm(integrator);
    FAIL() << "expected a throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("not stable"), std::string::npos) << e.what();
  }
  try {
    Discretize(ContinuousTf{Eigen::Vector3d(1.0, 0.0, 0.0), Eigen::Vector2d(1.0, 1.0)}, 1e-3,
               Discretization::kTustin);
    FAIL() << "expected a throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("improper"), std::string::npos) << e.what();
  }
  EXPECT_THROW(ParseDiscretization("bilinear", "q/discretization"), std::invalid_argument);
}

}  // namespace
}  // namespace mb

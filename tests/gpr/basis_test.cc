// The weight-space expansions: Fourier–Bessel weights against std::cyl_bessel_i, the feature
// kernel against the exact kernel, and the basis derivatives against finite differences.
#include "models/gpr/basis.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>
#include <vector>

#include <gtest/gtest.h>

namespace mb {
namespace {

TEST(GprBasis, FourierBesselWeightsMatchStdBessel) {
  for (double l : {0.3, 0.6, 1.0, 2.0, 5.0}) {
    const double z = 1.0 / (l * l);
    const Eigen::VectorXd q2 = PeriodicSpectralWeights(l, 12);
    for (int j = 0; j <= 12; ++j) {
      const double expected = (j == 0 ? 1.0 : 2.0) * std::exp(-z) * std::cyl_bessel_i(j, z);
      EXPECT_NEAR(q2(j), expected, 1e-14 + 1e-12 * expected) << "l = " << l << ", j = " << j;
    }
  }
  // Very short length scale (z = 400): e^{-z} I_0(z) is fine in the scaled recurrence.
  const Eigen::VectorXd q2 = PeriodicSpectralWeights(0.05, 400);
  EXPECT_NEAR(q2.sum(), 1.0, 1e-12);
  EXPECT_NEAR(q2(0), 1.0 / std::sqrt(2.0 * std::numbers::pi * 400.0), 1e-4);  // asymptotic I_0
}

TEST(GprBasis, FourierBesselLengthScaleDerivativeMatchesFiniteDifferences) {
  for (double l : {0.2, 1.0, 3.0}) {
    Eigen::VectorXd dlog;
    const Eigen::VectorXd q2 = PeriodicSpectralWeights(l, 8, &dlog);
    const double h = 1e-6;
    const Eigen::VectorXd plus = PeriodicSpectralWeights(l * std::exp(h), 8);
    const Eigen::VectorXd minus = PeriodicSpectralWeights(l * std::exp(-h), 8);
    for (int j = 0; j <= 8; ++j) {
      const double fd = (std::log(plus(j)) - std::log(minus(j))) / (2.0 * h);
      EXPECT_NEAR(dlog(j), fd, 1e-6 * (1.0 + std::abs(fd))) << "l = " << l << ", j = " << j;
    }
  }
}

TEST(GprBasis, HarmonicCountMeetsTolerance) {
  const int j = PeriodicHarmonicsForTolerance(1.0, 1e-12);
  const Eigen::VectorXd q2 = PeriodicSpectralWeights(1.0, j);
  EXPECT_LE(1.0 - q2.sum(), 1e-12 + 1e-15);
  EXPECT_GT(1.0 - PeriodicSpectralWeights(1.0, j - 1).sum(), 1e-12);
  EXPECT_GE(j, 8);  // DESIGN.md: about 11 harmonics at ℓ = 1, 1e-12
  EXPECT_LE(j, 13);
}

// Σ s_k ψ_k(a) ψ_k(b) against TisoKernel for inputs inside the trained ranges.
void ExpectFeatureKernelMatches(GprKernel kernel, const GprHyperparameters& hp, double tolerance) {
  const GprRange xr{0.1, 0.325};
  const GprRange vr{0.05, 0.5};
  const GprBasis basis = ChooseGprBasis(kernel, hp, xr, vr, tolerance);
  Eigen::VectorXd s;
  GprSpectralWeights(basis, hp, &s);
  const int m = GprFeatureCount(basis);
  std::vector<double> pa(static_cast<std::size_t>(m)), pb(static_cast<std::size_t>(m));
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> ux(xr.min, xr.max), uv(vr.min, vr.max);
  double worst = 0.0;
  for (int trial = 0; trial < 200; ++trial) {
    const double xa = ux(rng), va = uv(rng), xb = ux(rng), vb = uv(rng);
    EvaluateGprBasis(basis, xa, va, pa.data());
    EvaluateGprBasis(basis, xb, vb, pb.data());
    double approx = 0.0;
    for (int k = 0; k < m; ++k) approx += s(k) * pa[static_cast<std::size_t>(k)] * pb[static_cast<std::size_t>(k)];
    worst = std::max(worst, std::abs(approx - TisoKernel(kernel, hp, xa, va, xb, vb)));
  }
  const double scale = hp.signal_variance_x + hp.signal_variance_xdot;
  EXPECT_LT(worst, 20.0 * tolerance * scale + 1e-14 * m * scale)
      << GprKernelName(kernel) << " with " << m << " features";
}

TEST(GprBasis, FeatureKernelMatchesExactKernel) {
  GprHyperparameters hp;
  hp.signal_variance_x = 0.5;
  hp.length_scale_x = 0.9;
  hp.signal_variance_xdot = 0.3;
  hp.length_scale_xdot = 0.15;
  for (double tol : {1e-6, 1e-12}) ExpectFeatureKernelMatches(GprKernel::kPeriodicSe, hp, tol);
  hp.length_scale_x = 0.006;
  for (double tol : {1e-6, 1e-12}) ExpectFeatureKernelMatches(GprKernel::kSeSe, hp, tol);
}

TEST(GprBasis, DerivativesMatchFiniteDifferences) {
  GprHyperparameters hp;
  hp.length_scale_x = 0.7;
  hp.length_scale_xdot = 0.2;
  for (GprKernel kernel : {GprKernel::kPeriodicSe, GprKernel::kSeSe}) {
    if (kernel == GprKernel::kSeSe) hp.length_scale_x = 0.01;
    const GprBasis basis = ChooseGprBasis(kernel, hp, {0.0, 0.2}, {0.05, 0.5}, 1e-8);
    const auto m = static_cast<std::size_t>(GprFeatureCount(basis));
    std::vector<double> dx(m), dv(m), dtau(m), plus(m), minus(m);
    const double x = 0.0731, v = 0.233, h = 1e-7;
    EvaluateGprBasisDerivatives(basis, x, v, dx.data(), dv.data());
    EvaluateGprBasisPeriodDerivative(basis, x, dtau.data());
    EvaluateGprBasis(basis, x + h, v, plus.data());
    EvaluateGprBasis(basis, x - h, v, minus.data());
    for (std::size_t k = 0; k < m; ++k) {
      EXPECT_NEAR(dx[k], (plus[k] - minus[k]) / (2 * h), 1e-5 * (1 + std::abs(dx[k]))) << k;
    }
    EvaluateGprBasis(basis, x, v + h, plus.data());
    EvaluateGprBasis(basis, x, v - h, minus.data());
    for (std::size_t k = 0; k < m; ++k) {
      EXPECT_NEAR(dv[k], (plus[k] - minus[k]) / (2 * h), 1e-5 * (1 + std::abs(dv[k]))) << k;
    }
    GprBasis moved_up = basis, moved_down = basis;
    moved_up.period += h;
    moved_down.period -= h;
    EvaluateGprBasis(moved_up, x, v, plus.data());
    EvaluateGprBasis(moved_down, x, v, minus.data());
    for (std::size_t k = 0; k < m; ++k) {
      EXPECT_NEAR(dtau[k], (plus[k] - minus[k]) / (2 * h), 1e-4 * (1 + std::abs(dtau[k]))) << k;
    }
    // DotGprBasis is ψᵀβ.
    std::vector<double> psi(m), beta(m);
    for (std::size_t k = 0; k < m; ++k) beta[k] = std::sin(1.0 + static_cast<double>(k));
    EvaluateGprBasis(basis, x, v, psi.data());
    double dot = 0.0;
    for (std::size_t k = 0; k < m; ++k) dot += psi[k] * beta[k];
    EXPECT_NEAR(DotGprBasis(basis, beta.data(), x, v), dot, 1e-13 * static_cast<double>(m));
  }
}

TEST(GprBasis, SpectralWeightDerivativesMatchFiniteDifferences) {
  GprHyperparameters hp;
  hp.signal_variance_x = 0.8;
  hp.length_scale_x = 0.9;
  hp.signal_variance_xdot = 0.2;
  hp.length_scale_xdot = 0.1;
  const GprBasis basis = ChooseGprBasis(GprKernel::kPeriodicSe, hp, {0, 0.2}, {0.05, 0.5}, 1e-10);
  Eigen::VectorXd s;
  Eigen::MatrixXd dlog;
  GprSpectralWeights(basis, hp, &s, &dlog);
  const Eigen::VectorXd theta = ToLogParameters(hp);
  for (int p : {kLogSignalVarianceX, kLogLengthScaleX, kLogSignalVarianceXdot, kLogLengthScaleXdot}) {
    Eigen::VectorXd plus = theta, minus = theta;
    plus(p) += 1e-6;
    minus(p) -= 1e-6;
    Eigen::VectorXd sp, sm;
    GprSpectralWeights(basis, FromLogParameters(plus), &sp);
    GprSpectralWeights(basis, FromLogParameters(minus), &sm);
    for (Eigen::Index k = 0; k < s.size(); ++k) {
      if (s(k) < 1e-200) continue;
      const double fd = (std::log(sp(k)) - std::log(sm(k))) / 2e-6;
      EXPECT_NEAR(dlog(k, p), fd, 1e-5 * (1 + std::abs(fd))) << GprParameterName(p) << " k=" << k;
    }
  }
}

// The features come from recurrences (rotation for the periodic pairs, Chebyshev for the Hilbert
// sines) started from one bounded-range sincos; every harmonic must still equal its definition.
// Inputs include both ends of the Hilbert domain, where the Chebyshev recurrence loses most.
TEST(GprBasis, FeaturesEqualTheirDefinitionsHarmonicByHarmonic) {
  constexpr double kPi = 3.14159265358979323846;
  GprBasis basis;
  basis.kernel = GprKernel::kPeriodicSe;
  basis.period = 0.0225;
  basis.harmonics = 61;
  basis.xdot_domain = {0.2, 0.35, 203};
  const int p = GprPositionFeatureCount(basis);
  std::vector<double> psi(static_cast<std::size_t>(GprFeatureCount(basis)));
  const double inputs[][2] = {{0.0, 0.2}, {0.1234, -0.15 + 1e-9}, {-0.31, 0.55 - 1e-9},
                              {0.0225 * 7 - 1e-12, 0.37}, {0.01, 0.2 + 0.35 * 0.999}};
  double worst = 0.0;
  for (const auto& in : inputs) {
    const double x = in[0];
    const double v = in[1];
    EvaluateGprBasis(basis, x, v, psi.data());
    EXPECT_EQ(psi[0], 1.0);
    for (int j = 1; j <= basis.harmonics; ++j) {
      const double phase = 2.0 * kPi * j * x / basis.period;
      worst = std::max(worst, std::abs(psi[static_cast<std::size_t>(2 * j - 1)] - std::cos(phase)));
      worst = std::max(worst, std::abs(psi[static_cast<std::size_t>(2 * j)] - std::sin(phase)));
    }
    const HilbertDomain& d = basis.xdot_domain;
    for (int j = 1; j <= d.count; ++j) {
      const double want =
          std::sin(kPi * j * (v - d.center + d.half_width) / (2.0 * d.half_width)) /
          std::sqrt(d.half_width);
      worst = std::max(worst, std::abs(psi[static_cast<std::size_t>(p + j - 1)] - want));
    }
  }
  EXPECT_LT(worst, 1e-11) << "largest deviation from libm over all features";
}

TEST(GprBasis, TooManyFeaturesIsAClearError) {
  GprHyperparameters hp;
  hp.length_scale_x = 1e-5;  // "DS" position length scale far below the range
  try {
    ChooseGprBasis(GprKernel::kSeSe, hp, {0.0, 0.7}, {0.0, 0.5}, 1e-12);
    FAIL() << "expected std::runtime_error";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("raise the lower bound of the length scale"),
              std::string::npos)
        << e.what();
  }
  EXPECT_THROW(PeriodicSpectralWeights(-1.0, 3), std::invalid_argument);
  EXPECT_THROW(HilbertDomainForTolerance({1.0, 0.0}, 0.1, 1e-6), std::invalid_argument);
}

}  // namespace
}  // namespace mb

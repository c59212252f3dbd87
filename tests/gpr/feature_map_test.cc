// The real-time feature map (models/gpr/feature_map.h) and GprModel's queries built on it, against the
// straightforward formulas: every feature by its own std::sin/std::cos, ψᵀβ and ψᵀΣψ as plain sums.
#include "models/gpr/feature_map.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <utility>
#include <vector>

#include <gtest/gtest.h>

#include "models/gpr/gpr_model.h"

namespace mb {
namespace {

constexpr double kPi = std::numbers::pi;
const GprRange kXRange{0.1, 0.325};
const GprRange kVRange{0.05, 0.5};

// basis.h's definitions, one library call per feature.
std::vector<double> DirectFeatures(const GprBasis& basis, double x, double xdot) {
  std::vector<double> psi;
  const auto hilbert = [&psi](const HilbertDomain& d, double u) {
    const bool inside = std::abs(u - d.center) <= d.half_width;
    for (int j = 1; j <= d.count; ++j) {
      psi.push_back(inside ? std::sin(kPi * j * (u - d.center + d.half_width) / (2.0 * d.half_width)) /
                                 std::sqrt(d.half_width)
                           : 0.0);
    }
  };
  if (basis.kernel == GprKernel::kPeriodicSe) {
    psi.push_back(1.0);
    for (int j = 1; j <= basis.harmonics; ++j) {
      psi.push_back(std::cos(2.0 * kPi * j * x / basis.period));
      psi.push_back(std::sin(2.0 * kPi * j * x / basis.period));
    }
  } else {
    hilbert(basis.x_domain, x);
  }
  hilbert(basis.xdot_domain, xdot);
  return psi;
}

GprBasis TestBasis(GprKernel kernel, double length_scale_x, double length_scale_xdot) {
  GprHyperparameters hp;
  hp.length_scale_x = length_scale_x;
  hp.length_scale_xdot = length_scale_xdot;
  return ChooseGprBasis(kernel, hp, kXRange, kVRange, 1e-10);
}

// A model over `basis` with random weights and a random positive definite covariance (not a fit: the
// test is of the arithmetic, for any posterior).
GprModel RandomModel(const GprBasis& basis, std::mt19937& rng) {
  std::normal_distribution<double> normal;
  const Eigen::Index m = GprFeatureCount(basis);
  GprModelData data;
  data.kernel = basis.kernel;
  data.hyperparameters.period = basis.period;
  data.basis = basis;
  data.mean = 0.7;
  data.x_range = kXRange;
  data.xdot_range = kVRange;
  data.weights.resize(m);
  for (Eigen::Index k = 0; k < m; ++k) data.weights(k) = normal(rng);
  Eigen::MatrixXd a(m, m);
  for (Eigen::Index k = 0; k < a.size(); ++k) a.data()[k] = normal(rng);
  data.weight_covariance = a * a.transpose() / static_cast<double>(m) + 1e-3 * Eigen::MatrixXd::Identity(m, m);
  return GprModel(std::move(data));
}

struct Case {
  GprKernel kernel;
  double length_scale_x, length_scale_xdot;
};
const Case kCases[] = {{GprKernel::kPeriodicSe, 1.0, 0.2}, {GprKernel::kPeriodicSe, 0.3, 0.05},
                       {GprKernel::kSeSe, 0.05, 0.2}, {GprKernel::kSeSe, 0.02, 0.03}};

TEST(GprFeatureMap, FeaturesMatchTheDirectFormulas) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> x_of(-0.5, 1.0);  // beyond the trained ranges too
  std::uniform_real_distribution<double> v_of(-0.5, 1.0);
  for (const Case& c : kCases) {
    const GprBasis basis = TestBasis(c.kernel, c.length_scale_x, c.length_scale_xdot);
    const GprFeatureMap map(basis);
    ASSERT_EQ(map.feature_count(), GprFeatureCount(basis));
    GprFeatureBuffer psi;
    std::vector<double> reference(static_cast<std::size_t>(GprFeatureCount(basis)));
    std::normal_distribution<double> normal;
    Eigen::VectorXd beta(GprFeatureCount(basis));
    for (Eigen::Index k = 0; k < beta.size(); ++k) beta(k) = normal(rng);
    const GprPackedWeights packed(map.constants(), beta.data());
    GprFeatureBuffer psi_packed;
    for (int i = 0; i < 500; ++i) {
      const double x = x_of(rng);
      const double v = v_of(rng);
      const double dot = map.EvaluateAndDot(beta.data(), x, v, psi.values);
      EXPECT_EQ(dot, map.Dot(beta.data(), x, v)) << "EvaluateAndDot and Dot give the same bits";
      EXPECT_EQ(dot, map.Dot(packed, x, v)) << "the packed β gives the same bits";
      EXPECT_EQ(dot, map.EvaluateAndDot(packed, x, v, psi_packed.values));
      for (int k = 0; k < map.feature_count(); ++k) ASSERT_EQ(psi_packed.values[k], psi.values[k]);
      EvaluateGprBasis(basis, x, v, reference.data());
      const std::vector<double> direct = DirectFeatures(basis, x, v);
      for (std::size_t k = 0; k < direct.size(); ++k) {
        // Features are O(1) (Hilbert: O(L^−1/2)); the recurrences lose a few ulps per harmonic: basis_test's bound
        // against libm, 1e-11 (measured 1.04e-12 at the 46th PS feature in the ASan build, under 1e-12 in Release).
        ASSERT_NEAR(psi.values[k], direct[k], 1e-11) << GprKernelName(c.kernel) << " k = " << k << " x = " << x;
        // EvaluateGprBasis's four-lane Chebyshev recurrence drifts by up to ~(m/4)²·eps (basis_test's bound
        // against libm is 1e-11; measured 1.06e-12 here), more than the eight-lane one.
        ASSERT_NEAR(psi.values[k], reference[k], 1e-11) << GprKernelName(c.kernel) << " k = " << k;
      }
    }
  }
}

TEST(GprFeatureMap, PredictionsMatchTheStraightforwardFormulas) {
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> x_of(-0.2, 0.6);
  std::uniform_real_distribution<double> v_of(0.0, 0.55);
  for (const Case& c : kCases) {
    const GprBasis basis = TestBasis(c.kernel, c.length_scale_x, c.length_scale_xdot);
    const GprModel model = RandomModel(basis, rng);
    const GprModelData& data = model.data();
    // A copy of the fitted posterior at other addresses: Predict reads it unpacked (the online learner's path).
    const Eigen::VectorXd weights_copy = data.weights;
    const Eigen::MatrixXd covariance_copy = data.weight_covariance;
    const GprPosteriorView copy{weights_copy.data(), covariance_copy.data()};
    const double prior_variance = data.hyperparameters.signal_variance_x + data.hyperparameters.signal_variance_xdot;
    for (int i = 0; i < 300; ++i) {
      const double x = x_of(rng);
      const double v = v_of(rng);
      const std::vector<double> psi_direct = DirectFeatures(basis, x, std::clamp(v, kVRange.min, kVRange.max));
      const Eigen::Map<const Eigen::VectorXd> psi(psi_direct.data(), static_cast<Eigen::Index>(psi_direct.size()));
      // eq. 22/24 and eq. 23 (gpr_model.h) as written, with the full matrix.
      const double expected_mean = data.mean + psi.dot(data.weights);
      const double mean_scale = std::abs(data.mean) + psi.cwiseProduct(data.weights).cwiseAbs().sum();
      const double quadratic = psi.dot(data.weight_covariance * psi);
      // Round-off scale of ψᵀΣψ: Σ_ij |ψ_i Σ_ij ψ_j| (the sum can cancel).
      const double quadratic_scale = psi.cwiseAbs().dot(data.weight_covariance.cwiseAbs() * psi.cwiseAbs());
      const double represented = psi.cwiseAbs2().dot(model.spectral_weights());
      const double expected_std = std::sqrt(std::max(quadratic, 0.0) + std::max(prior_variance - represented, 0.0));
      const double fast_mean = model.PredictPosteriorMean(x, v);
      double mean = 0.0;
      double std = 0.0;
      model.Predict(x, v, &mean, &std);
      EXPECT_NEAR(fast_mean, expected_mean, 1e-12 * mean_scale) << GprKernelName(c.kernel) << " x = " << x;
      EXPECT_EQ(mean, fast_mean) << "Predict and PredictPosteriorMean give the same bits";
      EXPECT_NEAR(std * std, expected_std * expected_std, 1e-12 * (quadratic_scale + prior_variance))
          << GprKernelName(c.kernel) << " x = " << x;
      EXPECT_NEAR(std, expected_std, 1e-12 * expected_std) << GprKernelName(c.kernel) << " x = " << x;
      double mean_unpacked = 0.0;
      double std_unpacked = 0.0;
      model.Predict(copy, x, v, &mean_unpacked, &std_unpacked);
      EXPECT_EQ(mean_unpacked, mean);
      EXPECT_NEAR(std_unpacked, expected_std, 1e-12 * expected_std) << GprKernelName(c.kernel) << " (unpacked)";
    }
  }
}

// The "DS" covariance as cosine series and a cross block (GprSeriesCovariance): the quadratic form of the
// matrix to round-off, inside and outside the Hilbert domains.
TEST(GprFeatureMap, SeriesQuadraticFormEqualsTheMatrixOne) {
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> x_of(-0.2, 0.6);
  std::uniform_real_distribution<double> v_of(0.0, 0.55);
  for (const Case& c : kCases) {
    if (c.kernel != GprKernel::kSeSe) continue;
    const GprBasis basis = TestBasis(c.kernel, c.length_scale_x, c.length_scale_xdot);
    const GprModel model = RandomModel(basis, rng);
    const GprFeatureMap& map = model.feature_map();
    const Eigen::MatrixXd& cov = model.data().weight_covariance;
    const GprSeriesCovariance series(map.constants(), cov);
    GprFeatureBuffer psi;
    for (int i = 0; i < 300; ++i) {
      const double x = x_of(rng);
      const double v = v_of(rng);
      map.EvaluateAndDot(model.data().weights.data(), x, v, psi.values);
      const Eigen::Map<const Eigen::VectorXd> p(psi.values, map.feature_count());
      const double scale = p.cwiseAbs().dot(cov.cwiseAbs() * p.cwiseAbs());
      EXPECT_NEAR(map.QuadraticForm(series, x, v, psi), p.dot(cov * p), 1e-12 * scale) << "x = " << x << " v = " << v;
    }
  }
}

// The map runs the widest kernels the CPU has; the others run on other machines (CI runners without AVX-512, the
// baseline anywhere). Every set this CPU supports gives the widest set's results to round-off.
TEST(GprFeatureMap, EveryInstructionSetGivesTheSameResults) {
  std::mt19937 rng(13);
  std::uniform_real_distribution<double> x_of(-0.2, 0.6);
  std::uniform_real_distribution<double> v_of(0.05, 0.5);
  for (const Case& c : kCases) {
    const GprBasis basis = TestBasis(c.kernel, c.length_scale_x, c.length_scale_xdot);
    const GprModel model = RandomModel(basis, rng);
    const GprModelData& data = model.data();
    const GprFeatureMap widest(basis);
    const GprPackedWeights packed(widest.constants(), data.weights.data());
    const GprPackedLowerTriangle packed_covariance(data.weight_covariance);
    const GprSeriesCovariance series(widest.constants(), data.weight_covariance);
    const int m = widest.feature_count();
    int sets = 0;
    for (const char* name : {"baseline", "avx2_fma", "avx512f"}) {
      GprFeatureMap map(basis);
      if (!map.UseInstructionSet(name)) continue;
      ++sets;
      EXPECT_STREQ(map.instruction_set(), name);
      GprFeatureBuffer psi;
      GprFeatureBuffer reference;
      for (int i = 0; i < 100; ++i) {
        const double x = x_of(rng);
        const double v = v_of(rng);
        const double dot = map.EvaluateAndDot(packed, x, v, psi.values);
        const double expected_dot = widest.EvaluateAndDot(packed, x, v, reference.values);
        EXPECT_EQ(map.Dot(data.weights.data(), x, v), dot) << name;
        const Eigen::Map<const Eigen::VectorXd> p(reference.values, m);
        EXPECT_NEAR(dot, expected_dot, 1e-12 * p.cwiseProduct(data.weights).cwiseAbs().sum()) << name;
        for (int k = 0; k < m; ++k) ASSERT_NEAR(psi.values[k], reference.values[k], 1e-13) << name << " k = " << k;
        const double scale = p.cwiseAbs().dot(data.weight_covariance.cwiseAbs() * p.cwiseAbs());
        const double expected = widest.QuadraticForm(data.weight_covariance.data(), reference.values);
        EXPECT_NEAR(map.QuadraticForm(data.weight_covariance.data(), psi.values), expected, 1e-12 * scale) << name;
        EXPECT_NEAR(map.QuadraticForm(packed_covariance, psi), expected, 1e-12 * scale) << name;
        if (c.kernel == GprKernel::kSeSe) {
          EXPECT_NEAR(map.QuadraticForm(series, x, v, psi), expected, 1e-12 * scale) << name;
        }
        EXPECT_NEAR(map.WeightedSquares(model.spectral_weights().data(), psi.values),
                    widest.WeightedSquares(model.spectral_weights().data(), reference.values),
                    1e-12 * p.cwiseAbs2().dot(model.spectral_weights()))
            << name;
      }
    }
    EXPECT_GE(sets, 1) << "the baseline is always there";
    GprFeatureMap map(basis);
    EXPECT_FALSE(map.UseInstructionSet("sse9"));
    EXPECT_STREQ(map.instruction_set(), widest.instruction_set());
  }
}

TEST(GprFeatureMap, QuadraticFormReadsOnlyTheLowerTriangle) {
  std::mt19937 rng(3);
  const GprBasis basis = TestBasis(GprKernel::kSeSe, 0.05, 0.2);
  const GprModel model = RandomModel(basis, rng);
  const GprFeatureMap map(basis);
  GprFeatureBuffer psi;
  map.EvaluateAndDot(model.data().weights.data(), 0.2, 0.3, psi.values);
  Eigen::MatrixXd cov = model.data().weight_covariance;
  const double expected = map.QuadraticForm(cov.data(), psi.values);
  const double expected_packed = map.QuadraticForm(GprPackedLowerTriangle(cov), psi);
  cov.triangularView<Eigen::StrictlyUpper>().setConstant(std::nan(""));
  EXPECT_EQ(map.QuadraticForm(cov.data(), psi.values), expected);
  EXPECT_EQ(map.QuadraticForm(GprPackedLowerTriangle(cov), psi), expected_packed);
  EXPECT_NEAR(expected_packed, expected, 1e-12 * expected);
  EXPECT_GT(expected, 0.0);
}

}  // namespace
}  // namespace mb

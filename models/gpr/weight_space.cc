#include "models/gpr/weight_space.h"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

#include <Eigen/Cholesky>

namespace mb {
namespace {

constexpr Eigen::Index kBlockRows = 256;
using RowMatrix = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>;

// Everything an evaluation at one hp needs: D, A = DGD + σ²I factorised, a = A⁻¹b.
struct Solved {
  Eigen::VectorXd d;
  Eigen::MatrixXd dlog_s;
  Eigen::LLT<Eigen::MatrixXd> llt;
  Eigen::VectorXd b;
  Eigen::VectorXd a;
  double log_marginal_likelihood = 0.0;
};

Solved Solve(const GprFeatureStatistics& stats, const GprHyperparameters& hp, bool want_dlog) {
  Solved out;
  Eigen::VectorXd s;
  GprSpectralWeights(stats.basis, hp, &s, want_dlog ? &out.dlog_s : nullptr);
  out.d = s.cwiseSqrt();
  const double noise = hp.noise_variance;
  Eigen::MatrixXd a_matrix = out.d.asDiagonal() * stats.gram * out.d.asDiagonal();
  a_matrix.diagonal().array() += noise;
  out.llt.compute(a_matrix);
  if (out.llt.info() != Eigen::Success) {
    throw std::runtime_error("weight-space GP: ΦᵀΦ + noise_variance·I is not positive definite at "
                             "noise_variance = " + std::to_string(noise) +
                             ": raise the noise variance (or its lower bound)");
  }
  out.b = out.d.cwiseProduct(stats.projection);
  out.a = out.llt.solve(out.b);
  const double n = static_cast<double>(stats.count);
  const double m = static_cast<double>(stats.gram.rows());
  const double quad = stats.sum_squares - out.b.dot(out.a);
  const double log_det_a = 2.0 * out.llt.matrixLLT().diagonal().array().log().sum();
  out.log_marginal_likelihood = -0.5 * quad / noise - 0.5 * (n - m) * std::log(noise) -
                                0.5 * log_det_a - 0.5 * n * std::log(2.0 * std::numbers::pi);
  return out;
}

}  // namespace

GprFeatureStatistics AccumulateGprFeatureStatistics(const GprBasis& basis,
                                                    const Eigen::Ref<const Eigen::VectorXd>& x,
                                                    const Eigen::Ref<const Eigen::VectorXd>& xdot,
                                                    const Eigen::Ref<const Eigen::VectorXd>& y,
                                                    bool period_derivative) {
  if (x.size() != xdot.size() || x.size() != y.size() || x.size() == 0) {
    throw std::invalid_argument(
        "AccumulateGprFeatureStatistics: x, xdot and y must have the same nonzero length (got " +
        std::to_string(x.size()) + ", " + std::to_string(xdot.size()) + ", " +
        std::to_string(y.size()) + ")");
  }
  const Eigen::Index m = GprFeatureCount(basis);
  const bool with_dtau = period_derivative && basis.kernel == GprKernel::kPeriodicSe;
  GprFeatureStatistics stats;
  stats.basis = basis;
  stats.gram.setZero(m, m);
  stats.projection.setZero(m);
  stats.count = x.size();
  stats.has_period_derivative = with_dtau;
  if (with_dtau) {
    stats.gram_dperiod.setZero(m, m);
    stats.projection_dperiod.setZero(m);
  }
  RowMatrix psi(kBlockRows, m);
  RowMatrix dpsi(with_dtau ? kBlockRows : 0, m);
  for (Eigen::Index start = 0; start < x.size(); start += kBlockRows) {
    const Eigen::Index rows = std::min(kBlockRows, x.size() - start);
    for (Eigen::Index r = 0; r < rows; ++r) {
      const Eigen::Index i = start + r;
      if (!std::isfinite(x(i)) || !std::isfinite(xdot(i)) || !std::isfinite(y(i))) {
        throw std::invalid_argument("AccumulateGprFeatureStatistics: sample " + std::to_string(i) +
                                    " is not finite (x = " + std::to_string(x(i)) +
                                    ", xdot = " + std::to_string(xdot(i)) +
                                    ", y = " + std::to_string(y(i)) + "): remove it from the data");
      }
      EvaluateGprBasis(basis, x(i), xdot(i), psi.row(r).data());
      if (with_dtau) EvaluateGprBasisPeriodDerivative(basis, x(i), dpsi.row(r).data());
    }
    const auto block = psi.topRows(rows);
    const auto y_block = y.segment(start, rows);
    stats.gram.selfadjointView<Eigen::Lower>().rankUpdate(block.transpose());
    stats.projection.noalias() += block.transpose() * y_block;
    stats.sum_squares += y_block.squaredNorm();
    if (with_dtau) {
      const auto dblock = dpsi.topRows(rows);
      stats.gram_dperiod.noalias() += dblock.transpose() * block;
      stats.projection_dperiod.noalias() += dblock.transpose() * y_block;
    }
  }
  stats.gram.triangularView<Eigen::StrictlyUpper>() = stats.gram.transpose();
  if (with_dtau) {
    // ∂(ΨᵀΨ)/∂τ = Ψ_τᵀΨ + ΨᵀΨ_τ.
    const Eigen::MatrixXd half = stats.gram_dperiod;
    stats.gram_dperiod = half + half.transpose();
  }
  return stats;
}

double WeightSpaceLogMarginalLikelihood(const GprFeatureStatistics& stats,
                                        const GprHyperparameters& hp,
                                        Eigen::VectorXd* gradient) {
  const Solved sol = Solve(stats, hp, gradient != nullptr);
  if (gradient == nullptr) return sol.log_marginal_likelihood;

  const Eigen::Index m = stats.gram.rows();
  const double noise = hp.noise_variance;
  const double n = static_cast<double>(stats.count);
  const Eigen::MatrixXd a_inv = sol.llt.solve(Eigen::MatrixXd::Identity(m, m));
  const Eigen::VectorXd da = sol.d.cwiseProduct(sol.a);  // D a
  const Eigen::VectorXd g_da = stats.gram * da;          // G D a
  // ∂L/∂d_k = a_k (c_k − (G D a)_k)/σ² − (A⁻¹ D G)_kk.
  const Eigen::MatrixXd dg = sol.d.asDiagonal() * stats.gram;
  const Eigen::VectorXd det_term = (a_inv.array() * dg.array()).colwise().sum().transpose();
  const Eigen::VectorXd dl_dd =
      (sol.a.array() * (stats.projection - g_da).array() / noise).matrix() - det_term;

  gradient->setZero(kGprParameterCount);
  // ∂d_k/∂θ_i = ½ d_k ∂log s_k/∂θ_i.
  const Eigen::VectorXd chain = 0.5 * dl_dd.cwiseProduct(sol.d);
  gradient->noalias() = sol.dlog_s.transpose() * chain;

  const double quad = stats.sum_squares - sol.b.dot(sol.a);
  const double dl_dnoise = 0.5 * quad / (noise * noise) - 0.5 * sol.a.squaredNorm() / noise -
                           0.5 * (n - static_cast<double>(m)) / noise - 0.5 * a_inv.trace();
  (*gradient)(kLogNoiseVariance) = noise * dl_dnoise;

  if (stats.has_period_derivative) {
    // ∂A/∂τ = D G_τ D, ∂b/∂τ = D c_τ.
    const double fit = 2.0 * sol.d.cwiseProduct(stats.projection_dperiod).dot(sol.a) -
                       da.dot(stats.gram_dperiod * da);
    const Eigen::MatrixXd a_dot = sol.d.asDiagonal() * stats.gram_dperiod * sol.d.asDiagonal();
    const double trace = (a_inv.array() * a_dot.array()).sum();
    (*gradient)(kLogPeriod) = hp.period * (0.5 * fit / noise - 0.5 * trace);
  }
  return sol.log_marginal_likelihood;
}

GprWeightPosterior SolveGprWeightPosterior(const GprFeatureStatistics& stats,
                                           const GprHyperparameters& hp) {
  const Solved sol = Solve(stats, hp, false);
  const Eigen::Index m = stats.gram.rows();
  GprWeightPosterior post;
  post.weights = sol.d.cwiseProduct(sol.a);
  const Eigen::MatrixXd a_inv = sol.llt.solve(Eigen::MatrixXd::Identity(m, m));
  const Eigen::MatrixXd cov = hp.noise_variance * (sol.d.asDiagonal() * a_inv * sol.d.asDiagonal());
  post.covariance = 0.5 * (cov + cov.transpose());  // exactly symmetric (the file stores one triangle)
  post.log_marginal_likelihood = sol.log_marginal_likelihood;
  return post;
}

}  // namespace mb

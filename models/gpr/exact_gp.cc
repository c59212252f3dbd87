#include "models/gpr/exact_gp.h"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace mb {
namespace {

void CheckLengths(const char* where, Eigen::Index nx, Eigen::Index nv, Eigen::Index ny) {
  if (nx != nv || nx != ny || nx == 0) {
    throw std::invalid_argument(std::string(where) +
                                ": x, xdot and y must have the same nonzero length (got " +
                                std::to_string(nx) + ", " + std::to_string(nv) + ", " +
                                std::to_string(ny) + ")");
  }
}

Eigen::LLT<Eigen::MatrixXd> FactorizeCovariance(GprKernel kernel, const GprHyperparameters& hp,
                                                const Eigen::Ref<const Eigen::VectorXd>& x,
                                                const Eigen::Ref<const Eigen::VectorXd>& xdot) {
  Eigen::MatrixXd k = TisoKernelMatrix(kernel, hp, x, xdot);
  k.diagonal().array() += hp.noise_variance;
  Eigen::LLT<Eigen::MatrixXd> llt(k);
  if (llt.info() != Eigen::Success) {
    throw std::runtime_error("exact GP: K + noise_variance·I is not positive definite at "
                             "noise_variance = " + std::to_string(hp.noise_variance) +
                             ": raise the noise variance (or its lower bound)");
  }
  return llt;
}

double LogMarginalLikelihood(const Eigen::LLT<Eigen::MatrixXd>& llt,
                             const Eigen::VectorXd& y, const Eigen::VectorXd& alpha) {
  const double n = static_cast<double>(y.size());
  const double log_det_half = llt.matrixLLT().diagonal().array().log().sum();
  return -0.5 * y.dot(alpha) - log_det_half - 0.5 * n * std::log(2.0 * std::numbers::pi);
}

}  // namespace

double ExactLogMarginalLikelihood(GprKernel kernel, const GprHyperparameters& hp,
                                  const Eigen::Ref<const Eigen::VectorXd>& x,
                                  const Eigen::Ref<const Eigen::VectorXd>& xdot,
                                  const Eigen::Ref<const Eigen::VectorXd>& y,
                                  Eigen::VectorXd* gradient) {
  CheckLengths("ExactLogMarginalLikelihood", x.size(), xdot.size(), y.size());
  const Eigen::LLT<Eigen::MatrixXd> llt = FactorizeCovariance(kernel, hp, x, xdot);
  const Eigen::VectorXd yv = y;
  const Eigen::VectorXd alpha = llt.solve(yv);
  const double lml = LogMarginalLikelihood(llt, yv, alpha);
  if (gradient != nullptr) {
    const Eigen::Index n = x.size();
    // W = ααᵀ − K_y⁻¹; ∂L/∂θ_i = ½ Σ_ab W_ab ∂K_ab/∂θ_i (symmetric: off-diagonal pairs twice).
    Eigen::MatrixXd w = llt.solve(Eigen::MatrixXd::Identity(n, n));
    w = alpha * alpha.transpose() - w;
    gradient->setZero(kGprParameterCount);
    for (Eigen::Index j = 0; j < n; ++j) {
      for (Eigen::Index i = j; i < n; ++i) {
        const double weight = (i == j ? 0.5 : 1.0) * w(i, j);
        const auto dk = TisoKernelGradient(kernel, hp, x(i), xdot(i), x(j), xdot(j));
        for (int p = 0; p < kGprParameterCount; ++p) (*gradient)(p) += weight * dk[static_cast<std::size_t>(p)];
      }
    }
    (*gradient)(kLogNoiseVariance) = 0.5 * hp.noise_variance * w.trace();
    if (kernel != GprKernel::kPeriodicSe) (*gradient)(kLogPeriod) = 0.0;
  }
  return lml;
}

ExactGp::ExactGp(GprKernel kernel, const GprHyperparameters& hp,
                 const Eigen::Ref<const Eigen::VectorXd>& x,
                 const Eigen::Ref<const Eigen::VectorXd>& xdot,
                 const Eigen::Ref<const Eigen::VectorXd>& y)
    : kernel_(kernel), hp_(hp), x_(x), xdot_(xdot) {
  CheckLengths("ExactGp", x.size(), xdot.size(), y.size());
  llt_ = FactorizeCovariance(kernel, hp, x, xdot);
  const Eigen::VectorXd yv = y;
  alpha_ = llt_.solve(yv);
  log_marginal_likelihood_ = LogMarginalLikelihood(llt_, yv, alpha_);
}

double ExactGp::PosteriorMean(double x, double xdot) const noexcept {
  double mean = 0.0;
  for (Eigen::Index i = 0; i < x_.size(); ++i) {
    mean += TisoKernel(kernel_, hp_, x, xdot, x_(i), xdot_(i)) * alpha_(i);
  }
  return mean;
}

double ExactGp::PosteriorVariance(double x, double xdot) const {
  Eigen::VectorXd k_star(x_.size());
  for (Eigen::Index i = 0; i < x_.size(); ++i) {
    k_star(i) = TisoKernel(kernel_, hp_, x, xdot, x_(i), xdot_(i));
  }
  const Eigen::VectorXd v = llt_.matrixL().solve(k_star);
  return TisoKernel(kernel_, hp_, x, xdot, x, xdot) - v.squaredNorm();
}

}  // namespace mb

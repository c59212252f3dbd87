// Signal relevance by additive components (signal_relevance.h): each signal's piecewise-linear function fitted on all
// contiguous blocks but one and scored on the one left out.
#include "models/diagnosis/signal_relevance.h"

#include <algorithm>
#include <stdexcept>

#include <Eigen/Dense>
#include <fmt/format.h>

namespace mb {
namespace {

// Hat functions on `knots` knots at the quantiles of z (duplicates merged), plus a constant: N × (k + 1).
Eigen::MatrixXd HatBasis(const Eigen::VectorXd& z, Eigen::Index knots) {
  std::vector<double> sorted(z.data(), z.data() + z.size());
  std::sort(sorted.begin(), sorted.end());
  std::vector<double> at;
  for (Eigen::Index k = 0; k < knots; ++k) {
    const auto i = static_cast<std::size_t>(static_cast<double>(k) / static_cast<double>(knots - 1) *
                                            static_cast<double>(sorted.size() - 1));
    if (at.empty() || sorted[i] > at.back()) at.push_back(sorted[i]);
  }
  const Eigen::Index n = z.size(), k = static_cast<Eigen::Index>(at.size());
  Eigen::MatrixXd x = Eigen::MatrixXd::Zero(n, k + 1);
  x.col(k).setOnes();
  if (k < 2) return x.rightCols(1);
  for (Eigen::Index i = 0; i < n; ++i) {
    const auto upper = std::upper_bound(at.begin(), at.end(), z(i));
    const Eigen::Index j = std::clamp<Eigen::Index>(static_cast<Eigen::Index>(upper - at.begin()) - 1, 0, k - 2);
    const double q = std::clamp((z(i) - at[static_cast<std::size_t>(j)]) /
                                    (at[static_cast<std::size_t>(j) + 1] - at[static_cast<std::size_t>(j)]),
                                0.0, 1.0);
    x(i, j) = 1.0 - q;
    x(i, j + 1) = q;
  }
  return x;
}

// Held-out MSE of r on the columns of x over `folds` contiguous blocks (ridge 1e-9 of the mean diagonal).
double HeldOutMse(const Eigen::MatrixXd& x, const Eigen::VectorXd& r, Eigen::Index folds) {
  const Eigen::Index n = r.size(), p = x.cols();
  std::vector<Eigen::MatrixXd> gram(static_cast<std::size_t>(folds));
  std::vector<Eigen::VectorXd> moment(static_cast<std::size_t>(folds));
  Eigen::MatrixXd total_gram = Eigen::MatrixXd::Zero(p, p);
  Eigen::VectorXd total_moment = Eigen::VectorXd::Zero(p);
  for (Eigen::Index b = 0; b < folds; ++b) {
    const Eigen::Index lo = b * n / folds, hi = (b + 1) * n / folds;
    const auto rows = x.middleRows(lo, hi - lo);
    gram[static_cast<std::size_t>(b)] = rows.transpose() * rows;
    moment[static_cast<std::size_t>(b)] = rows.transpose() * r.segment(lo, hi - lo);
    total_gram += gram[static_cast<std::size_t>(b)];
    total_moment += moment[static_cast<std::size_t>(b)];
  }
  double sse = 0.0;
  for (Eigen::Index b = 0; b < folds; ++b) {
    Eigen::MatrixXd g = total_gram - gram[static_cast<std::size_t>(b)];
    g.diagonal().array() += 1e-9 * std::max(1e-300, g.trace() / static_cast<double>(p));
    const Eigen::VectorXd theta = g.ldlt().solve(total_moment - moment[static_cast<std::size_t>(b)]);
    const Eigen::Index lo = b * n / folds, hi = (b + 1) * n / folds;
    sse += (r.segment(lo, hi - lo) - x.middleRows(lo, hi - lo) * theta).squaredNorm();
  }
  return sse / static_cast<double>(n);
}

}  // namespace

std::vector<SignalRelevance> RankSignalRelevance(const DiagnosisSignals& s, const Eigen::VectorXd& residual,
                                                 Eigen::Index folds, Eigen::Index knots) {
  const Eigen::Index n = s.size();
  if (residual.size() != n) {
    throw std::invalid_argument(fmt::format("RankSignalRelevance: the residual has {} samples, the signals {}",
                                            residual.size(), n));
  }
  folds = std::max<Eigen::Index>(2, folds);
  knots = std::max<Eigen::Index>(2, knots);
  const double mse0 = HeldOutMse(Eigen::MatrixXd::Ones(n, 1), residual, folds);
  std::vector<SignalRelevance> out;
  if (!(mse0 > 0.0)) return out;
  const auto add = [&](const std::string& name, const Eigen::MatrixXd& x) {
    out.push_back({name, std::max(0.0, 1.0 - HeldOutMse(x, residual, folds) / mse0)});
  };
  const auto varies = [](const Eigen::VectorXd& z) { return z.size() > 0 && z.maxCoeff() > z.minCoeff(); };
  if (varies(s.position)) add("position", HatBasis(s.position, knots));
  if (varies(s.velocity)) {
    add("velocity", HatBasis(s.velocity, knots));
    const double band = 0.01 * s.velocity.cwiseAbs().maxCoeff();
    Eigen::MatrixXd direction(n, 3);
    direction.col(0) = (s.velocity.array() > band).cast<double>().matrix();
    direction.col(1) = (s.velocity.array() < -band).cast<double>().matrix();
    direction.col(2).setOnes();
    add("direction of travel", direction);
  }
  if (varies(s.acceleration)) add("acceleration", HatBasis(s.acceleration, knots));
  if (varies(s.model_output)) add("model force", HatBasis(s.model_output, knots));
  add("time", HatBasis(s.time, knots));
  for (std::size_t k = 0; k < s.extra_columns.size(); ++k) {
    if (varies(s.extra_columns[k])) add(s.extra_names[k], HatBasis(s.extra_columns[k], knots));
  }
  std::stable_sort(out.begin(), out.end(),
                   [](const SignalRelevance& a, const SignalRelevance& b) { return a.heldout_share > b.heldout_share; });
  return out;
}

std::string DescribeRelevance(const std::vector<SignalRelevance>& relevance, double min_share) {
  std::string on, off;
  for (const SignalRelevance& r : relevance) {
    std::string& list = r.heldout_share >= min_share ? on : off;
    list += fmt::format("{}{} ({:.1f} %)", list.empty() ? "" : ", ", r.signal, 100.0 * r.heldout_share);
  }
  if (on.empty()) return fmt::format("depends on none of the signals alone (each below {:.0f} %: {})", 100.0 * min_share, off);
  return fmt::format("depends on {}{}", on, off.empty() ? "" : "; not on " + off);
}

}  // namespace mb

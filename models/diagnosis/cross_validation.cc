// Contiguous-block cross-validation (DiagnoseMissingEffects, steps 3–4): the record split into k contiguous time
// blocks; for a set S of regressor columns the held-out error Σ_blocks ‖r_b − X_b(S)·θ_{−b}‖²/N, θ_{−b} fitted by
// least squares on the other blocks, computed from per-block Gram matrices (ridge 1e-9 for collinear columns).
// Contiguous blocks rather than random folds: the residual is autocorrelated, and a random split would let a column
// fit the noise of a held-out sample's neighbours. Source: DIAGNOSIS.md, "Naming the missing effect", step 3; the
// algorithm in diagnosis.h, step 3.
#include "models/diagnosis/cross_validation.h"

#include <algorithm>
#include <cstddef>
#include <stdexcept>
#include <utility>

#include <Eigen/Dense>
#include <fmt/format.h>

namespace mb::diagnosis_detail {

BlockGrams::BlockGrams(const RegressorMatrix& m, Eigen::Index folds) {
  constexpr Eigen::Index kChunk = 1024;  // rows per chunk: 1024 × q doubles stay in the cache
  const Eigen::Index n = m.rows(), q = m.cols();
  Eigen::MatrixXd chunk;
  for (Eigen::Index b = 0; b < folds; ++b) {
    const Eigen::Index start = b * n / folds, end = (b + 1) * n / folds;
    Eigen::MatrixXd gram = Eigen::MatrixXd::Zero(q, q);
    Eigen::VectorXd xty = Eigen::VectorXd::Zero(q);
    for (Eigen::Index lo = start; lo < end; lo += kChunk) {
      const Eigen::Index count = std::min(kChunk, end - lo);
      m.WeightedRows(lo, count, &chunk);
      gram.selfadjointView<Eigen::Lower>().rankUpdate(chunk.transpose());
      xty.noalias() += chunk.transpose() * m.wr.segment(lo, count);
    }
    gram.triangularView<Eigen::StrictlyUpper>() = gram.transpose();
    gram_.push_back(std::move(gram));
    xty_.push_back(std::move(xty));
    yty_.push_back(m.wr.segment(start, end - start).squaredNorm());
  }
  total_gram_ = Eigen::MatrixXd::Zero(q, q);
  total_xty_ = Eigen::VectorXd::Zero(q);
  for (std::size_t b = 0; b < gram_.size(); ++b) {
    total_gram_ += gram_[b];
    total_xty_ += xty_[b];
    total_yty_ += yty_[b];
  }
  n_ = static_cast<double>(n);
  folds_ = folds;
}

BlockGrams::BlockGrams(const RegressorMatrix& m, Eigen::Index folds, Lazy)
    : source_(&m) {
  const Eigen::Index n = m.rows(), q = m.cols(), p = m.base.cols();
  n_ = static_cast<double>(n);
  folds_ = folds;
  filled_.assign(static_cast<std::size_t>(q), 0);
  group_.assign(static_cast<std::size_t>(q), 0);
  for (std::size_t c = 0; c < m.cands.size(); ++c) {
    for (Eigen::Index j : m.cands[c].idx) group_[static_cast<std::size_t>(j)] = static_cast<Eigen::Index>(c) + 1;
  }
  // The moments: X_bᵀ(√w ⊙ r)_b of the weighted columns √w ⊙ x_j, i.e. x_j · (w ⊙ r) over the block.
  const Eigen::VectorXd sw_wr = m.sw.cwiseProduct(m.wr);
  total_gram_ = Eigen::MatrixXd::Zero(q, q);
  total_xty_ = Eigen::VectorXd::Zero(q);
  for (Eigen::Index b = 0; b < folds; ++b) {
    const Eigen::Index start = b * n / folds, end = (b + 1) * n / folds;
    Eigen::VectorXd xty(q);
    for (Eigen::Index j = 0; j < q; ++j) xty(j) = m.Col(j).segment(start, end - start).dot(sw_wr.segment(start, end - start));
    gram_.push_back(Eigen::MatrixXd::Zero(q, q));
    yty_.push_back(m.wr.segment(start, end - start).squaredNorm());
    total_xty_ += xty;
    total_yty_ += yty_.back();
    xty_.push_back(std::move(xty));
  }
  // Each group's own block: the base's, and each candidate's.
  std::vector<std::vector<Eigen::Index>> groups(m.cands.size() + 1);
  for (Eigen::Index j = 0; j < q; ++j) groups[static_cast<std::size_t>(group_[static_cast<std::size_t>(j)])].push_back(j);
  for (const std::vector<Eigen::Index>& g : groups) {
    const auto k = static_cast<Eigen::Index>(g.size());
    if (k == 0) continue;
    Eigen::MatrixXd w(n, k);
    for (Eigen::Index i = 0; i < k; ++i) w.col(i) = m.sw.cwiseProduct(m.Col(g[static_cast<std::size_t>(i)]));
    for (Eigen::Index b = 0; b < folds; ++b) {
      const Eigen::Index start = b * n / folds, end = (b + 1) * n / folds;
      const Eigen::MatrixXd block = w.middleRows(start, end - start).transpose() * w.middleRows(start, end - start);
      for (Eigen::Index i = 0; i < k; ++i) {
        for (Eigen::Index j = 0; j < k; ++j) {
          const Eigen::Index gi = g[static_cast<std::size_t>(i)], gj = g[static_cast<std::size_t>(j)];
          gram_[static_cast<std::size_t>(b)](gi, gj) = block(i, j);
          total_gram_(gi, gj) += block(i, j);
        }
      }
    }
  }
  // The base is in every fit the ranking makes.
  for (Eigen::Index j = 0; j < p; ++j) FillColumn(j);
}

void BlockGrams::FillColumn(Eigen::Index k) const {
  const RegressorMatrix& m = *source_;
  const Eigen::Index n = m.rows(), q = m.cols();
  const Eigen::VectorXd u = m.sw.cwiseAbs2().cwiseProduct(m.Col(k));  // w ⊙ x_k: (√w x_j)·(√w x_k) = x_j·(w x_k)
  for (Eigen::Index j = 0; j < q; ++j) {
    if (Known(j, k)) continue;
    const auto col = m.Col(j);
    double total = 0.0;
    for (Eigen::Index b = 0; b < folds_; ++b) {
      const Eigen::Index start = b * n / folds_, end = (b + 1) * n / folds_;
      const double g = col.segment(start, end - start).dot(u.segment(start, end - start));
      gram_[static_cast<std::size_t>(b)](j, k) = gram_[static_cast<std::size_t>(b)](k, j) = g;
      total += g;
    }
    total_gram_(j, k) = total_gram_(k, j) = total;
  }
  filled_[static_cast<std::size_t>(k)] = 1;
}

void BlockGrams::Ensure(const std::vector<Eigen::Index>& idx) const {
  if (filled_.empty()) return;
  for (std::size_t a = 0; a < idx.size(); ++a) {
    for (std::size_t b = a + 1; b < idx.size(); ++b) {
      if (Known(idx[a], idx[b])) continue;
      if (source_ == nullptr) {
        throw std::logic_error(fmt::format("BlockGrams: the entry ({}, {}) was never computed and the Grams no longer "
                                           "read their matrix (Detach)", idx[a], idx[b]));
      }
      FillColumn(idx[a]);
      break;
    }
  }
}

Eigen::VectorXd BlockGrams::HeldOutErrors(const std::vector<Eigen::Index>& idx, const RegressorMatrix& m) const {
  Ensure(idx);
  Eigen::VectorXd e = m.wr;
  if (idx.empty()) return e;
  const Eigen::Index n = m.rows();
  for (Eigen::Index b = 0; b < folds_; ++b) {
    const Eigen::Index start = b * n / folds_, end = (b + 1) * n / folds_;
    const auto ub = static_cast<std::size_t>(b);
    const Eigen::VectorXd theta = SolveHeldOut(idx, ub);
    const auto sw = m.sw.segment(start, end - start);
    for (std::size_t j = 0; j < idx.size(); ++j) {
      e.segment(start, end - start) -=
          theta(static_cast<Eigen::Index>(j)) * sw.cwiseProduct(m.Col(idx[j]).segment(start, end - start));
    }
  }
  return e;
}

double BlockGrams::HeldOutMse(const std::vector<Eigen::Index>& idx) const {
  Ensure(idx);
  double sse = 0.0;
  for (std::size_t b = 0; b < gram_.size(); ++b) {
    if (idx.empty()) {
      sse += yty_[b];
      continue;
    }
    const Eigen::VectorXd theta = SolveHeldOut(idx, b);
    sse += yty_[b] - 2.0 * theta.dot(SubVector(xty_[b], idx)) + theta.dot(SubMatrix(gram_[b], idx) * theta);
  }
  return sse / n_;
}

Eigen::VectorXd BlockGrams::Fit(const std::vector<Eigen::Index>& idx, double* sse) const {
  Ensure(idx);
  if (idx.empty()) {
    *sse = total_yty_;
    return {};
  }
  const Eigen::MatrixXd g = SubMatrix(total_gram_, idx);
  const Eigen::VectorXd h = SubVector(total_xty_, idx);
  const Eigen::VectorXd theta = Solve(g, h);
  *sse = std::max(0.0, total_yty_ - 2.0 * theta.dot(h) + theta.dot(g * theta));
  return theta;
}

Eigen::VectorXd BlockGrams::InSampleErrors(const std::vector<Eigen::Index>& idx, const RegressorMatrix& m) const {
  Eigen::VectorXd e = m.wr;
  double sse = 0.0;
  const Eigen::VectorXd theta = Fit(idx, &sse);
  for (std::size_t j = 0; j < idx.size(); ++j) {
    e -= theta(static_cast<Eigen::Index>(j)) * m.sw.cwiseProduct(m.Col(idx[j]));
  }
  return e;
}

BlockGrams BlockGrams::Restrict(const std::vector<Eigen::Index>& idx) const {
  Ensure(idx);
  BlockGrams out;
  for (std::size_t b = 0; b < gram_.size(); ++b) {
    out.gram_.push_back(SubMatrix(gram_[b], idx));
    out.xty_.push_back(SubVector(xty_[b], idx));
  }
  out.yty_ = yty_;
  out.total_gram_ = SubMatrix(total_gram_, idx);
  out.total_xty_ = SubVector(total_xty_, idx);
  out.total_yty_ = total_yty_;
  out.n_ = n_;
  out.folds_ = folds_;
  return out;
}

Eigen::MatrixXd BlockGrams::SubMatrix(const Eigen::MatrixXd& m, const std::vector<Eigen::Index>& idx) {
  Eigen::MatrixXd out(static_cast<Eigen::Index>(idx.size()), static_cast<Eigen::Index>(idx.size()));
  for (std::size_t i = 0; i < idx.size(); ++i)
    for (std::size_t j = 0; j < idx.size(); ++j)
      out(static_cast<Eigen::Index>(i), static_cast<Eigen::Index>(j)) = m(idx[i], idx[j]);
  return out;
}

Eigen::VectorXd BlockGrams::SubVector(const Eigen::VectorXd& v, const std::vector<Eigen::Index>& idx) {
  Eigen::VectorXd out(static_cast<Eigen::Index>(idx.size()));
  for (std::size_t i = 0; i < idx.size(); ++i) out(static_cast<Eigen::Index>(i)) = v(idx[i]);
  return out;
}

Eigen::VectorXd BlockGrams::SolveHeldOut(const std::vector<Eigen::Index>& idx, std::size_t b) const {
  // The submatrices subtracted, not the whole q × q Grams: the same entries, without forming a q × q temporary at
  // every call (q is every candidate's columns, this runs per candidate and block).
  Eigen::MatrixXd g = SubMatrix(total_gram_, idx) - SubMatrix(gram_[b], idx);
  for (std::size_t j = 0; j < idx.size(); ++j) {
    g(static_cast<Eigen::Index>(j), static_cast<Eigen::Index>(j)) += kHeldOutRidge * total_gram_(idx[j], idx[j]);
  }
  return Solve(std::move(g), SubVector(total_xty_, idx) - SubVector(xty_[b], idx));
}

Eigen::VectorXd BlockGrams::Solve(Eigen::MatrixXd g, const Eigen::VectorXd& h) {
  const double ridge = 1e-9 * std::max(1.0, g.trace() / static_cast<double>(g.rows()));
  g.diagonal().array() += ridge;
  return g.ldlt().solve(h);
}

}  // namespace mb::diagnosis_detail

// Block cross-validation (DiagnoseMissingEffects, steps 3–4): the record split into k folds, each of up to
// DiagnosisOptions::fold_segments contiguous time segments spread over the record (segment s in fold s mod k); for a set S of
// regressor columns the held-out error Σ_folds ‖r_b − X_b(S)·θ_{−b}‖²/N, θ_{−b} fitted by least squares on the other
// folds, computed from per-fold Gram matrices (ridge 1e-9 for collinear columns). Contiguous segments rather than
// random samples: the residual is autocorrelated, and a random split would let a column fit the noise of a held-out
// sample's neighbours. Segments spread over the record rather than one block per fold: an effect of time (a step, a
// window, a warm-up) or of a stretch of travel the record visits once is then fitted on both sides of every held-out
// segment, not extrapolated from the rest of the record (a drag that steps in the last fifth had no sample after its
// step to be fitted on, and its held-out gain was nothing; Arlot & Celisse, "A survey of cross-validation procedures
// for model selection", Statistics Surveys 4 (2010), §8.1, blocked and h-block schemes for dependent data). Source: DIAGNOSIS.md, "Naming the missing effect", step 3; the
// algorithm in diagnosis.h, step 3.
#include "models/diagnosis/cross_validation.h"

#include <algorithm>
#include <cstddef>
#include <utility>

#include <Eigen/Dense>

namespace mb::diagnosis_detail {

std::vector<BlockGrams::Segment> BlockGrams::Segments(Eigen::Index n, Eigen::Index folds, Eigen::Index per_fold) {
  per_fold = std::max<Eigen::Index>(1, std::min(per_fold, n / (folds * kMinSegmentRows)));
  const Eigen::Index count = folds * per_fold;
  std::vector<Segment> segments;
  for (Eigen::Index s = 0; s < count; ++s) segments.push_back({s * n / count, (s + 1) * n / count, s % folds});
  return segments;
}

BlockGrams::BlockGrams(const RegressorMatrix& m, const DiagnosisOptions& options) {
  const Eigen::Index folds = options.folds;
  constexpr Eigen::Index kChunk = 1024;  // rows per chunk: 1024 × q doubles stay in the cache
  const Eigen::Index n = m.rows(), q = m.cols();
  gram_.assign(static_cast<std::size_t>(folds), Eigen::MatrixXd::Zero(q, q));
  xty_.assign(static_cast<std::size_t>(folds), Eigen::VectorXd::Zero(q));
  yty_.assign(static_cast<std::size_t>(folds), 0.0);
  segments_ = Segments(n, folds, options.catalogue.loop != nullptr ? 1 : options.fold_segments);
  Eigen::MatrixXd chunk;
  for (const Segment& segment : segments_) {
    const auto b = static_cast<std::size_t>(segment.fold);
    for (Eigen::Index lo = segment.start; lo < segment.end; lo += kChunk) {
      const Eigen::Index count = std::min(kChunk, segment.end - lo);
      m.WeightedRows(lo, count, &chunk);
      gram_[b].selfadjointView<Eigen::Lower>().rankUpdate(chunk.transpose());
      xty_[b].noalias() += chunk.transpose() * m.wr.segment(lo, count);
    }
    yty_[b] += m.wr.segment(segment.start, segment.end - segment.start).squaredNorm();
  }
  for (Eigen::MatrixXd& gram : gram_) gram.triangularView<Eigen::StrictlyUpper>() = gram.transpose();
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

Eigen::VectorXd BlockGrams::HeldOutErrors(const std::vector<Eigen::Index>& idx, const RegressorMatrix& m) const {
  Eigen::VectorXd e = m.wr;
  if (idx.empty()) return e;
  std::vector<Eigen::VectorXd> theta;
  for (Eigen::Index b = 0; b < folds_; ++b) theta.push_back(SolveHeldOut(idx, static_cast<std::size_t>(b)));
  for (const Segment& segment : segments_) {
    const Eigen::Index length = segment.end - segment.start;
    const Eigen::VectorXd& t = theta[static_cast<std::size_t>(segment.fold)];
    const auto sw = m.sw.segment(segment.start, length);
    for (std::size_t j = 0; j < idx.size(); ++j) {
      e.segment(segment.start, length) -=
          t(static_cast<Eigen::Index>(j)) * sw.cwiseProduct(m.Col(idx[j]).segment(segment.start, length));
    }
  }
  return e;
}

double BlockGrams::HeldOutMse(const std::vector<Eigen::Index>& idx) const {
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

BlockGrams BlockGrams::Restrict(const std::vector<Eigen::Index>& idx) const {
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
  out.segments_ = segments_;
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
  Eigen::MatrixXd g = SubMatrix(total_gram_ - gram_[b], idx);
  for (std::size_t j = 0; j < idx.size(); ++j) {
    g(static_cast<Eigen::Index>(j), static_cast<Eigen::Index>(j)) += kHeldOutRidge * total_gram_(idx[j], idx[j]);
  }
  return Solve(std::move(g), SubVector(total_xty_ - xty_[b], idx));
}

Eigen::VectorXd BlockGrams::Solve(Eigen::MatrixXd g, const Eigen::VectorXd& h) {
  const double ridge = 1e-9 * std::max(1.0, g.trace() / static_cast<double>(g.rows()));
  g.diagonal().array() += ridge;
  return g.ldlt().solve(h);
}

}  // namespace mb::diagnosis_detail

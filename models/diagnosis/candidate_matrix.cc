// The candidates' regressor matrix (DiagnoseMissingEffects, step 2): the proposed effects' regressor columns
// (EffectType::regressors) beside the base model's free-parameter regressors, parallel-filtered like the compared
// output when the data are equation-error data, scaled to unit RMS; a candidate that the base's columns already
// reproduce (DiagnosisOptions::redundant_with_base) is in the model and is not ranked. Source: DIAGNOSIS.md, "Naming
// the missing effect", step 3 (a candidate library of regressors, SINDy's idea: Brunton, Proctor & Kutz 2016).
#include "models/diagnosis/candidate_matrix.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <utility>

#include <Eigen/Dense>
#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include "models/diagnosis/effect_registry.h"
#include "models/diagnosis/signal_processing.h"

namespace mb::diagnosis_detail {
namespace {

// The smallest share, over the columns of `columns` (N × k), of a column's energy that the base regressors
// `base` (N × p, QR-factorised in `qr`) reproduce by least squares: 1 − ‖c − B·B⁺c‖²/‖c‖². 0 when p = 0. A
// candidate whose every column lies in the base's span adds only what separates it from the base — for
// coulomb_friction against a base that already fits F_c, only its dead band — and would be named for that.
double ShareSpannedByBase(const Eigen::MatrixXd& columns, const Eigen::MatrixXd& base,
                          const Eigen::ColPivHouseholderQR<Eigen::MatrixXd>& qr) {
  if (base.cols() == 0) return 0.0;
  double share = 1.0;
  for (Eigen::Index j = 0; j < columns.cols(); ++j) {
    const double energy = columns.col(j).squaredNorm();
    if (!(energy > 0.0)) continue;
    const Eigen::VectorXd rest = columns.col(j) - base * qr.solve(columns.col(j));
    share = std::min(share, 1.0 - rest.squaredNorm() / energy);
  }
  return share;
}

}  // namespace

Eigen::MatrixXd::ConstColXpr RegressorMatrix::Raw(Eigen::Index j) const {
  const Eigen::Index p = base.cols();
  if (j < p) return base.col(j);
  const Candidate& c = cands[owner_[static_cast<std::size_t>(j - p)]];
  return c.reg.columns.col(j - c.idx.front());
}

void RegressorMatrix::WeightedRows(Eigen::Index start, Eigen::Index count, Eigen::MatrixXd* chunk) const {
  chunk->resize(count, cols());
  const auto w = sw.segment(start, count);
  for (Eigen::Index j = 0; j < cols(); ++j) chunk->col(j) = w.cwiseProduct(Col(j).segment(start, count));
}

void RegressorMatrix::IndexColumns() {
  owner_.clear();
  for (std::size_t c = 0; c < cands.size(); ++c) owner_.insert(owner_.end(), cands[c].idx.size(), c);
}

void FilterCandidateColumns(const EffectType& type, const DiagnosisSignals& signals, const DiagnosisOptions& options,
                            Eigen::MatrixXd* columns) {
  if (const LoopResponse* loop = options.catalogue.loop.get()) {  // simulation mode: the force through the loop
    if (ThroughTheLoop(type.traits) && !EffectSimulatedInTheDiagram(type.traits, signals)) {
      *columns = options.simulate_loop_columns ? loop->Simulate(*columns) : loop->Apply(*columns);
    }
    return;
  }
  if (type.traits.regressor_in_output_band) return;
  if (!(options.regressor_filter_hz > 0.0)) return;
  const double ts = options.sample_period > 0.0 ? options.sample_period : MedianTimeStep(signals.time);
  // The columns are filtered independently, four at a time (ZeroPhaseLowPassColumns), the groups in parallel (a
  // refinement's serial golden section waits on them).
  constexpr Eigen::Index kGroup = 4;
  tbb::parallel_for(Eigen::Index{0}, (columns->cols() + kGroup - 1) / kGroup, [&](Eigen::Index g) {
    const Eigen::Index j = g * kGroup;
    ZeroPhaseLowPassColumns(columns->middleCols(j, std::min(kGroup, columns->cols() - j)), ts,
                            options.regressor_filter_hz);
  });
}

RegressorMatrix BuildCandidateMatrix(const DiagnosisSignals& signals, const Eigen::MatrixXd& base_cols,
                                     const std::vector<EffectInstance>& proposed, const DiagnosisOptions& options,
                                     std::vector<std::string>* notes) {
  const Eigen::Index n = signals.size(), p = base_cols.cols();
  // (Eigen's QR of an N × 0 matrix is not defined: without base regressors nothing is spanned.)
  const Eigen::ColPivHouseholderQR<Eigen::MatrixXd> base_qr =
      p > 0 ? Eigen::ColPivHouseholderQR<Eigen::MatrixXd>(base_cols) : Eigen::ColPivHouseholderQR<Eigen::MatrixXd>();
  // Each candidate's columns, filtering and share in the base's span are its own: computed in parallel, kept (and
  // noted) in the order proposed.
  struct Built {
    std::optional<Candidate> candidate;
    std::string note;
  };
  std::vector<Built> built(proposed.size());
  tbb::parallel_for(std::size_t{0}, proposed.size(), [&](std::size_t i) {
    const EffectInstance& e = proposed[i];
    const EffectType& type = LookupEffect(e.name);
    Candidate c{e, &type, {}, {}};
    try {
      c.reg = type.regressors(e, signals);
    } catch (const std::invalid_argument& error) {  // e.g. a parameter out of range on this record: skip it, say why
      built[i].note = fmt::format("{} skipped: its regressors cannot be computed on this record ({})", e.name,
                                  error.what());
      return;
    }
    FilterCandidateColumns(type, signals, options, &c.reg.columns);
    if (!c.reg.columns.allFinite()) {
      built[i].note = fmt::format("{} skipped: its regressors are not finite on this record", e.name);
      return;
    }
    if (c.reg.columns.cwiseAbs().maxCoeff() == 0.0) return;  // nothing to fit (e.g. no positive motion)
    const double spanned = ShareSpannedByBase(c.reg.columns, base_cols, base_qr);
    if (spanned >= options.redundant_with_base) {
      built[i].note = fmt::format(
          "{} is already in the model: the base's free parameters reproduce {:.1f} % of its regressor, so it is "
          "refit with them rather than proposed as missing",
          e.name, 100.0 * spanned);
      return;
    }
    built[i].candidate = std::move(c);
  });
  RegressorMatrix m;
  Eigen::Index total_cols = p;
  for (Built& b : built) {
    if (!b.note.empty()) notes->push_back(std::move(b.note));
    if (!b.candidate) continue;
    total_cols += b.candidate->reg.columns.cols();
    m.cands.push_back(std::move(*b.candidate));
  }
  m.base = base_cols;
  Eigen::Index col = p;
  for (auto& c : m.cands) {
    for (Eigen::Index j = 0; j < c.reg.columns.cols(); ++j) c.idx.push_back(col + j);
    col += c.reg.columns.cols();
  }
  m.scale.resize(total_cols);
  m.IndexColumns();
  for (Eigen::Index j = 0; j < total_cols; ++j) {
    const double rms = m.Raw(j).norm() / std::sqrt(static_cast<double>(n));
    m.scale(j) = rms > 0.0 ? rms : 1.0;
  }
  return m;
}

}  // namespace mb::diagnosis_detail

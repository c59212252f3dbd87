#include "models/diagnosis/effect_proposal.h"

#include <algorithm>

#include <Eigen/Dense>

#include "models/diagnosis/signal_processing.h"

namespace mb {
namespace {

// The strongest independent peaks of the position periodogram, each at its true period: a weaker peak at k·P
// (a sub-harmonic) means the period is k·P; periods beyond the search range are left out.
std::vector<ProposedPeriod> PositionPeriods(const Periodogram& pg, const CatalogueOptions& options) {
  std::vector<ProposedPeriod> out;
  for (std::size_t i = 0; i < pg.peaks.size() && static_cast<int>(out.size()) < options.max_position_periods; ++i) {
    if (pg.peaks[i].harmonic_of >= 0) continue;
    int sub = 1;
    for (const auto& p : pg.peaks) {
      if (p.harmonic_of == static_cast<int>(i) && p.harmonic_order < 0) sub = std::max(sub, -p.harmonic_order);
    }
    const double period = pg.peaks[i].period * sub;
    if (period > pg.max_period) continue;
    out.push_back({period, std::min(options.max_harmonics, sub * HarmonicCount(pg, i, options.max_harmonics))});
  }
  return out;
}

}  // namespace

ProposalContext::ProposalContext(const DiagnosisSignals& signals, const Eigen::VectorXd& residual,
                                 const Eigen::MatrixXd& base_columns, const CatalogueOptions& options,
                                 CandidateSearch* search)
    : signals_(signals), residual_(residual), base_columns_(base_columns), options_(options), search_(search) {
  max_speed_ = signals.velocity.cwiseAbs().maxCoeff();
  dead_band_ = options.dead_band_fraction * max_speed_;
  position_span_ = signals.position.maxCoeff() - signals.position.minCoeff();
  sample_period_ = MedianTimeStep(signals.time);
  if (position_span_ > 0.0) {
    PeriodogramOptions po = options.position_periodogram;
    if (po.max_period <= 0.0) po.max_period = position_span_ / options.min_position_cycles;
    search->position_periodogram = PositionPeriodogram(signals.position, residual, po);
    position_periods_ = PositionPeriods(search->position_periodogram, options);
  }
  search->time_periodogram = TimePeriodogram(signals.time, residual, options.time_periodogram);
  if (position_span_ > 0.0) {
    search->motion_frequency_hz =
        1.0 / TimePeriodogram(signals.time, signals.position, options.time_periodogram).best().period;
  }
}

Eigen::MatrixXd ProposalContext::BaseWithConstant() const {
  Eigen::MatrixXd base(size(), base_columns_.cols() + 1);
  base << base_columns_, Eigen::VectorXd::Ones(size());
  return base;
}

void ProposalContext::Propose(std::string effect, std::map<std::string, double> parameters) {
  search_->candidates.push_back({std::move(effect), std::move(parameters)});
}

void ProposalContext::Note(std::string note) { search_->notes.push_back(std::move(note)); }

int HarmonicCount(const Periodogram& pg, std::size_t index, int max_harmonics) {
  int h = 1;
  for (const auto& p : pg.peaks) {
    if (p.harmonic_of == static_cast<int>(index) && p.harmonic_order > 0) h = std::max(h, p.harmonic_order);
  }
  return std::min(h, max_harmonics);
}

double ResidualSumOfSquares(const Eigen::MatrixXd& base, const Eigen::Ref<const Eigen::MatrixXd>& extra,
                            const Eigen::VectorXd& r) {
  Eigen::MatrixXd x(r.size(), base.cols() + extra.cols());
  x << base, extra;
  const Eigen::VectorXd scale = (x.colwise().norm().array() + 1e-300).inverse();
  x = x * scale.asDiagonal();
  Eigen::MatrixXd g = x.transpose() * x;
  g.diagonal().array() += 1e-10;
  const Eigen::VectorXd beta = g.ldlt().solve(x.transpose() * r);
  return (r - x * beta).squaredNorm();
}

}  // namespace mb

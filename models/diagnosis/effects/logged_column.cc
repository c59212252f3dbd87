// logged_column, logged_column_rate: the residual follows a column of the log that the diagram does not read — another
// axis's acceleration or force (coupling through the frame), a temperature, a bus voltage, a second sensor. The
// grammar's factor of an unused column (DIAGNOSIS.md, "Beyond the catalogue"), two products of one table:
//   logged_column       c        {column: its index in DiagnosisSignals::extra_columns, named in extra_names}
//   logged_column_rate  dc/dt    (CentralDifference on the record's own time grid: a coupling through a lag)
// Proposal: every unused column that varies over the record; the forward selection's held-out test on contiguous
// blocks decides, so a column that does not matter (a slow temperature on a record whose friction does not drift) is
// not named. A column that is the compared output, the position or the velocity in another form (squared correlation
// ≥ 0.98: EMPS's input_V beside force_N, its reference_m beside position_m) is not proposed, with a note. Blocks: an
// input connector reading the column into a gain (logged_column) or a discrete_derivative (logged_column_rate),
// summed into the force (blocks/gain.cc, blocks/discrete_derivative.cc).
#include <cmath>
#include <string>
#include <utility>

#include <fmt/format.h>

#include "models/diagnosis/effect_proposal.h"
#include "models/diagnosis/effect_registry.h"
#include "models/diagnosis/effect_regressors.h"
#include "models/diagnosis/signal_processing.h"

namespace mb {
namespace {

constexpr double kDuplicate = 0.98;  // squared correlation with a signal the model reads: the same signal

// The squared correlation of a and b (0 when either is constant).
double SquaredCorrelation(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  const Eigen::ArrayXd da = a.array() - a.mean(), db = b.array() - b.mean();
  const double saa = da.square().sum(), sbb = db.square().sum();
  if (!(saa > 0.0 && sbb > 0.0)) return 0.0;
  const double sab = (da * db).sum();
  return sab * sab / (saa * sbb);
}

// The column the effect names; std::invalid_argument when its index is not one of the signals' extra columns.
std::size_t ColumnIndex(const EffectInstance& e, const DiagnosisSignals& s) {
  const double k = RequiredParameter(e, "column");
  if (!(k >= 0.0 && k < static_cast<double>(s.extra_columns.size()) && k == std::floor(k))) {
    throw std::invalid_argument(fmt::format(
        "effect '{}': column {} is not one of the log's {} column(s) that the diagram does not read; a record carried "
        "to another must hold the same extra columns",
        e.name, k, s.extra_columns.size()));
  }
  return static_cast<std::size_t>(k);
}

struct ColumnFactor {
  const char* name;
  int catalogue_order;
  bool rate;  // dc/dt, else c
  const char* physics;
  const char* formula;
};

const ColumnFactor kFactors[] = {
    {"logged_column", 120, false,
     "the residual follows a column of the log that the diagram does not read (coupling from another axis, a "
     "temperature, a bus voltage): add an input connector reading it and a gain into the force",
     "c, a log column the diagram does not read"},
    {"logged_column_rate", 121, true,
     "the residual follows the rate of a column of the log that the diagram does not read (a coupling through a lag, "
     "another axis's jerk or velocity): add an input connector reading it and a discrete derivative into the force",
     "dc/dt, c a log column the diagram does not read"},
};

void Propose(const ColumnFactor& f, ProposalContext& c) {
  const DiagnosisSignals& s = c.signals();
  for (std::size_t k = 0; k < s.extra_columns.size(); ++k) {
    const Eigen::VectorXd& column = s.extra_columns[k];
    if (!(column.maxCoeff() > column.minCoeff())) continue;
    // A column that is the compared output (or the motion the model reads) in another unit is no new signal: the
    // logged command as a voltage would fit the measurement's own noise (EMPS logs input_V beside force_N).
    const std::pair<const char*, const Eigen::VectorXd*> read[] = {
        {"the compared output (the logged command)", &s.logged_command}, {"the position", &s.position},
        {"the velocity", &s.velocity}};
    const char* duplicate = nullptr;
    for (const auto& [what, signal] : read) {
      if (signal->size() == column.size() && SquaredCorrelation(column, *signal) >= kDuplicate) duplicate = what;
    }
    if (duplicate != nullptr) {
      if (!f.rate) {  // one note per column
        c.Note(fmt::format("logged_column not proposed for '{}': it is {} in another form (squared correlation ≥ {:g})",
                           s.extra_names[k], duplicate, kDuplicate));
      }
      continue;
    }
    c.Propose(f.name, {{"column", static_cast<double>(k)}});
  }
}

EffectType ColumnEffect(const ColumnFactor& f) {
  EffectType t;
  t.name = f.name;
  t.catalogue_order = f.catalogue_order;
  t.physics = f.physics;
  t.regressor_formula = f.formula;
  t.parameters = {{"column", "", "the column's index among the log's unread columns (named in the description)"}};
  t.regressors = [&f](const EffectInstance& e, const DiagnosisSignals& s) {
    const Eigen::VectorXd& c = s.extra_columns[ColumnIndex(e, s)];
    return SingleColumn(e.name, f.rate ? CentralDifference(s.time, c) : c);
  };
  t.propose = [&f](ProposalContext& c) { Propose(f, c); };
  return t;
}

bool RegisterColumnFactors() {
  for (const ColumnFactor& f : kFactors) EffectRegistry::Global().Add(ColumnEffect(f));
  return true;
}

[[maybe_unused]] const bool kColumnFactorsRegistered = RegisterColumnFactors();

}  // namespace
}  // namespace mb


// logged_column, logged_column_rate: the residual follows a column of the log that the diagram does not read — another
// axis's acceleration or force (coupling through the frame), a temperature, a bus voltage, a second sensor. The
// grammar's factor of an unused column (DIAGNOSIS.md, "Beyond the catalogue"), two products of one table:
//   logged_column       c − c̄    {column: its index in DiagnosisSignals::extra_columns, named in extra_names; the mean
//                                 c̄ is the base's offset}
//   logged_column_rate  dc/dt    (CentralDifference on the record's own time grid: a coupling through a lag)
// Proposal: every unused column that varies over the record; the forward selection's held-out test on contiguous
// blocks decides, so a column that does not matter (a slow temperature on a record whose friction does not drift) is
// not named. A column that is the compared output, the position or the velocity in another form (squared correlation
// ≥ 0.98: EMPS's input_V beside force_N, its reference_m beside position_m) is not proposed, with a note. Blocks: an
// input connector reading the column into a gain (logged_column) or a discrete_derivative (logged_column_rate),
// summed into the force (blocks/gain.cc, blocks/discrete_derivative.cc).
#include <string>

#include <fmt/format.h>

#include "models/diagnosis/effect_proposal.h"
#include "models/diagnosis/effect_registry.h"
#include "models/diagnosis/effect_regressors.h"
#include "models/diagnosis/factors.h"
#include "models/diagnosis/signal_processing.h"

namespace mb {
namespace {

struct ColumnFactor {
  const char* name;
  int catalogue_order;
  bool rate;  // dc/dt, else c
  const char* modulator;  // the grammar's pair it is: 1 × this modulator (factors.h)
  const char* physics;
  const char* formula;
};

const ColumnFactor kFactors[] = {
    {"logged_column", 120, false, "column",
     "the residual follows a column of the log that the diagram does not read (coupling from another axis, a "
     "temperature, a bus voltage): add an input connector reading it and a gain into the force",
     "c − c̄, a log column the diagram does not read less its mean"},
    {"logged_column_rate", 121, true, "column_rate",
     "the residual follows the rate of a column of the log that the diagram does not read (a coupling through a lag, "
     "another axis's jerk or velocity): add an input connector reading it and a discrete derivative into the force",
     "dc/dt, c a log column the diagram does not read"},
};

void Propose(const ColumnFactor& f, ProposalContext& c) {
  const DiagnosisSignals& s = c.signals();
  for (std::size_t k = 0; k < s.extra_columns.size(); ++k) {
    if (!(s.extra_columns[k].maxCoeff() > s.extra_columns[k].minCoeff())) continue;
    if (const char* duplicate = UnreadColumnDuplicate(s, k)) {
      if (!f.rate) {  // one note per column
        c.Note(fmt::format("logged_column not proposed for '{}': it is {} in another form (squared correlation ≥ {:g})",
                           s.extra_names[k], duplicate, kDuplicateColumnCorrelation));
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
  t.multiplier = "one";
  t.modulator = f.modulator;
  t.physics = f.physics;
  t.regressor_formula = f.formula;
  t.parameters = {{"column", "", "the column's index among the log's unread columns (named in the description)"}};
  t.regressors = [&f](const EffectInstance& e, const DiagnosisSignals& s) {
    const Eigen::VectorXd& c = UnreadColumn(e, s);
    return SingleColumn(e.name, f.rate ? CentralDifference(s.time, c) : Centered(c));
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


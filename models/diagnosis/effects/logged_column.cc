// logged_column: the residual follows a column of the log that the diagram does not read — another axis's
// acceleration or force (coupling through the frame), a temperature, a bus voltage, a second sensor. The grammar's
// factor of an unused column (DIAGNOSIS.md, "Beyond the catalogue"): regressors the column c and its rate dc/dt
// (CentralDifference on the record's own time grid) {column: its index in DiagnosisSignals::extra_columns, named in
// extra_names}. Proposal: every unused column that varies over the record; the forward selection's held-out test on
// contiguous blocks decides, so a column that does not matter (a slow temperature on a record whose friction does not
// drift) is not named. A column that is the compared output, the position or the velocity in another form (squared
// correlation ≥ 0.98: EMPS's input_V beside force_N, its reference_m beside position_m) is not proposed, with a note. No block yet: add an input connector reading the column and a gain into the force by hand.
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

constexpr const char* kName = "logged_column";
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

EffectType LoggedColumn() {
  EffectType t;
  t.name = kName;
  t.catalogue_order = 120;
  t.physics = "the residual follows a column of the log that the diagram does not read (coupling from another axis, a "
              "temperature, a bus voltage): add an input connector reading it and a gain into the force";
  t.regressor_formula = "c, dc/dt for a log column c the diagram does not read";
  t.parameters = {{"column", "", "the column's index among the log's unread columns (named in the description)"}};
  t.regressors = [](const EffectInstance& e, const DiagnosisSignals& s) {
    const Eigen::VectorXd& c = s.extra_columns[ColumnIndex(e, s)];
    EffectRegressors out;
    out.columns.resize(s.size(), 2);
    out.columns.col(0) = c;
    out.columns.col(1) = CentralDifference(s.time, c);
    out.column_names = {e.name + ".value", e.name + ".rate"};
    return out;
  };
  t.propose = [](ProposalContext& c) {
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
        c.Note(fmt::format("logged_column not proposed for '{}': it is {} in another form (squared correlation ≥ {:g})",
                           s.extra_names[k], duplicate, kDuplicate));
        continue;
      }
      c.Propose(kName, {{"column", static_cast<double>(k)}});
    }
  };
  return t;
}

}  // namespace
}  // namespace mb

MB_REGISTER_EFFECT(logged_column, mb::LoggedColumn())

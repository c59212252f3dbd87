// mass_change: the moving mass changes during the record — a payload picked up or set down, a tool change. The
// residual is then structured in time, not in the state: after the change the model misses Δm·a. Regressor
// a·H(t − t_c) {change_time t_c [s]}, its coefficient Δm (the mass picked up, in the unit of the force per unit of
// acceleration). Proposal: a likelihood-ratio scan over the break time (the joint fit of the residual on
// [base, 1, a·H(t − t_c)] over a uniform grid of t_c in the middle 80 % of the record, then a golden-section search
// between the best point's neighbours: Andrews' sup-F test of a structural break, the Chow test at an unknown time);
// not proposed when the best break is at the scan's edge (no change inside the record) or a slow drift of the mass,
// a·(t − t₀)/T, fits better than a step (a note says so). Its significance is the forward selection's held-out test
// on contiguous blocks. Block: switched_gain "payload_change" on the acceleration input, its gain free
// (blocks/switched_gain.cc). Sources: Chow (1960), Econometrica 28(3); Andrews (1993), Econometrica 61(4);
// DIAGNOSIS.md, "Parameters that change".
#include <algorithm>
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "models/diagnosis/effect_proposal.h"
#include "models/diagnosis/effect_registry.h"
#include "models/diagnosis/effect_regressors.h"

namespace mb {
namespace {

constexpr const char* kName = "mass_change";
constexpr int kGrid = 81;
constexpr double kTrim = 0.1;  // of the record's duration left out at each end (Andrews' trimming)

Eigen::VectorXd Column(const DiagnosisSignals& s, double change_time) {
  return (s.time.array() >= change_time).select(s.acceleration, 0.0);
}

void Propose(ProposalContext& c) {
  const DiagnosisSignals& s = c.signals();
  if (!(s.acceleration.cwiseAbs().maxCoeff() > 0.0)) return;
  const double t0 = s.time(0), duration = s.time(c.size() - 1) - t0;
  const Eigen::MatrixXd base = c.BaseWithConstant();
  const JointFitResidual fit(base, c.residual(), c.loop());
  const auto sse = [&](double t) { return fit(Column(s, t)); };
  const double lo = t0 + kTrim * duration, step = (1.0 - 2.0 * kTrim) * duration / (kGrid - 1);
  int best = 0;
  double best_sse = std::numeric_limits<double>::infinity();
  for (int i = 0; i < kGrid; ++i) {
    const double e = sse(lo + i * step);
    if (e < best_sse) { best_sse = e; best = i; }
  }
  if (best == 0 || best == kGrid - 1) return;  // the best break at the scan's edge: no change inside the record
  double a = lo + (best - 1) * step, b = lo + (best + 1) * step;
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  double x1 = b - g * (b - a), x2 = a + g * (b - a), e1 = sse(x1), e2 = sse(x2);
  for (int it = 0; it < 30 && b - a > 0.1 * c.sample_period(); ++it) {
    if (e1 < e2) { b = x2; x2 = x1; e2 = e1; x1 = b - g * (b - a); e1 = sse(x1); }
    else { a = x1; x1 = x2; e1 = e2; x2 = a + g * (b - a); e2 = sse(x2); }
  }
  const double change_time = sse(0.5 * (a + b)) <= best_sse ? 0.5 * (a + b) : lo + best * step;
  const Eigen::VectorXd drift = s.acceleration.cwiseProduct(((s.time.array() - t0) / duration).matrix());
  const double drift_sse = fit(drift);
  if (drift_sse <= sse(change_time)) {
    c.Note(fmt::format("mass_change not proposed: a slow drift of the mass over the record fits the residual at least "
                       "as well as a step (best step at {:.3g} s): a drift (temperature, wear), not a payload change",
                       change_time));
    return;
  }
  c.Propose(kName, {{"change_time", change_time}});
}

EffectType MassChange() {
  EffectType t;
  t.name = kName;
  t.catalogue_order = 61;
  t.multiplier = "acceleration";  // the grammar's pair it is (factors.h)
  t.modulator = "time_step";
  t.physics = "the moving mass changes during the record (a payload picked up, a tool change): the mass steps at the "
              "change time; add a switched gain on the acceleration";
  t.regressor_formula = "a·H(t − t_c)";
  t.parameters = {{"change_time", "s", "t_c: when the mass changes"}};
  t.traits.coefficient_parameter = "change";  // Δm, the mass picked up (negative: set down)
  t.regressors = [](const EffectInstance& e, const DiagnosisSignals& s) {
    return SingleColumn(e.name, Column(s, RequiredParameter(e, "change_time")));
  };
  t.propose = Propose;
  return t;
}

}  // namespace
}  // namespace mb

MB_REGISTER_EFFECT(mass_change, mb::MassChange())

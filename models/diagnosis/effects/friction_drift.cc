// friction_drift: the viscous friction drifts during the record — the lubricant of a guide or a screw warming up
// (its viscosity falls with temperature), wear. The residual is then structured in time: the model's one viscous
// coefficient is right on average and wrong at the start and the end. Regressor v·ρ(t), ρ = (t − t_s)/(t_e − t_s)
// over the record {start_time t_s, end_time t_e [s]: the record's first and last instants}, its coefficient ΔF_v
// (the change of the viscous coefficient over the record, in the force's unit per unit of velocity; reported as
// "change"). Proposed when the velocity changes sign or speed and a drift fits the residual better than a step of
// the viscous coefficient at the best time (a sup-F scan as mass_change's): a step is a change of the machine, not a
// drift. Its significance is the forward selection's held-out test on contiguous blocks. Block: ramped_gain
// "friction_drift" on the velocity input, its gain free (blocks/ramped_gain.cc). Source: DIAGNOSIS.md, "Parameters
// that change"; Armstrong-Hélouvry, Dupont, Canudas de Wit (1994), Automatica 30(7), §2.5 (temperature).
#include <cmath>
#include <limits>

#include <fmt/format.h>

#include "models/diagnosis/effect_proposal.h"
#include "models/diagnosis/effect_registry.h"
#include "models/diagnosis/effect_regressors.h"

namespace mb {
namespace {

constexpr const char* kName = "friction_drift";
constexpr int kGrid = 41;
constexpr double kTrim = 0.1;  // of the record's duration left out at each end of the step scan

Eigen::VectorXd Column(const DiagnosisSignals& s, double start, double end) {
  return s.velocity.cwiseProduct(((s.time.array() - start) / (end - start)).min(1.0).max(0.0).matrix());
}

void Propose(ProposalContext& c) {
  const DiagnosisSignals& s = c.signals();
  if (!(s.velocity.cwiseAbs().maxCoeff() > 0.0)) return;
  const double start = s.time(0), end = s.time(c.size() - 1), duration = end - start;
  if (!(duration > 0.0)) return;
  const Eigen::MatrixXd base = c.BaseWithConstant();  // JointFitResidual keeps a reference
  const JointFitResidual fit(base, c.residual());
  const double drift_sse = fit(Column(s, start, end));
  double step_sse = std::numeric_limits<double>::infinity(), step_time = start;
  for (int i = 0; i < kGrid; ++i) {
    const double t = start + duration * (kTrim + (1.0 - 2.0 * kTrim) * i / (kGrid - 1));
    const double e = fit((s.time.array() >= t).select(s.velocity, 0.0));
    if (e < step_sse) { step_sse = e; step_time = t; }
  }
  if (!(drift_sse < step_sse)) {
    c.Note(fmt::format("friction_drift not proposed: a step of the viscous friction (best at {:.3g} s) fits the "
                       "residual at least as well as a drift over the record",
                       step_time));
    return;
  }
  c.Propose(kName, {{"start_time", start}, {"end_time", end}});
}

EffectType FrictionDrift() {
  EffectType t;
  t.name = kName;
  t.catalogue_order = 62;
  t.physics = "the viscous friction drifts during the record (the lubricant warming up, wear): its change over the "
              "record; add a ramped_gain on the velocity (or let the machine warm up before logging)";
  t.regressor_formula = "v·(t − t_s)/(t_e − t_s)";
  t.parameters = {{"start_time", "s", "t_s: the record's first instant"},
                  {"end_time", "s", "t_e: the record's last instant"}};
  t.traits.coefficient_parameter = "change";
  t.regressors = [](const EffectInstance& e, const DiagnosisSignals& s) {
    const double start = RequiredParameter(e, "start_time"), end = RequiredParameter(e, "end_time");
    if (!(end > start)) throw std::invalid_argument("effect 'friction_drift': end_time must lie after start_time");
    return SingleColumn(e.name, Column(s, start, end));
  };
  t.propose = Propose;
  return t;
}

}  // namespace
}  // namespace mb

MB_REGISTER_EFFECT(friction_drift, mb::FrictionDrift())

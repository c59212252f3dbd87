// friction_drift: the viscous friction drifts during the record — the lubricant of a guide or a screw warming up
// (its viscosity falls with temperature), wear. The residual is then structured in time: the model's one viscous
// coefficient is right on average and wrong at the start and the end. Regressor v·ρ(t), ρ = (t − t_s)/(t_e − t_s)
// over the record {start_time t_s, end_time t_e [s]: the record's first and last instants}, its coefficient ΔF_v
// (the change of the viscous coefficient over the record, in the force's unit per unit of velocity; reported as
// "change"). Proposed when the velocity changes sign or speed and a drift fits the residual better than a step of
// the viscous coefficient at the best time (a sup-F scan as mass_change's): a step is a change of the machine, not a
// drift; and not when a first-order warm-up that settles inside the record fits better (friction_warm_up is proposed
// then; the shared scan: models/diagnosis/viscous_drift.h). Its significance is the forward selection's held-out test
// on contiguous blocks. Block: ramped_gain "friction_drift" on the velocity input, its gain free
// (blocks/ramped_gain.cc). Source: DIAGNOSIS.md, "Parameters that change"; Armstrong-Hélouvry, Dupont, Canudas de
// Wit (1994), Automatica 30(7), §2.5 (temperature).
#include <cmath>

#include <fmt/format.h>

#include "models/diagnosis/effect_proposal.h"
#include "models/diagnosis/effect_registry.h"
#include "models/diagnosis/effect_regressors.h"
#include "models/diagnosis/viscous_drift.h"

namespace mb {
namespace {

constexpr const char* kName = "friction_drift";

void Propose(ProposalContext& c) {
  const ViscousDriftScan scan = ScanViscousDrift(c);
  if (!std::isfinite(scan.ramp_sse)) return;
  if (scan.WarmUpFitsBest()) return;  // friction_warm_up is proposed instead (effects/friction_warm_up.cc)
  if (!(scan.ramp_sse < scan.step_sse)) {
    c.Note(fmt::format("friction_drift not proposed: a step of the viscous friction (best at {:.3g} s) fits the "
                       "residual at least as well as a drift over the record",
                       scan.step_time));
    return;
  }
  c.Propose(kName, {{"start_time", scan.start}, {"end_time", scan.end}});
}

EffectType FrictionDrift() {
  EffectType t;
  t.name = kName;
  t.catalogue_order = 62;
  t.multiplier = "velocity";  // the grammar's pair it is (factors.h)
  t.modulator = "time_ramp";
  t.physics = "the viscous friction drifts during the record (the lubricant warming up, wear): its change over the "
              "record; add a ramped_gain on the velocity (or let the machine warm up before logging)";
  t.regressor_formula = "v·(t − t_s)/(t_e − t_s)";
  t.parameters = {{"start_time", "s", "t_s: the record's first instant"},
                  {"end_time", "s", "t_e: the record's last instant"}};
  t.traits.coefficient_parameter = "change";
  t.regressors = [](const EffectInstance& e, const DiagnosisSignals& s) {
    const double start = RequiredParameter(e, "start_time"), end = RequiredParameter(e, "end_time");
    if (!(end > start)) throw std::invalid_argument("effect 'friction_drift': end_time must lie after start_time");
    return SingleColumn(e.name, RampedVelocity(s.time, s.velocity, start, end));
  };
  t.propose = Propose;
  return t;
}

}  // namespace
}  // namespace mb

MB_REGISTER_EFFECT(friction_drift, mb::FrictionDrift())

// friction_warm_up: the viscous friction changes during the record as a first-order warm-up — a lubricant (a guide's
// or a screw's grease, a bearing's oil) whose temperature follows the heat put into it through a thermal time constant
// T, its viscosity falling with the temperature (Reynolds' exponential law; over a modest rise ≈ linear in it), so that
// the viscous coefficient settles exponentially: F_v(t) = F_v,0 + ΔF_v·(1 − exp(−(t − t_s)/T)). Regressor
// v·(1 − exp(−(t − t_s)/T)) for t ≥ t_s, 0 before {start_time t_s [s]: the record's first instant; time_constant T
// [s]}, its coefficient ΔF_v (the change once warm, in the force's unit per unit of velocity; reported as "change").
// A warm-up that began before the record differs from one from t_s only by a constant viscous coefficient, which the
// base's viscous friction takes: T is what the record tells, and ΔF_v is the change from the record's start. Proposal:
// the shared scan of the drift's shapes (models/diagnosis/viscous_drift.h: T on a log grid over [duration/100,
// duration], then golden section, jointly with the base) — proposed when T lies inside that range and the warm-up fits
// the residual better than a linear ramp over the record (friction_drift) and than a step of the viscous coefficient at
// the best time (a change of the machine). Its significance is the forward selection's held-out test on contiguous
// blocks; T is re-estimated jointly with the other chosen effects (EffectTraits::refined_parameter). Block:
// ramped_gain "friction_warm_up" with shape "exponential" on the velocity input, its gain free (blocks/ramped_gain.cc).
// Source: DIAGNOSIS.md, "Parameters that change"; Armstrong-Hélouvry, Dupont, Canudas de Wit (1994), Automatica 30(7),
// §2.5 (temperature); the grammar's time factor "first-order warm-up 1 − exp(−t/τ)" (issue 40).
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "models/diagnosis/effect_proposal.h"
#include "models/diagnosis/effect_registry.h"
#include "models/diagnosis/effect_regressors.h"
#include "models/diagnosis/viscous_drift.h"

namespace mb {
namespace {

constexpr const char* kName = "friction_warm_up";

void Propose(ProposalContext& c) {
  const ViscousDriftScan scan = ScanViscousDrift(c);
  if (!std::isfinite(scan.warm_up_sse) || !scan.WarmUpFitsBest()) return;
  c.Propose(kName, {{"start_time", scan.start}, {"time_constant", scan.time_constant}});
}

EffectType FrictionWarmUp() {
  EffectType t;
  t.name = kName;
  t.catalogue_order = 63;
  t.multiplier = "velocity";  // the grammar's pair it is (factors.h)
  t.modulator = "time_warm_up";
  t.physics = "the viscous friction settles during the record as a first-order warm-up (the lubricant's temperature "
              "following the heat put into it, its viscosity falling): its time constant and its change once warm; "
              "add a ramped_gain with shape \"exponential\" on the velocity (or let the machine warm up before "
              "logging)";
  t.regressor_formula = "v·(1 − exp(−(t − t_s)/T)), 0 before t_s";
  t.parameters = {{"start_time", "s", "t_s: the record's first instant"},
                  {"time_constant", "s", "T: the warm-up's time constant (63 % of the change at t_s + T)"}};
  t.traits.coefficient_parameter = "change";
  t.traits.refined_parameter = "time_constant";
  t.regressors = [](const EffectInstance& e, const DiagnosisSignals& s) {
    const double start = RequiredParameter(e, "start_time"), time_constant = PositiveParameter(e, "time_constant");
    return SingleColumn(e.name, WarmingVelocity(s.time, s.velocity, start, time_constant));
  };
  t.propose = Propose;
  return t;
}

}  // namespace
}  // namespace mb

MB_REGISTER_EFFECT(friction_warm_up, mb::FrictionWarmUp())

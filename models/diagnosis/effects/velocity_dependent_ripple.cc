// velocity_dependent_ripple: a position-periodic ripple whose amplitude grows with speed. Regressors
// |v|·cos(2πx/P), |v|·sin(2πx/P) {period P [m]}. Proposal: at every proposed position period. Block:
// velocity_dependent_ripple "ripple" on the position and velocity inputs, its coefficients free; its
// position_offset (the encoder zero) belongs to the record.
#include "models/diagnosis/effect_proposal.h"
#include "models/diagnosis/effect_registry.h"
#include "models/diagnosis/effect_regressors.h"

namespace mb {
namespace {

constexpr const char* kName = "velocity_dependent_ripple";

EffectType VelocityDependentRipple() {
  EffectType t;
  t.name = kName;
  t.catalogue_order = 80;
  t.multiplier = "speed";  // the grammar's pair it is (factors.h)
  t.modulator = "position_periodic";
  t.physics = "a position-periodic ripple whose amplitude grows with speed; add a ripple term scaled by |v|";
  t.regressor_formula = "|v|·cos(2πx/P), |v|·sin(2πx/P)";
  t.parameters = {{"period", "m", "P: the pitch"}};
  t.traits.periodicity = Periodicity::kPosition;
  RefinePositionPeriod(&t.traits);  // the periodogram's peak placed by the joint fit
  t.regressors = [](const EffectInstance& e, const DiagnosisSignals& s) {
    const Eigen::VectorXd speed = s.velocity.cwiseAbs();
    return PeriodicColumns(s.position, PositiveParameter(e, "period"), 1, e.name, &speed);
  };
  t.propose = [](ProposalContext& c) {
    // Every proposed period: the strongest peak of the residual's periodogram need not be the speed-dependent one (a
    // short stroke's few-cycle period is placed by its power among the others).
    if (!(c.max_speed() > 0.0)) return;
    for (const ProposedPeriod& p : c.position_periods()) c.Propose(kName, {{"period", p.period}});
  };
  return t;
}

}  // namespace
}  // namespace mb

MB_REGISTER_EFFECT(velocity_dependent_ripple, mb::VelocityDependentRipple())

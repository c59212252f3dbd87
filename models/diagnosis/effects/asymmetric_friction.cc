// asymmetric_friction: friction that differs between the two directions of motion. Regressor 1 where v > v_db,
// else 0 (an offset in the positive direction only; with coulomb_friction and constant_offset: different levels
// per direction) {dead_band [m/s]}. No block on purpose: with a free offset and Coulomb friction it is the same
// regressor (1[v > 0] = (1 + sign v)/2 wherever the axis moves), so refitting those is the fix.
#include "models/diagnosis/effect_proposal.h"
#include "models/diagnosis/effect_registry.h"
#include "models/diagnosis/effect_regressors.h"

namespace mb {
namespace {

constexpr const char* kName = "asymmetric_friction";

EffectType AsymmetricFriction() {
  EffectType t;
  t.name = kName;
  t.catalogue_order = 40;
  t.physics = "friction that differs between the two directions of motion; use direction-dependent levels";
  t.regressor_formula = "1 where v > v_db, else 0";
  t.parameters = {{"dead_band", "m/s", "v_db: the positive direction starts above it"}};
  t.regressors = [](const EffectInstance& e, const DiagnosisSignals& s) {
    const double db = RequiredParameter(e, "dead_band");
    return SingleColumn(e.name, s.velocity.unaryExpr([db](double v) { return v > db ? 1.0 : 0.0; }));
  };
  t.propose = [](ProposalContext& c) {
    if (c.max_speed() > 0.0) c.Propose(kName, {{"dead_band", c.dead_band()}});
  };
  return t;
}

}  // namespace
}  // namespace mb

MB_REGISTER_EFFECT(asymmetric_friction, mb::AsymmetricFriction())

// viscous_friction: a force proportional to velocity. Regressor v. Block: a gain "viscous_extra" on the velocity
// input summed into the output, its gain free.
#include "models/diagnosis/effect_proposal.h"
#include "models/diagnosis/effect_registry.h"
#include "models/diagnosis/effect_regressors.h"

namespace mb {
namespace {

constexpr const char* kName = "viscous_friction";

EffectType ViscousFriction() {
  EffectType t;
  t.name = kName;
  t.catalogue_order = 20;
  t.multiplier = "velocity";  // the grammar's pair it is (factors.h)
  t.modulator = "constant";
  t.physics = "a force proportional to velocity; add or refit viscous friction";
  t.regressor_formula = "v";
  t.regressors = [](const EffectInstance& e, const DiagnosisSignals& s) { return SingleColumn(e.name, s.velocity); };
  t.propose = [](ProposalContext& c) {
    if (c.max_speed() > 0.0) c.Propose(kName);
  };
  return t;
}

}  // namespace
}  // namespace mb

MB_REGISTER_EFFECT(viscous_friction, mb::ViscousFriction())

// coulomb_friction: a constant force opposing motion. Regressor s_db(v) = sign(v), 0 inside the dead band
// |v| ≤ v_db {dead_band [m/s]}. Block: a friction element "coulomb_extra" (slip model) on the velocity input,
// its Coulomb level free.
#include <algorithm>

#include "models/diagnosis/effect_proposal.h"
#include "models/diagnosis/effect_registry.h"
#include "models/diagnosis/effect_regressors.h"

namespace mb {
namespace {

constexpr const char* kName = "coulomb_friction";

EffectType CoulombFriction() {
  EffectType t;
  t.name = kName;
  t.catalogue_order = 30;
  t.multiplier = "slip";  // the grammar's pair it is (factors.h)
  t.modulator = "constant";
  t.physics = "a constant force opposing motion; add or refit Coulomb friction (friction mode, not sign(v))";
  t.regressor_formula = "s_db(v) = sign(v), 0 inside the dead band |v| ≤ v_db";
  t.parameters = {{"dead_band", "m/s", "v_db: sign(v) is 0 below it (dead_band_fraction × max |v|)"}};
  t.regressors = [](const EffectInstance& e, const DiagnosisSignals& s) {
    return SingleColumn(e.name, SignDeadBand(s.velocity, RequiredParameter(e, "dead_band")));
  };
  // Not proposed when the model has a Coulomb law already: what it would add is its dead band, i.e. the friction law
  // near zero velocity, which the friction-law replacements (regularized_coulomb_friction, …) model.
  t.propose = [](ProposalContext& c) {
    if (!(c.max_speed() > 0.0)) return;
    if (BaseHasCoulombLaw(c)) {
      c.Note("coulomb_friction not proposed: the model has a Coulomb law; what it would add is its dead band, the "
             "friction law near zero velocity (see the friction-law replacements)");
      return;
    }
    c.Propose(kName, {{"dead_band", c.dead_band()}});
  };
  return t;
}

}  // namespace
}  // namespace mb

MB_REGISTER_EFFECT(coulomb_friction, mb::CoulombFriction())

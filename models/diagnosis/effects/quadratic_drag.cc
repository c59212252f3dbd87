// quadratic_drag: a drag that grows with the square of the speed, v·|v| — a fluid at high Reynolds number (air on a
// large carriage or a fan on the motor, oil pumped through a seal or a bearing gap), the grammar's v × |v|. The base's
// viscous friction takes its linear part (the fit of v·|v| on v over the record's speeds); what is left is the
// curvature, which no linear law has. Block: a gain "quadratic_drag" on the velocity input times the abs of the
// velocity (blocks/gain.cc), its gain (c [N·s²/m²]) free.
#include "models/diagnosis/effect_proposal.h"
#include "models/diagnosis/effect_registry.h"
#include "models/diagnosis/effect_regressors.h"

namespace mb {
namespace {

constexpr const char* kName = "quadratic_drag";

EffectType QuadraticDrag() {
  EffectType t;
  t.name = kName;
  t.catalogue_order = 21;
  t.multiplier = "velocity_speed";  // the grammar's pair it is (factors.h)
  t.modulator = "constant";
  t.physics =
      "a drag that grows with the square of the speed (a fluid at high Reynolds number: air on a large carriage, a fan "
      "on the motor, oil pumped through a seal or a bearing gap): c·v·|v|; add a gain on the velocity multiplied by "
      "its abs";
  t.regressor_formula = "v·|v|";
  t.traits.coefficient_parameter = "drag_coefficient";  // c [N·s²/m²]
  t.traits.positive_coefficient = true;                 // a drag dissipates: c > 0
  t.regressors = [](const EffectInstance& e, const DiagnosisSignals& s) {
    return SingleColumn(e.name, s.velocity.cwiseProduct(s.velocity.cwiseAbs()));
  };
  t.propose = [](ProposalContext& c) {
    if (c.max_speed() > 0.0) c.Propose(kName);
  };
  return t;
}

}  // namespace
}  // namespace mb

MB_REGISTER_EFFECT(quadratic_drag, mb::QuadraticDrag())

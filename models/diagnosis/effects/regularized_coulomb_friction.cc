// regularized_coulomb_friction: the model's Coulomb law sign(v) replaced near zero velocity by a smooth one,
// F_c·tanh(v/v_c) — a friction-law replacement (DIAGNOSIS.md, "When the base model is wrong elsewhere"): at rest
// and in slow motion the measured force does not flip ±F_c with the velocity noise. Regressor tanh(v/v_c)
// {regularization_velocity v_c [m/s]}, fitted jointly with the base's sign(v) (whose coefficient then drops).
// Proposed only when the base has a Coulomb law to replace (BaseHasCoulombLaw); v_c from a scan of the joint fit
// over 1e-4…0.1 × max |v|. Block (blocks/friction.cc): a friction element "smooth_coulomb" with regularization
// "tanh" on the velocity input (models/physics/friction.h, RegularizedFriction), its Coulomb level and v_c free; the
// model's own Coulomb level, which it replaces, is set to 0 and no longer refit (EffectTraits::replaces_coulomb_law).
#include <algorithm>

#include "models/diagnosis/effect_proposal.h"
#include "models/diagnosis/effect_registry.h"
#include "models/diagnosis/effect_regressors.h"

namespace mb {
namespace {

constexpr const char* kName = "regularized_coulomb_friction";

Eigen::VectorXd Column(const Eigen::VectorXd& v, double vc) { return (v.array() / vc).tanh(); }

void Propose(ProposalContext& c) {
  if (!(c.max_speed() > 0.0)) return;
  if (!BaseHasCoulombLaw(c)) return;  // no Coulomb law in the model to replace
  const Eigen::VectorXd& v = c.signals().velocity;
  const double vc = ScanJointFit(c, 1e-4 * c.max_speed(), 0.1 * c.max_speed(), 19,
                                 [&](double value) { return Eigen::MatrixXd(Column(v, value)); });
  if (vc > 0.0) c.Propose(kName, {{"regularization_velocity", vc}});
}

EffectType RegularizedCoulombFriction() {
  EffectType t;
  t.name = kName;
  t.catalogue_order = 45;
  t.physics = "the friction law near zero velocity is smooth, not sign(v): replace the Coulomb law by "
              "F_c·tanh(v/v_c) (the friction block with regularization \"tanh\", the model's Coulomb level refit)";
  t.regressor_formula = "tanh(v/v_c)";
  t.parameters = {{"regularization_velocity", "m/s", "v_c: below it the friction grows about linearly with v"}};
  t.traits.friction_law_replacement = true;
  t.traits.replaces_coulomb_law = true;
  t.traits.refined_parameter = "regularization_velocity";
  t.traits.refinement_range = 64.0;
  // Within the proposal's scan (up to a tenth of the top speed): the law near zero velocity. A tanh still rising at
  // 40 % of the top speed is a curvature of the law at speed (a drag v·|v| took one to 0.086 m/s on a 0.2 m/s record).
  t.traits.refined_upper_bound = [](const DiagnosisSignals& s) { return 0.1 * s.velocity.cwiseAbs().maxCoeff(); };
  t.regressors = [](const EffectInstance& e, const DiagnosisSignals& s) {
    return SingleColumn(e.name, Column(s.velocity, PositiveParameter(e, "regularization_velocity")));
  };
  t.propose = Propose;
  return t;
}

}  // namespace
}  // namespace mb

MB_REGISTER_EFFECT(regularized_coulomb_friction, mb::RegularizedCoulombFriction())

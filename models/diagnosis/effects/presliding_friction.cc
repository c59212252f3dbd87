// presliding_friction: the model's Coulomb law sign(v) replaced near zero velocity by pre-sliding — after a
// reversal the friction builds up over a small displacement δ before the contact slides (the elasto-plastic limit
// of the Dahl and LuGre models; Dahl 1968, Canudas de Wit et al. 1995). A friction-law replacement. Regressor
// z = (x − p_δ(x))/δ ∈ [−1, 1], p_δ the play operator of half-width δ {presliding_displacement δ [m]}. Proposed only
// when the base has a Coulomb law to replace (BaseHasCoulombLaw); δ from a scan of the joint fit over 0.5 µm…2 mm
// (at most 1 % of the travel). No block: a state-holding friction law (LuGre) is added by hand.
#include <algorithm>

#include "models/diagnosis/effect_proposal.h"
#include "models/diagnosis/effect_registry.h"
#include "models/diagnosis/effect_regressors.h"

namespace mb {
namespace {

constexpr const char* kName = "presliding_friction";

Eigen::VectorXd Column(const Eigen::VectorXd& x, double delta) { return (x - PlayOperator(x, delta)) / delta; }

void Propose(ProposalContext& c) {
  if (!(c.max_speed() > 0.0) || !(c.position_span() > 0.0)) return;
  if (!BaseHasCoulombLaw(c)) return;  // no Coulomb law in the model to replace
  const Eigen::VectorXd& x = c.signals().position;
  const double hi = std::min(2e-3, 0.01 * c.position_span());
  const double delta = ScanJointFit(c, 5e-7, hi, 15, [&](double value) { return Eigen::MatrixXd(Column(x, value)); });
  if (delta > 0.0) c.Propose(kName, {{"presliding_displacement", delta}});
}

EffectType PreslidingFriction() {
  EffectType t;
  t.name = kName;
  t.catalogue_order = 46;
  t.physics = "after each reversal the friction builds up over a pre-sliding displacement before sliding: replace "
              "the Coulomb law near zero velocity by a pre-sliding (Dahl/LuGre) law";
  t.regressor_formula = "(x − p_δ(x))/δ, p_δ the play operator of half-width δ";
  t.parameters = {{"presliding_displacement", "m", "δ: the displacement over which the friction builds up"}};
  t.traits.friction_law_replacement = true;
  t.regressors = [](const EffectInstance& e, const DiagnosisSignals& s) {
    return SingleColumn(e.name, Column(s.position, PositiveParameter(e, "presliding_displacement")));
  };
  t.propose = Propose;
  return t;
}

}  // namespace
}  // namespace mb

MB_REGISTER_EFFECT(presliding_friction, mb::PreslidingFriction())

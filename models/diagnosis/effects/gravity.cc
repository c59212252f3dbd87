// gravity: on a rotary axis, the weight of an unbalanced load — an arm, a pendulum, a vertical axis' counterweight
// out of balance — pulls with m·g·l·sin(θ + φ): a smooth force of the angle over the whole travel, often the largest
// term of the record. Regressors cos(2πθ/R), sin(2πθ/R), R one revolution in the position's unit
// (CatalogueOptions::revolution: 2π rad, 1 rev, 360 deg) {period R}; their amplitude is m·g·l [unit of the torque].
// Proposed on a rotary axis whose travel spans at least an eighth of a revolution (below, sin θ is a straight line:
// the position_dependent_force polynomial and the constant cover it). Block: position_periodic "gravity" with one
// harmonic and the period of one revolution (blocks/position_periodic.cc). Source: DIAGNOSIS.md, "Gravity on a rotary
// axis"; Spong, Hutchinson, Vidyasagar, Robot Modeling and Control (2006), §7.3, the pendulum's gravity term.
#include "models/diagnosis/effect_proposal.h"
#include "models/diagnosis/effect_registry.h"
#include "models/diagnosis/effect_regressors.h"

namespace mb {
namespace {

constexpr const char* kName = "gravity";
constexpr double kMinRevolutionShare = 0.125;  // of a revolution the travel must span

EffectType Gravity() {
  EffectType t;
  t.name = kName;
  t.catalogue_order = 64;
  t.physics = "gravity on an unbalanced load of a rotary axis, m·g·l·sin(θ + φ); add a one-harmonic position_periodic "
              "block with the period of one revolution";
  t.regressor_formula = "cos(2πθ/R), sin(2πθ/R), R = one revolution";
  t.parameters = {{"period", "", "R: one revolution in the position's unit (2π rad, 1 rev, 360 deg)"}};
  t.regressors = [](const EffectInstance& e, const DiagnosisSignals& s) {
    return PeriodicColumns(s.position, PositiveParameter(e, "period"), 1, e.name);
  };
  t.propose = [](ProposalContext& c) {
    const double revolution = c.options().revolution;
    if (!(revolution > 0.0)) return;  // a linear axis
    if (c.position_span() < kMinRevolutionShare * revolution) {
      c.Note("gravity not proposed: the travel spans less than an eighth of a revolution, where sin θ is a straight "
             "line (position_dependent_force and constant_offset cover it)");
      return;
    }
    c.Propose(kName, {{"period", revolution}});
  };
  return t;
}

}  // namespace
}  // namespace mb

MB_REGISTER_EFFECT(gravity, mb::Gravity())

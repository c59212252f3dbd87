// presliding_friction: the model's Coulomb law sign(v) replaced near zero velocity by pre-sliding — after a
// reversal the friction builds up over a small displacement δ before the contact slides (the elasto-plastic limit
// of the Dahl and LuGre models; Dahl 1968, Canudas de Wit et al. 1995). A friction-law replacement. Regressor
// z = (x − p_δ(x))/δ ∈ [−1, 1], p_δ the play operator of half-width δ {presliding_displacement δ [m]}. Proposed only
// when the base has a Coulomb law to replace (BaseHasCoulombLaw); δ from a scan of the joint fit over 2·10⁻⁶…0.008 of
// the travel (0.5 µm…2 mm on EMPS), at most the median displacement of a start (StartDisplacement), not proposed when the best δ
// is the longest tried. No block: a state-holding friction law (LuGre) is added by hand.
#include <algorithm>
#include <cmath>
#include <vector>

#include <fmt/format.h>

#include "models/diagnosis/effect_proposal.h"
#include "models/diagnosis/effect_registry.h"
#include "models/diagnosis/effect_regressors.h"

namespace mb {
namespace {

constexpr const char* kName = "presliding_friction";

Eigen::VectorXd Column(const Eigen::VectorXd& x, double delta) { return (x - PlayOperator(x, delta)) / delta; }

// The median displacement from the last sample at rest (|v| at most the dead band) to where the speed first exceeds 10 %
// of max |v| (the start of each move or reversal): pre-sliding is the micro-displacement regime before gross sliding, so
// its δ lies well within it. 0 when the record holds no such start.
double StartDisplacement(const ProposalContext& c) {
  const Eigen::VectorXd& x = c.signals().position;
  const Eigen::VectorXd& v = c.signals().velocity;
  std::vector<double> travelled;
  double at_rest = x(0);
  bool resting = std::abs(v(0)) <= c.dead_band();
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    const double speed = std::abs(v(i));
    if (speed <= c.dead_band()) {
      at_rest = x(i);
      resting = true;
    } else if (resting && speed > 0.1 * c.max_speed()) {
      travelled.push_back(std::abs(x(i) - at_rest));
      resting = false;
    }
  }
  if (travelled.empty()) return 0.0;
  std::nth_element(travelled.begin(), travelled.begin() + static_cast<std::ptrdiff_t>(travelled.size() / 2),
                   travelled.end());
  return travelled[travelled.size() / 2];
}

constexpr double kShortestShare = 2e-6;  // of the travel: the shortest δ tried
constexpr double kLongestShare = 8e-3;   // of the travel: the longest δ tried

void Propose(ProposalContext& c) {
  if (!(c.max_speed() > 0.0) || !(c.position_span() > 0.0)) return;
  if (!BaseHasCoulombLaw(c)) return;  // no Coulomb law in the model to replace
  const Eigen::VectorXd& x = c.signals().position;
  const double start = StartDisplacement(c);
  // Scaled by the travel, in the position's own unit (m, rad, V): on EMPS's 0.25 m, 0.5 µm…2 mm.
  const double lo = kShortestShare * c.position_span();
  const double hi = std::min(kLongestShare * c.position_span(), start);
  if (!(hi > lo)) return;
  const double delta = ScanJointFit(c, lo, hi, 15, [&](double value) { return Eigen::MatrixXd(Column(x, value)); });
  if (!(delta > 0.0)) return;
  if (delta > hi / 1.05) {  // the best δ is the longest tried: a force of the position after each start, not pre-sliding
    c.Note(fmt::format("presliding_friction not proposed: the joint fit's best δ is the longest tried ({:.3g}, the "
                       "median displacement before the speed exceeds 10 % of its maximum), i.e. a force of the position "
                       "after each start (a play, a spring) rather than pre-sliding", delta));
    return;
  }
  c.Propose(kName, {{"presliding_displacement", delta}});
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
  t.traits.refined_parameter = "presliding_displacement";
  t.traits.refinement_range = 8.0;
  t.regressors = [](const EffectInstance& e, const DiagnosisSignals& s) {
    return SingleColumn(e.name, Column(s.position, PositiveParameter(e, "presliding_displacement")));
  };
  t.propose = Propose;
  return t;
}

}  // namespace
}  // namespace mb

MB_REGISTER_EFFECT(presliding_friction, mb::PreslidingFriction())

// backlash: a load coupled through a play (gear, belt, coupling): after each reversal the motor travels the gap
// before it drives the load again, so the load's friction is felt only once the play is taken up — the force jumps
// when the relative motion has crossed the gap. Regressor e_g(x)·s_db(v), e_g = 1 when the play operator of
// half-width g/2 is engaged (|x − p(x)| = g/2), else 0 {backlash g [m] (the full gap), dead_band [m/s]}. Proposal: a
// scan of the joint fit over 0.25 %…5 % of the travel; a best gap at either end is not a play. Block: backlash_friction (blocks/), the same law.
#include <algorithm>

#include <fmt/format.h>

#include "models/diagnosis/effect_proposal.h"
#include "models/diagnosis/effect_registry.h"
#include "models/diagnosis/effect_regressors.h"

namespace mb {
namespace {

constexpr const char* kName = "backlash";

Eigen::VectorXd Column(const Eigen::VectorXd& x, const Eigen::VectorXd& sign, double gap) {
  const double half = 0.5 * gap;
  const Eigen::VectorXd far = PlayOperator(x, half);
  Eigen::VectorXd out(x.size());
  for (Eigen::Index i = 0; i < x.size(); ++i) out(i) = std::abs(x(i) - far(i)) >= half * (1.0 - 1e-6) ? sign(i) : 0.0;
  return out;
}

void Propose(ProposalContext& c) {
  if (!(c.max_speed() > 0.0) || !(c.position_span() > 0.0)) return;
  const Eigen::VectorXd& x = c.signals().position;
  const Eigen::VectorXd sign = SignDeadBand(c.signals().velocity, c.dead_band());
  // Gaps below 0.25 % of the travel are crossed within a few milliseconds of each reversal: there the regressor is
  // the friction law near zero velocity (pre-sliding, a lagging velocity estimate), which the friction-law
  // replacements model; on logs with nothing missing such "gaps" of 10–20 µm were named.
  const double lo = 0.0025 * c.position_span();
  const double hi = 0.05 * c.position_span();
  const double gap = ScanJointFit(c, lo, hi, 21,
                                  [&](double value) { return Eigen::MatrixXd(Column(x, sign, value)); });
  if (!(gap > 0.0)) return;
  if (gap < 1.05 * lo) {  // the best gap is the smallest tried: no gap of its own, the law near zero velocity
    c.Note(fmt::format("backlash not proposed: the joint fit's best gap is the smallest tried ({:.3g}, 0.25 % of the "
                       "travel), i.e. the friction law near zero velocity rather than a play", gap));
    return;
  }
  if (gap > 0.95 * hi) {  // the widest tried: the jump tracks the position over the travel, not a reversal
    c.Note(fmt::format("backlash not proposed: the joint fit's best gap is the widest tried ({:.3g}, 5 % of the "
                       "travel), i.e. a force that changes with the position over the travel (gravity, a spring) "
                       "rather than a play",
                       gap));
    return;
  }
  c.Propose(kName, {{"backlash", gap}, {"dead_band", c.dead_band()}});
}

EffectType Backlash() {
  EffectType t;
  t.name = kName;
  t.catalogue_order = 62;
  t.physics = "a load behind a play (backlash, dead zone): after each reversal its friction is felt only once the "
              "gap is crossed; add a play (a backlash_friction block of gap g) between the motor and the load's friction";
  t.regressor_formula = "e_g(x)·s_db(v), e_g = 1 once the play of width g is taken up";
  t.parameters = {{"backlash", "m", "g: the full gap crossed after each reversal"},
                  {"dead_band", "m/s", "v_db: sign(v) is 0 below it"}};
  t.traits.refined_parameter = "backlash";
  t.traits.refinement_range = 4.0;
  t.regressors = [](const EffectInstance& e, const DiagnosisSignals& s) {
    const Eigen::VectorXd sign = SignDeadBand(s.velocity, RequiredParameter(e, "dead_band"));
    return SingleColumn(e.name, Column(s.position, sign, PositiveParameter(e, "backlash")));
  };
  t.propose = Propose;
  return t;
}

}  // namespace
}  // namespace mb

MB_REGISTER_EFFECT(backlash, mb::Backlash())

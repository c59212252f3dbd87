// position_periodic: a force periodic in position (cogging, screw-lead or gear ripple). Regressors
// cos(2πkx/P), sin(2πkx/P), k = 1..K {period P [m], harmonics K}. Proposal: the strongest independent peaks of
// the residual's position periodogram (ProposalContext::position_periods). Block: position_periodic "ripple" on
// the position input, its Fourier coefficients free; its position_offset (the encoder zero) belongs to the record.
#include "models/diagnosis/effect_proposal.h"
#include "models/diagnosis/effect_registry.h"
#include "models/diagnosis/effect_regressors.h"

namespace mb {
namespace {

constexpr const char* kName = "position_periodic";

EffectType PositionPeriodic() {
  EffectType t;
  t.name = kName;
  t.catalogue_order = 70;
  t.multiplier = "one";  // the grammar's pair it is (factors.h)
  t.modulator = "position_periodic";
  t.physics =
      "a force periodic in position (cogging, screw-lead or gear ripple); add a cogging/ripple block with this "
      "period and its harmonics";
  t.regressor_formula = "cos(2πkx/P), sin(2πkx/P), k = 1..K";
  t.parameters = {{"period", "m", "P: the pitch (pole pitch, screw lead, tooth pitch)"},
                  {"harmonics", "", "K, 1 when absent"}};
  t.traits.periodicity = Periodicity::kPosition;
  RefinePositionPeriod(&t.traits);  // the periodogram's peak placed by the joint fit
  t.regressors = [](const EffectInstance& e, const DiagnosisSignals& s) {
    return PeriodicColumns(s.position, PositiveParameter(e, "period"), HarmonicsParameter(e), e.name);
  };
  t.propose = [](ProposalContext& c) {
    for (const ProposedPeriod& p : c.position_periods()) {
      c.Propose(kName, {{"period", p.period}, {"harmonics", p.harmonics}});
    }
  };
  return t;
}

}  // namespace
}  // namespace mb

MB_REGISTER_EFFECT(position_periodic, mb::PositionPeriodic())

// mass_mismatch: a force proportional to acceleration (the moving mass is wrong, e.g. a payload). Regressor a.
// Block: a gain "payload" on the acceleration input summed into the output, its gain free.
#include "models/diagnosis/effect_proposal.h"
#include "models/diagnosis/effect_registry.h"
#include "models/diagnosis/effect_regressors.h"

namespace mb {
namespace {

constexpr const char* kName = "mass_mismatch";

EffectType MassMismatch() {
  EffectType t;
  t.name = kName;
  t.catalogue_order = 60;
  t.multiplier = "acceleration";  // the grammar's pair it is (factors.h)
  t.modulator = "constant";
  t.physics = "a force proportional to acceleration; refit the moving mass (payload)";
  t.regressor_formula = "a";
  t.regressors = [](const EffectInstance& e, const DiagnosisSignals& s) {
    return SingleColumn(e.name, s.acceleration);
  };
  t.propose = [](ProposalContext& c) {
    if (c.signals().acceleration.cwiseAbs().maxCoeff() > 0.0) c.Propose(kName);
  };
  return t;
}

}  // namespace
}  // namespace mb

MB_REGISTER_EFFECT(mass_mismatch, mb::MassMismatch())

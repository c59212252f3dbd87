// constant_offset: a constant bias of the residual (sensor offset, gravity on an incline, amplifier offset).
// Regressor 1. Block: a constant "offset_extra" summed into the output, its value free.
#include "models/diagnosis/effect_proposal.h"
#include "models/diagnosis/effect_registry.h"
#include "models/diagnosis/effect_regressors.h"

namespace mb {
namespace {

constexpr const char* kName = "constant_offset";

EffectType ConstantOffset() {
  EffectType t;
  t.name = kName;
  t.catalogue_order = 10;
  t.multiplier = "one";  // the grammar's pair it is (factors.h)
  t.modulator = "constant";
  t.physics = "a constant bias (sensor offset, gravity on an incline, amplifier offset)";
  t.regressor_formula = "1";
  t.regressors = [](const EffectInstance& e, const DiagnosisSignals& s) {
    return SingleColumn(e.name, Eigen::VectorXd::Ones(s.size()));
  };
  // A constant belongs among the candidates, else asymmetric friction hides in the mean (DIAGNOSIS.md step 4).
  t.propose = [](ProposalContext& c) { c.Propose(kName); };
  return t;
}

}  // namespace
}  // namespace mb

MB_REGISTER_EFFECT(constant_offset, mb::ConstantOffset())

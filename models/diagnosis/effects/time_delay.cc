// time_delay: the measurement lags the model by a pure delay d (measured = ŷ(t − d)): a sensor or logging delay (the
// position measured late, a logger's buffer). Regressor ŷ(t − d) − ŷ(t) (linear interpolation; ≈ −d·dŷ/dt for small d)
// {delay d [s] > 0}; it is the error itself, so it must enter with a coefficient near 1. Proposal: the signed lag of
// the measurement behind ŷ (ProposalContext::model_output_delay), when positive; a negative one — the log leads the
// model, a command that acts later than logged — is actuator_lag's (effects/actuator_lag.cc). Block: transport_delay
// "delay" before the output, its delay free.
#include "models/diagnosis/effect_proposal.h"
#include "models/diagnosis/effect_registry.h"
#include "models/diagnosis/effect_regressors.h"
#include "models/diagnosis/signal_processing.h"

namespace mb {
namespace {

constexpr const char* kName = "time_delay";

EffectType TimeDelay() {
  EffectType t;
  t.name = kName;
  t.catalogue_order = 110;
  t.physics = "the measurement lags the model by a pure delay (a sensor or logger delay: the signal is recorded late); "
              "add a delay block (transport or sampling delay) before the output";
  t.regressor_formula = "ŷ(t − d) − ŷ(t) (linear interpolation; ≈ −d·dŷ/dt for small d)";
  t.parameters = {{"delay", "s", "d: how long the measurement lags the model"}};
  t.traits.regressor_is_error = true;
  t.traits.regressor_in_output_band = true;
  t.traits.refined_parameter = "delay";
  t.traits.refinement_range = 4.0;
  t.regressors = [](const EffectInstance& e, const DiagnosisSignals& s) {
    const Eigen::VectorXd& y = NeedModelOutput(e, s);
    return SingleColumn(e.name, ShiftedInTime(s.time, y, RequiredParameter(e, "delay")) - y);
  };
  t.propose = [](ProposalContext& c) {
    if (const double delay = c.model_output_delay(); delay > 0.0) c.Propose(kName, {{"delay", delay}});
  };
  return t;
}

}  // namespace
}  // namespace mb

MB_REGISTER_EFFECT(time_delay, mb::TimeDelay())

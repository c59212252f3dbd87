// actuator_lag: the logged command acts a time d after its time stamp — the drive's current loop, PWM, a fieldbus
// cycle. In equation-error mode the model's force ŷ is computed from the motion, i.e. from the force that acted, so the
// logged command leads it: measured(t) = ŷ(t + d). Regressor ŷ(t + d) − ŷ(t) (linear interpolation; ≈ d·dŷ/dt) {lag d
// [s] > 0}; it is the error itself (coefficient near 1). Proposal: the signed lag of the measurement behind ŷ
// (ProposalContext::model_output_delay), when negative and at least one sample period — the other sign, a measurement
// that lags, is time_delay's (a sensor delay). Block: transport_delay on the command path (BlockPlacement::kOnCommand,
// blocks/transport_delay.cc). Source: DIAGNOSIS.md, "Delay sign"; for a small delay the residual ≈ −delay·dŷ/dt (Ljung,
// System Identification, 2nd ed., §16.6, residual analysis).
#include <fmt/format.h>

#include "models/diagnosis/effect_proposal.h"
#include "models/diagnosis/effect_registry.h"
#include "models/diagnosis/effect_regressors.h"
#include "models/diagnosis/signal_processing.h"

namespace mb {
namespace {

constexpr const char* kName = "actuator_lag";

EffectType ActuatorLag() {
  EffectType t;
  t.name = kName;
  t.catalogue_order = 111;
  t.physics = "the logged command acts later than logged (current loop, PWM, fieldbus): the force that moves the axis "
              "at t is the command logged at t − d; add a transport_delay on the command path";
  t.regressor_formula = "ŷ(t + d) − ŷ(t) (linear interpolation; ≈ d·dŷ/dt for small d)";
  t.parameters = {{"lag", "s", "d: how long after its time stamp the logged command acts"}};
  t.traits.regressor_is_error = true;
  t.traits.regressor_in_output_band = true;
  t.traits.refined_parameter = "lag";
  t.traits.refinement_range = 4.0;
  t.regressors = [](const EffectInstance& e, const DiagnosisSignals& s) {
    const Eigen::VectorXd& y = NeedModelOutput(e, s);
    return SingleColumn(e.name, ShiftedInTime(s.time, y, -PositiveParameter(e, "lag")) - y);
  };
  t.propose = [](ProposalContext& c) {
    const double delay = c.model_output_delay();
    if (!(delay < 0.0)) return;
    // The block reads the logged command: a lag shorter than one sample is an interpolation between neighbouring
    // samples that averages the log's own noise (on EMPS a 0.38 ms "lag" raised the training error 2.00 → 2.61 N).
    if (-delay < c.sample_period()) {
      c.Note(fmt::format("actuator_lag not proposed: the log leads the model by {:.3g} ms, less than one sample "
                         "period ({:.3g} ms)",
                         -delay * 1e3, c.sample_period() * 1e3));
      return;
    }
    c.Propose(kName, {{"lag", -delay}});
  };
  return t;
}

}  // namespace
}  // namespace mb

MB_REGISTER_EFFECT(actuator_lag, mb::ActuatorLag())

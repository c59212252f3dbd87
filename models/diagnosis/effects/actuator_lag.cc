// actuator_lag: the logged command acts a time d after its time stamp — the drive's current loop, PWM, a fieldbus
// cycle. In equation-error mode the model's force ŷ is computed from the motion, i.e. from the force that acted, so the
// logged command leads it: measured(t) = ŷ(t + d). Regressor ŷ(t + d) − ŷ(t) (linear interpolation; ≈ d·dŷ/dt) {lag d
// [s] > 0}; it is the error itself (coefficient near 1). Proposal: the signed lag of the measurement behind ŷ
// (ProposalContext::model_output_delay), when negative and at least one sample period — the other sign, a measurement
// that lags, is time_delay's (a sensor delay). Block: transport_delay on the command path (BlockPlacement::kOnCommand,
// blocks/transport_delay.cc). Source: DIAGNOSIS.md, "Delay sign"; for a small delay the residual ≈ −delay·dŷ/dt (Ljung,
// System Identification, 2nd ed., §16.6, residual analysis).
// Simulation mode (EffectTraits::command_path): the plant receives the model's drive force u
// (DiagnosisSignals::drive_force) d late, so the force it lacks — a load — is u(t) − u(t − d), along the command the
// loop gives with the lag (CommandPathLoad); it reaches the position through the closed loop. d minimises the base's
// refit of the residual less that load through the loop (its coefficient held at 1) over [1, kMaxLagSamples] sample
// periods (a log grid and a golden-section search), and is proposed inside that range. Where the diagram is at hand
// (DiagnosisSignals::simulate_effect), d is then refined, and the column built, by simulating the diagram with the
// lag's transport delay in its loop: the output-error model itself rather than its linearisation.
#include <exception>

#include <fmt/format.h>

#include "models/diagnosis/effect_proposal.h"
#include "models/diagnosis/effect_registry.h"
#include "models/diagnosis/effect_regressors.h"
#include "models/diagnosis/signal_processing.h"

namespace mb {
namespace {

constexpr const char* kName = "actuator_lag";
constexpr double kMaxLagSamples = 50.0;  // simulation mode's scan: up to this many sample periods
// Simulation mode: the range around the linearised loop's lag that the diagram's own simulation searches.
constexpr double kRefinedLow = 0.6, kRefinedHigh = 1.6;

// Simulation mode: u(t) − u(t − d), the force the plant lacks when it receives the drive force u late by d.
Eigen::VectorXd LateForce(const Eigen::VectorXd& time, const Eigen::VectorXd& u, double d) {
  return u - ShiftedInTime(time, u, d);
}

void ProposeInSimulation(ProposalContext& c) {
  const DiagnosisSignals& s = c.signals();
  const Eigen::MatrixXd base = c.BaseWithConstant();
  const Eigen::MatrixXd gram = base.transpose() * base, none(c.size(), 0);
  // The coefficient held at its physical 1: free, a shorter lag with a larger coefficient fits as well (u(t) − u(t − d)
  // ≈ d·du/dt for a small d).
  const auto sse = [&](double d) {
    const Eigen::VectorXd load =
        CommandPathLoad({kName, {}}, s, [&](const Eigen::VectorXd& u) { return LateForce(s.time, u, d); });
    const Eigen::VectorXd r = c.residual() - c.loop()->Apply(load).col(0);
    return JointFitResidual(base, gram, r)(none);
  };
  const double lo = c.sample_period(), hi = kMaxLagSamples * c.sample_period();
  double lag = MinimiseOnLogGrid(lo, hi, 25, 20, sse, true);
  if (!(lag > 1.05 * lo && lag < 0.95 * hi)) {
    c.Note(fmt::format("actuator_lag not proposed: the joint fit through the loop is best at a lag of {:.3g} ms, at "
                       "the edge of the range scanned ({:.3g}–{:.3g} ms)",
                       lag * 1e3, lo * 1e3, hi * 1e3));
    return;
  }
  if (s.simulate_effect) {
    // Refined on the diagram itself, the lag's transport delay in the loop: the scan's loop is linearised at one moving
    // stretch and the controller's reaction with it (on the independent record it put a 4 ms lag at 3.35 ms).
    const auto exact = [&](double d) {
      const Eigen::VectorXd r = c.residual() - s.simulate_effect({kName, {{"lag", d}}});
      return JointFitResidual(base, gram, r)(none);
    };
    try {
      const double scanned = lag;
      lag = MinimiseOnLogGrid(kRefinedLow * scanned, kRefinedHigh * scanned, 7, 8, exact, true);
      c.Note(fmt::format("actuator_lag's lag refined on the closed-loop diagram with its transport delay in: {:.4g} ms "
                         "through the linearised loop, {:.4g} ms simulated",
                         scanned * 1e3, lag * 1e3));
    } catch (const std::exception& e) {  // the amended diagram does not simulate: the linearised loop's lag stands
      c.Note(fmt::format("actuator_lag's lag not refined on the diagram ({}): {:.4g} ms through the linearised loop",
                         e.what(), lag * 1e3));
    }
  }
  c.Propose(kName, {{"lag", lag}});
}

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
  t.traits.command_path = true;
  t.traits.refined_parameter = "lag";
  t.traits.refinement_range = 4.0;
  t.regressors = [](const EffectInstance& e, const DiagnosisSignals& s) {
    if (s.simulate_effect) {  // simulation mode, the diagram at hand: the lag in its loop, the output's change
      PositiveParameter(e, "lag");
      return SingleColumn(e.name, s.simulate_effect(e));
    }
    if (s.drive_force.size() == s.size()) {
      const double d = PositiveParameter(e, "lag");
      return SingleColumn(e.name,
                          CommandPathLoad(e, s, [&](const Eigen::VectorXd& u) { return LateForce(s.time, u, d); }));
    }
    const Eigen::VectorXd& y = NeedModelOutput(e, s);
    return SingleColumn(e.name, ShiftedInTime(s.time, y, -PositiveParameter(e, "lag")) - y);
  };
  t.propose = [](ProposalContext& c) {
    if (c.loop() != nullptr) {  // simulation mode: a lag of the drive's force, or nothing (ŷ is the position there)
      if (c.signals().drive_force.size() == c.size()) ProposeInSimulation(c);
      return;
    }
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

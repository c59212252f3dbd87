#include "blocks/velocity_estimator.h"

#include "engine/block_roles.h"
#include "models/stability/dob_design.h"

namespace mb {

// Discrete state: [started, filter state (1)].
VelocityEstimator::VelocityEstimator(const BlockConfig& config)
    : Block(config.name),
      filter_(VelocityEstimatorFilter(config.parameters.Number("cutoff_hz"), config.sample_time->period)) {
  DeclareInputPort("x", 1, "", /*direct_feedthrough=*/true);
  DeclareOutputPort("velocity");
  DeclareDiscreteState(1 + filter_.order());
  SetSampleTime(*config.sample_time);
}

void VelocityEstimator::CalcOutput(const BlockContext& c) const {
  const auto s = c.discrete_state();
  // Before the first update the input has stood still: velocity 0.
  c.y(0) = s(0) == 0.0 ? 0.0 : FilterOutput(filter_, c.u(0), s.data() + 1);
}

void VelocityEstimator::UpdateDiscrete(const BlockContext& c) const {
  auto s = c.discrete_state();
  if (s(0) == 0.0) {
    FilterSteadyState(filter_, c.u(0), s.data() + 1);
    s(0) = 1.0;
  }
  FilterUpdate(filter_, c.u(0), s.data() + 1);
}

MB_REGISTER_BLOCK(VelocityEstimator, BlockType{
    "velocity_estimator",
    "Velocity estimate F_ẋ (Assumption 2): backward difference + first-order low-pass at cutoff_hz, "
    "v[k] = a v[k−1] + (1−a)(x[k] − x[k−1])/Ts, a = exp(−2π f_c Ts). sampleTime required; starts at rest.",
    {Bounded("cutoff_hz", 100.0, "Hz", "low-pass cut-off f_c", 1e-9, 1e12)},
    SampleTimeRule::kRequired,
    [](const BlockConfig& c) { return std::make_unique<VelocityEstimator>(c); }})

// The parts of a motion loop this block can be (engine/block_roles.h; tools/workflow/loop_from_diagram.h).
MB_REGISTER_LOOP_ROLES(VelocityEstimator, "velocity_estimator", {"pd_derivative_filter", "gp_velocity_filter"})

}  // namespace mb

#include "blocks/f_gp.h"

#include <stdexcept>

#include "engine/block_roles.h"
#include "models/stability/dob_design.h"

namespace mb {

FGp::FGp(const BlockConfig& config) : Block(config.name), weight_(config.parameters.Number("weight")) {
  if (!(weight_ >= 0.0 && weight_ < 1.0)) {
    throw std::invalid_argument(config.name + "/weight: α must satisfy 0 ≤ α < 1 (eq. 53), got " +
                                std::to_string(weight_));
  }
  filter_ = Discretize(BinomialLowPass(config.parameters.Number("cutoff_hz"), config.parameters.Integer("order")),
                       config.sample_time->period, Discretization::kZeroOrderHold);
  DeclareInputPort("mu", 1, "N", /*direct_feedthrough=*/false);
  DeclareOutputPort("d_hat_g", 1, "N");
  DeclareDiscreteState(filter_.order());
  SetSampleTime(*config.sample_time);
}

void FGp::CalcOutput(const BlockContext& c) const {
  c.y(0) = FilterOutput(filter_, 0.0, c.discrete_state().data());  // b_0 = 0: μ is not read
}

void FGp::UpdateDiscrete(const BlockContext& c) const {
  FilterUpdate(filter_, weight_ * c.u(0), c.discrete_state().data());
}

MB_REGISTER_BLOCK(FGp, BlockType{
    "f_gp",
    "GP-path filter (eq. 53): d_hat_g = F_gp{α·mu}, F_gp = binomial low-pass of `order` at cutoff_hz, ZOH, "
    "strictly proper (no feedthrough), 0 ≤ α < 1. sampleTime required.",
    {Bounded("weight", 0.5, "", "GP weight α, 0 ≤ α < 1 (α_max of eq. 62 bounds it)", 0.0, 1.0),
     Bounded("cutoff_hz", 100.0, "Hz", "F_gp cut-off frequency", 1e-9, 1e12),
     Bounded("order", 1, "", "F_gp order (binomial)", 1, 8, ParamType::kInteger)},
    SampleTimeRule::kRequired,
    [](const BlockConfig& c) { return std::make_unique<FGp>(c); }})

// The parts of a motion loop this block can be (engine/block_roles.h; tools/workflow/loop_from_diagram.h).
MB_REGISTER_LOOP_ROLES(FGp, "f_gp", {"gp_filter"})

}  // namespace mb

#pragma once
// zero_order_hold: y = u sampled at the hits, held in between (Simulink's Zero-Order Hold). Discrete.

#include "engine/block.h"
#include "engine/registry.h"

namespace mb {

/// y(t) = u(t_k) for t_k ≤ t < t_{k+1}, t_k = offset + k·Ts. Ports: in "u", out "y" (width n). Requires a
/// sampleTime [Ts, offset]; parameter width n. The input feeds through: the output at hit t_k is the input
/// computed at t_k (engine/block.h, step 1). Before the first hit (t0 < offset) the output is 0.
class ZeroOrderHold final : public Block {
 public:
  explicit ZeroOrderHold(const BlockConfig& config);
  void CalcOutput(const BlockContext& context) const override;
};

}  // namespace mb

#pragma once
// abs: y = |u| — Simulink's Abs block (a speed from a velocity: |v| × a ripple is a ripple that grows with speed).
// Inherited sample time; u feeds through.

#include "engine/block.h"
#include "engine/registry.h"

namespace mb {

/// y = |u|. Ports: in "u", out "y" (width 1, the unit of u). No parameters. The output's slope jumps at u = 0: in
/// simulation mode a variable-step solver steps over the kink as over Simulink's Abs with zero-crossing detection off.
/// Source: MathWorks, Simulink "Abs" block reference.
class Abs final : public Block {
 public:
  explicit Abs(const BlockConfig& config);
  void CalcOutput(const BlockContext& context) const override;
};

}  // namespace mb

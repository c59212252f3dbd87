#pragma once
// sqrt: y = √u — Simulink's Sqrt block, its output held at 0 below u = 0. Inherited sample time; u feeds through.

#include "engine/block.h"
#include "engine/registry.h"

namespace mb {

/// y = √max(u, 0). Ports: in "u", out "y" (width 1, the square root of u's unit). No parameters. Below 0 the output
/// is 0, not NaN (Simulink's real-valued Sqrt gives NaN there): a signal that rounding takes a hair below 0, as
/// 1 − 4r at the largest share r = 1/4 a saturating force constant allows (tools/workflow/suggest.cc), stays a number
/// in a loop that never throws. Throws nothing. Source: MathWorks, Simulink "Sqrt" block reference.
class Sqrt final : public Block {
 public:
  explicit Sqrt(const BlockConfig& config);
  void CalcOutput(const BlockContext& context) const override;
};

}  // namespace mb

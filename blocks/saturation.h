#pragma once
// saturation: y = min(max(u, lower), upper) (Simulink's Saturation). Inherited sample time.

#include "engine/block.h"
#include "engine/registry.h"

namespace mb {

/// y = clamp(u, lower, upper), element-wise. Ports: in "u", out "y" (width n). Parameters: lower, upper
/// (defaults −1, 1; unit free), width n. No zero crossings are declared at the limits: the kinks are
/// continuous in y, CVODE's error control handles them (set the solver's max_step when a limit must be resolved
/// finely). @throws std::invalid_argument if lower > upper.
class Saturation final : public Block {
 public:
  explicit Saturation(const BlockConfig& config);
  void CalcOutput(const BlockContext& context) const override;

 private:
  double lower_;
  double upper_;
};

}  // namespace mb

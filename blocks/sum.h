#pragma once
// sum: y = Σ s_i·u_i with signs from a string such as "+-+" (Simulink's Sum block). Inherited sample time.

#include <vector>

#include "engine/block.h"
#include "engine/registry.h"

namespace mb {

/// y = Σ_i s_i u_i. Ports: inputs "u1" … "uN" (N = number of signs, width n each), out "y" (width n).
/// Parameter `signs`: a string of '+' and '-' (default "++"). @throws std::invalid_argument for other characters.
class Sum final : public Block {
 public:
  explicit Sum(const BlockConfig& config);
  void CalcOutput(const BlockContext& context) const override;

 private:
  std::vector<double> signs_;
};

}  // namespace mb

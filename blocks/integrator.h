#pragma once
// integrator: ẋ = u, y = x, x(0) = x0 (Simulink's Integrator, continuous). Output does not feed through.

#include "engine/block.h"
#include "engine/registry.h"

namespace mb {

/// ẋ = u, y = x. Ports: in "u", out "y" (width n). Parameters: initial_condition x0 (scalar or n-vector),
/// width n. The input has no direct feedthrough, so an integrator breaks algebraic loops.
class Integrator final : public Block {
 public:
  explicit Integrator(const BlockConfig& config);
  void Initialize(const BlockContext& context) const override;
  void CalcOutput(const BlockContext& context) const override;
  void CalcDerivatives(const BlockContext& context) const override;

 private:
  Eigen::VectorXd initial_condition_;
};

}  // namespace mb

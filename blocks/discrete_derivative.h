#pragma once
// discrete_derivative: y[k] = K·(u[k] − u[k−1])/Ts (Simulink's Discrete Derivative), the rate of a sampled signal.

#include "engine/block.h"
#include "engine/registry.h"

namespace mb {

/// y[k] = K·(u[k] − u[k−1])/Ts, the backward difference of the input over the sample period Ts [s]. Ports: in "u"
/// (feeds through), out "y" [unit of u per second × unit of K]. Parameters: gain K. Requires a sampleTime
/// [Ts, offset]. The first output is 0: u[−1] is taken as u[0] — a signal that starts away from 0 (a temperature, a
/// logged column) gives no kick, where Simulink's default initial condition (0) gives K·u[0]/Ts once.
/// Source: the Discrete Derivative block of Simulink's Discrete library; Franklin, Powell & Workman, Digital Control of
/// Dynamic Systems, 3rd ed., §6.2 (backward difference).
class DiscreteDerivative final : public Block {
 public:
  explicit DiscreteDerivative(const BlockConfig& config);
  void Initialize(const BlockContext& context) const override;
  void CalcOutput(const BlockContext& context) const override;
  void UpdateDiscrete(const BlockContext& context) const override;

 private:
  double gain_;
  double period_;  // Ts [s]
};

}  // namespace mb

#pragma once
// speed_dependent_saturation: a saturation whose limits fall with the speed in the direction of motion — a drive that
// runs out of voltage at speed. A winding of resistance R on a bus of voltage V_bus, with force constant k_t and
// back-EMF constant k_e, can drive at most i = (±V_bus − k_e·v)/R in steady state: the force lies in
// [lower − k·v, upper − k·v] with upper = −lower = k_t·V_bus/R and k = k_t·k_e/R. Simulink: a Saturation Dynamic
// whose "up" and "lo" inputs are upper − k·v and lower − k·v (a Gain of −k on v and two Bias blocks). The block that
// adds the diagnosed effect drive_voltage_limit on the command path (docs/diagnosis.md).

#include "engine/block.h"
#include "engine/registry.h"

namespace mb {

/// y = min(max(u, lower − speed_slope·v), upper − speed_slope·v). Ports: in "u" (the command, any unit: N, N·m, A),
/// in "v" [m/s, or rad/s on a rotary axis]; out "y" (u's unit). Both inputs feed through. Parameters: upper, lower
/// (the limits at standstill, u's unit; defaults 1, −1), speed_slope k ≥ 0 (u's unit per unit of velocity: N·s/m;
/// default 0, a constant saturation). Inherited sample time; no zero crossings are declared at the limits (the kinks
/// are continuous in y, as the saturation block's). Source: the motor's voltage equation V = R·i + L·di/dt + k_e·v at
/// steady state (Hughes & Drury, "Electric Motors and Drives", §3.4). @throws std::invalid_argument if lower > upper.
class SpeedDependentSaturation final : public Block {
 public:
  explicit SpeedDependentSaturation(const BlockConfig& config);
  void CalcOutput(const BlockContext& context) const override;

 private:
  double lower_;
  double upper_;
  double slope_;
};

}  // namespace mb

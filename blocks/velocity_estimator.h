#pragma once
// velocity_estimator: F_ẋ of the paper's Assumption 2, the velocity estimate from the sampled, quantised
// encoder position: a backward difference followed by a first-order low-pass (pole a = exp(−2π f_c Ts)),
//
//   v[k] = a·v[k−1] + (1 − a)·(x[k] − x[k−1])/Ts,       F(z) = (1 − a)(1 − z⁻¹)/(Ts (1 − a z⁻¹)),
//
// unit slope at DC (a ramp v·t is estimated as v, with a lag of ≈ 1/(2π f_c) + Ts/2 s), ‖F‖₁ = 2(1 − a)/Ts =
// γ_ẋ. A single encoder count q gives a spike of (1 − a)·q/Ts: with q = 0.2 µm, Ts = 1 ms and f_c = 100 Hz,
// 0.09 mm/s. The estimator starts at rest at x(0) (no spike from a non-zero initial position). Also the
// filtered derivative of the PD (eq. 3) when applied to the tracking error.

#include "engine/block.h"
#include "engine/registry.h"
#include "models/stability/lti.h"

namespace mb {

/// Ports: in "x" (direct feedthrough), out "velocity" (unit of x per second). Parameter: cutoff_hz [Hz].
/// Requires a sampleTime. @throws std::invalid_argument for a bad cut-off.
class VelocityEstimator final : public Block {
 public:
  explicit VelocityEstimator(const BlockConfig& config);
  void CalcOutput(const BlockContext& context) const override;
  void UpdateDiscrete(const BlockContext& context) const override;

  const DiscreteTf& filter() const { return filter_; }

 private:
  DiscreteTf filter_;
};

}  // namespace mb

#pragma once
// flexible_load: a load mass on a spring–damper behind the motor (the two-mass model of a drive with one
// lightly damped structural mode), seen from the motor side: the force the load needs, given the motor's
// acceleration. Continuous; no direct feedthrough.

#include "engine/block.h"
#include "engine/registry.h"

namespace mb {

/// A load of mass m coupled to the motor by a spring k and a damper c; the encoder and the force are on the
/// motor side. With e = x_load − x_motor, ω_r = √(k/m) = 2π·frequency_hz and ζ = c/(2√(km)) = damping_ratio:
///   ë = −ω_r² e − 2ζω_r ė − a,      f = m·ẍ_load = −m(ω_r² e + 2ζω_r ė),
/// i.e. F(s) = m·(2ζω_r s + ω_r²)/(s² + 2ζω_r s + ω_r²)·A(s): m·a well below f_r (the load moves with the motor),
/// a resonant peak of height ≈ 1/(2ζ) at f_r, the load decoupled above it. Source: the two-mass model, e.g.
/// Ellis, "Control System Design Guide", 4th ed., ch. 16 (resonance with a compliant load).
/// In the motor's equation of motion (equation error: measured motion in, force out) the motor force is
/// M_motor·a + friction + f. The diagnosis' `resonance` regressors are the same terms: g = ω_r²/(s² + 2ζω_r s +
/// ω_r²)·a and ġ/ω_r, with coefficients m and 2ζm.
/// Ports: in "a" (motor acceleration [m/s²]), out "f" (force the load exerts through the spring on the motor,
/// taken with the sign of the drive force [N]). Parameters: mass m [kg] (required; any sign, a fit may
/// pass through zero), frequency_hz f_r > 0 [Hz] (required), damping_ratio ζ > 0 (default 0.02). Initial
/// state e = ė = 0 (the load at rest relative to the motor).
/// @throws std::invalid_argument (naming the parameter) for f_r ≤ 0, ζ ≤ 0 or a non-finite value.
class FlexibleLoad final : public Block {
 public:
  explicit FlexibleLoad(const BlockConfig& config);
  void CalcOutput(const BlockContext& context) const override;
  void CalcDerivatives(const BlockContext& context) const override;

 private:
  double mass_;
  double omega_;  // ω_r [rad/s]
  double zeta_;
};

}  // namespace mb

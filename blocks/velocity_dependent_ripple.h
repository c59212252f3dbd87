#pragma once
// velocity_dependent_ripple: a position-periodic ripple whose amplitude grows in proportion to the speed —
// y = |v|·Σ_{h=1..H} a_h cos(2π h (x − x₀)/P) + b_h sin(2π h (x − x₀)/P). A ripple that is a velocity-dependent
// force (a screw's or a guide's periodic damping; back-EMF ripple of a motor driven at speed) rather than a
// cogging force. The catalogue effect "velocity_dependent_ripple" of the diagnosis (docs/diagnosis.md, regressors
// |v|·cos(2πx/P), |v|·sin(2πx/P)); coefficients are usually fitted.

#include "engine/block.h"
#include "engine/registry.h"
#include "models/physics/fourier_series.h"

namespace mb {

/// Ports: in "x" [m], in "v" [m/s]; out "y" (unit of coefficient × m/s, e.g. N with coefficients in N·s/m).
/// Parameters: period P [m] > 0, harmonics H ≥ 1, cos_coefficients a_1…a_H and sin_coefficients b_1…b_H
/// (per unit speed, empty = zeros), position_offset x₀ [m] (default 0). Inherited sample time; x and v feed
/// through. |v| is continuous, so no event is needed at a reversal.
/// @throws std::invalid_argument if a coefficient vector is neither empty nor of length H.
class VelocityDependentRipple final : public Block {
 public:
  explicit VelocityDependentRipple(const BlockConfig& config);
  void CalcOutput(const BlockContext& context) const override;

 private:
  PositionFourierSeries series_;
};

}  // namespace mb

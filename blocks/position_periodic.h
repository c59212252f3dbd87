#pragma once
// position_periodic: a force (or any signal) periodic in position — cogging at the magnet pole pitch, ripple at
// a ball screw's lead:  y = Σ_{h=1..H} a_h cos(2π h (x − x₀)/P) + b_h sin(2π h (x − x₀)/P).
// x₀ (position_offset) is the position reference of the ripple: an incremental encoder is zeroed wherever
// the machine powered up, so a ripple learned on one record is re-referenced on another by x₀ alone (one
// parameter, the same for every harmonic) while its shape (a_h, b_h) carries over.
// The catalogue effect "position_periodic" of the diagnosis (docs/diagnosis.md); coefficients are usually
// fitted (`compare --fit ripple.cos_coefficients,ripple.sin_coefficients`).

#include "engine/block.h"
#include "engine/registry.h"
#include "models/physics/fourier_series.h"

namespace mb {

/// Ports: in "x" [m], out "y" (unit of the coefficients, e.g. N). Parameters: period P [m] > 0, harmonics H ≥ 1,
/// cos_coefficients a_1…a_H and sin_coefficients b_1…b_H (empty = zeros), position_offset x₀ [m] (default 0).
/// Inherited sample time; x feeds through.
/// @throws std::invalid_argument if a coefficient vector is neither empty nor of length H.
class PositionPeriodic final : public Block {
 public:
  explicit PositionPeriodic(const BlockConfig& config);
  void CalcOutput(const BlockContext& context) const override;

 private:
  PositionFourierSeries series_;
};

}  // namespace mb

#pragma once
// position_periodic: a force (or any signal) periodic in position — cogging at the magnet pole pitch, ripple at
// a ball screw's lead:  y = Σ_{h=1..H} a_h cos(2π h x/P) + b_h sin(2π h x/P).
// The catalogue effect "position_periodic" of the diagnosis (docs/diagnosis.md); coefficients are usually
// fitted (`compare --fit ripple.cos_coefficients,ripple.sin_coefficients`).

#include "engine/block.h"
#include "engine/registry.h"

namespace mb {

/// Ports: in "x" [m], out "y" (unit of the coefficients, e.g. N). Parameters: period P [m] > 0, harmonics H ≥ 1,
/// cos_coefficients a_1…a_H and sin_coefficients b_1…b_H (empty = zeros). Inherited sample time; x feeds through.
/// @throws std::invalid_argument if a coefficient vector is neither empty nor of length H.
class PositionPeriodic final : public Block {
 public:
  explicit PositionPeriodic(const BlockConfig& config);
  void CalcOutput(const BlockContext& context) const override;

 private:
  double wavenumber_;  // 2π/P [rad/m]
  Eigen::VectorXd cos_, sin_;
};

}  // namespace mb

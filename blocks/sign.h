#pragma once
// sign: y = sign(u) — Simulink's Sign block (1 for u > 0, 0 at 0, −1 for u < 0), with an optional dead band: y = 0 for
// |u| ≤ dead_band (a friction's direction of slip from a noisy velocity), or regularised: y = tanh(u/u_r) (the friction
// block's regularization "tanh", smooth through 0). Inherited sample time; u feeds through.

#include "engine/block.h"
#include "engine/registry.h"

namespace mb {

/// y = sign(u), 0 for |u| ≤ dead_band; or y = tanh(u/u_r) when regularization_velocity u_r > 0 (then dead_band must be
/// 0). Ports: in "u", out "y" (width 1). Parameters: dead_band ≥ 0 (default 0, Simulink's Sign; the unit of u),
/// regularization_velocity u_r ≥ 0 (default 0 = none; the unit of u: m/s on a velocity). The sign's output jumps where u
/// crosses ±dead_band: in simulation mode a variable-step solver steps over the jump as it does over Simulink's Sign
/// with zero-crossing detection off; the regularised form has no jump (Armstrong-Hélouvry, Dupont, Canudas de Wit,
/// Automatica 30(7), 1994: the regularised Coulomb law).
/// @throws std::invalid_argument for a negative dead band or regularization velocity (the registry's bounds), or both
/// given.
class Sign final : public Block {
 public:
  explicit Sign(const BlockConfig& config);
  void CalcOutput(const BlockContext& context) const override;

 private:
  double dead_band_;
  double regularization_velocity_;  // u_r; 0 = the sign with its dead band
};

}  // namespace mb

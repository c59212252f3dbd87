#pragma once
// sign: y = sign(u) — Simulink's Sign block (1 for u > 0, 0 at 0, −1 for u < 0), with an optional dead band: y = 0 for
// |u| ≤ dead_band (a friction's direction of slip from a noisy velocity). Inherited sample time; u feeds through.

#include "engine/block.h"
#include "engine/registry.h"

namespace mb {

/// y = sign(u), 0 for |u| ≤ dead_band. Ports: in "u", out "y" (width 1). Parameters: dead_band ≥ 0 (default 0,
/// Simulink's Sign; the unit of u). The output jumps where u crosses ±dead_band: in simulation mode a variable-step
/// solver steps over the jump as it does over Simulink's Sign with zero-crossing detection off.
/// @throws std::invalid_argument (through the registry's bounds) for a negative dead band.
class Sign final : public Block {
 public:
  explicit Sign(const BlockConfig& config);
  void CalcOutput(const BlockContext& context) const override;

 private:
  double dead_band_;
};

}  // namespace mb

#pragma once
// hysteresis: a force that follows the stroke since the last reversal — a flexure, a preloaded guide, a friction
// damper's band, a cable — as a generalised Maxwell-slip model, i.e. a Prandtl–Ishlinskii sum of stop operators
// (Brokate & Sprekels, Hysteresis and Phase Transitions, 1996, ch. 2; Al-Bender, Lampaert & Swevers, IEEE TAC 50(11),
// 2005): n elasto-slide elements, element i a spring that slides once stretched by its break-away displacement r_i,
// then carrying its break-away force F_i. f = Σ F_i·(x − p_i)/r_i, p_i the play operator of half-width r_i on the
// position x: p_i ← clamp(p_i, x − r_i, x + r_i). Rate-independent: the same loop at any speed. The diagnosed effect
// `hysteresis` (models/diagnosis/effects/hysteresis.cc) uses the same elements as its regressors.

#include <Eigen/Core>

#include "engine/block.h"
#include "engine/registry.h"

namespace mb {

/// Ports: in "x" [m] (position), out "f" [N]. Parameters: breakaway_displacements r_1 … r_n > 0 [m] and
/// breakaway_forces F_1 … F_n [N], as many (1 ≤ n ≤ 50). Discrete (needs a sampleTime): the elements' play positions
/// p_i are the state, updated at each hit, starting at the first hit's x (every element relaxed). Direct feedthrough
/// from x. @throws std::invalid_argument for an r_i ≤ 0 or not finite, lengths that differ or are out of range, or no
/// sampleTime.
class Hysteresis final : public Block {
 public:
  explicit Hysteresis(const BlockConfig& config);
  void CalcOutput(const BlockContext& context) const override;
  void UpdateDiscrete(const BlockContext& context) const override;

 private:
  /// Element i's play position after following x (x itself before the first hit).
  double Play(const BlockContext& context, Eigen::Index i) const;
  Eigen::VectorXd displacements_, forces_;  // r_i [m], F_i [N]
};

}  // namespace mb

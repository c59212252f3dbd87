#pragma once
// f_gp: the weighted low-pass of the GP compensation path (paper eq. 53, Assumption 5),
//   d̂_g = F_gp{α·μ},  F_gp(s) = ω^n/(s + ω)^n discretised by zero-order hold, 0 ≤ α < 1,
// strictly proper (the output at hit k depends on μ up to hit k−1), so the GP path never closes an algebraic
// loop. ‖F_gp‖₁ = 1 (its impulse response is non-negative with unit sum), hence γ_g = 1 in eq. 55–58.

#include "engine/block.h"
#include "engine/registry.h"
#include "models/stability/lti.h"

namespace mb {

/// Ports: in "mu" [N] (posterior mean; no direct feedthrough), out "d_hat_g" [N]. Parameters: weight α ∈ [0, 1),
/// cutoff_hz [Hz], order n (1…8). Requires a sampleTime. @throws std::invalid_argument for bad parameters.
class FGp final : public Block {
 public:
  explicit FGp(const BlockConfig& config);
  void CalcOutput(const BlockContext& context) const override;
  void UpdateDiscrete(const BlockContext& context) const override;

  double weight() const { return weight_; }
  const DiscreteTf& filter() const { return filter_; }

 private:
  double weight_;
  DiscreteTf filter_;
};

}  // namespace mb

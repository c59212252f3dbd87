#pragma once
// transfer_function: a continuous SISO transfer function H(s) = N(s)/D(s) (Simulink's Transfer Fcn),
// realised in controllable canonical form.

#include "engine/block.h"
#include "engine/registry.h"

namespace mb {

/// H(s) = (b_0 s^m + … + b_m)/(a_0 s^n + … + a_n), coefficients in DESCENDING powers of s, proper (m ≤ n after
/// leading zeros of the numerator are dropped), a_0 ≠ 0. Ports: in "u", out "y". Parameters: numerator,
/// denominator (vectors; default 1 and [1, 1]). Initial state zero.
/// Realisation (controllable canonical form; Ogata, Modern Control Engineering, 5th ed., §9-2), after dividing
/// by a_0 and padding the numerator to n+1 entries b_0…b_n:
///   ẋ_1 = u − a_1 x_1 − … − a_n x_n,  ẋ_k = x_{k−1} (k = 2…n),
///   y = Σ_k (b_k − a_k b_0) x_k + b_0 u.
/// The input feeds through directly only when H is biproper (m = n, b_0 ≠ 0); otherwise the block breaks
/// algebraic loops like an integrator. n = 0 is a pure gain b_0/a_0.
/// @throws std::invalid_argument for an empty or all-zero denominator, a zero leading denominator coefficient,
/// or an improper H (more numerator than denominator order). An all-zero numerator is allowed (y = 0).
class TransferFunction final : public Block {
 public:
  explicit TransferFunction(const BlockConfig& config);
  void CalcOutput(const BlockContext& context) const override;
  void CalcDerivatives(const BlockContext& context) const override;

 private:
  Eigen::VectorXd a_;  // a_1 … a_n (normalised)
  Eigen::VectorXd c_;  // b_k − a_k b_0, k = 1 … n
  double d_ = 0.0;     // b_0
};

}  // namespace mb

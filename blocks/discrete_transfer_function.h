#pragma once
// discrete_transfer_function: a discrete SISO transfer function H(z) = N(z)/D(z) (Simulink's Discrete Transfer
// Fcn), realised in direct form II transposed.

#include "engine/block.h"
#include "engine/registry.h"

namespace mb {

/// H(z) = (b_0 z^m + … + b_m)/(a_0 z^n + … + a_n), coefficients in DESCENDING powers of z (Simulink's
/// convention: numerator [1], denominator [1, −0.5] is 1/(z − 0.5), a one-sample delay), proper (m ≤ n after
/// leading zeros of the numerator are dropped), a_0 ≠ 0. Ports: in "u", out "y". Parameters: numerator,
/// denominator; requires a sampleTime [Ts, offset]. Initial state zero.
/// After dividing by a_0 and padding the numerator with leading zeros to n+1 entries, H = (β_0 + β_1 z⁻¹ + … +
/// β_n z⁻ⁿ)/(1 + α_1 z⁻¹ + … + α_n z⁻ⁿ), computed at hit k in direct form II transposed (Oppenheim & Schafer,
/// Discrete-Time Signal Processing, 3rd ed., §6.5):
///   y[k] = β_0 u[k] + s_1[k],
///   s_i[k+1] = β_i u[k] − α_i y[k] + s_{i+1}[k] (i = 1…n−1),  s_n[k+1] = β_n u[k] − α_n y[k].
/// The input feeds through directly only when β_0 ≠ 0 (m = n).
/// @throws std::invalid_argument for a zero leading denominator coefficient or an improper H.
class DiscreteTransferFunction final : public Block {
 public:
  explicit DiscreteTransferFunction(const BlockConfig& config);
  void CalcOutput(const BlockContext& context) const override;
  void UpdateDiscrete(const BlockContext& context) const override;

 private:
  Eigen::VectorXd alpha_;  // α_1 … α_n
  Eigen::VectorXd beta_;   // β_1 … β_n
  double beta0_ = 0.0;
};

}  // namespace mb

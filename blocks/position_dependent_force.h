#pragma once
// position_dependent_force: a smooth force of position — a spring, a cable carrier, a magnet's attraction, a
// hardening suspension (Duffing's cubic stiffness) — as a polynomial in the normalised position
// ξ = (x − center)/half_range: f = Σ_{j=1..J} c_j ξ^j. Stateless; x feeds through.

#include <Eigen/Core>

#include "engine/block.h"
#include "engine/registry.h"

namespace mb {

/// f = Σ_j coefficients[j−1]·((x − center)/half_range)^j. Ports: in "x" [m]; out "f" [N]. Parameters: center [m],
/// half_range [m] > 0, coefficients c_1…c_J [N] (J ≥ 1; [] = zero force). With J = 3: c_1 = k_1·h,
/// c_3 = k_3·h³ for f = k_1(x − x₀) + k_3(x − x₀)³ (h = half_range) plus a quadratic term c_2.
class PositionDependentForce final : public Block {
 public:
  explicit PositionDependentForce(const BlockConfig& config);
  void CalcOutput(const BlockContext& context) const override;

 private:
  double center_, half_range_;
  Eigen::VectorXd coefficients_;
};

}  // namespace mb

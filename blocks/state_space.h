#pragma once
// state_space: a continuous linear state-space model (Simulink's State-Space).

#include "engine/block.h"
#include "engine/registry.h"

namespace mb {

/// ẋ = A x + B u, y = C x + D u, x(0) = x0. Matrices are given as ROW-MAJOR flat vectors (the same numbers as
/// MATLAB's [a11 a12; a21 a22] read row by row); the sizes follow from them: n² = |A| (n ≥ 1), m = |B|/n inputs,
/// p = |C|/n outputs, and D has p·m entries (default 0 = all zeros). Ports: in "u" (width m), out "y"
/// (width p). Parameters: A, B, C, D, x0 (scalar or n entries, default 0). The input feeds through directly
/// iff D has a non-zero entry. @throws std::invalid_argument naming the matrix whose size does not fit.
class StateSpace final : public Block {
 public:
  explicit StateSpace(const BlockConfig& config);
  void Initialize(const BlockContext& context) const override;
  void CalcOutput(const BlockContext& context) const override;
  void CalcDerivatives(const BlockContext& context) const override;

 private:
  Eigen::MatrixXd a_, b_, c_, d_;
  Eigen::VectorXd x0_;
  bool feedthrough_ = false;
};

}  // namespace mb

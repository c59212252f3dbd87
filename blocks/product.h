#pragma once
// product: element-wise product and division of its inputs (Simulink's Product, element-wise mode).

#include <vector>

#include "engine/block.h"
#include "engine/registry.h"

namespace mb {

/// y = Π_i u_i^{e_i}, element-wise, with e_i = +1 for '*' and −1 for '/' in `ops` (e.g. "*/" gives
/// y = u1 / u2; "/" alone gives y = 1/u1). Ports: inputs "u1" … "uN" (N = length of ops, width n each), out
/// "y" (width n). Parameters: ops (default "**"), width n. Inherits its sample time; all inputs feed through.
/// Division by zero follows IEEE 754 (±inf, or NaN for 0/0), as Simulink does; the callbacks cannot throw.
/// @throws std::invalid_argument for an empty `ops` or a character other than '*' and '/'.
class Product final : public Block {
 public:
  explicit Product(const BlockConfig& config);
  void CalcOutput(const BlockContext& context) const override;

 private:
  std::vector<bool> divide_;
};

}  // namespace mb

#pragma once
// constant: y = c.

#include "engine/block.h"
#include "engine/registry.h"

namespace mb {

/// y = value. Port: out "y" (width = number of entries in `value`). Parameter `value` (scalar or vector).
class Constant final : public Block {
 public:
  explicit Constant(const BlockConfig& config);
  void CalcOutput(const BlockContext& context) const override;

 private:
  Eigen::VectorXd value_;
};

}  // namespace mb

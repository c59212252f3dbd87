#pragma once
// gain: y = K·u (element-wise for a vector gain). Inherited sample time; u feeds through.

#include "engine/block.h"
#include "engine/registry.h"

namespace mb {

/// y = K u. Ports: in "u" (width n), out "y" (width n). Parameters: gain K (scalar or n-vector), width n.
class Gain final : public Block {
 public:
  explicit Gain(const BlockConfig& config);
  void CalcOutput(const BlockContext& context) const override;

 private:
  Eigen::VectorXd gain_;
};

}  // namespace mb

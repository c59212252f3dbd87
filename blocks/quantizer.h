#pragma once
// quantizer: y = q·round(u/q) (Simulink's Quantizer; round half away from zero). Inherited sample time.

#include "engine/block.h"
#include "engine/registry.h"

namespace mb {

/// y = q·round(u/q), element-wise, with std::round (halves away from zero: q = 1 maps 0.5 to 1 and −0.5 to −1).
/// Ports: in "u", out "y" (width n). Parameters: interval q > 0 (default 1, unit of u, e.g. an encoder's
/// resolution in m), width n. Models an encoder or a DAC; no zero crossings are declared at the steps.
class Quantizer final : public Block {
 public:
  explicit Quantizer(const BlockConfig& config);
  void CalcOutput(const BlockContext& context) const override;

 private:
  double interval_;
};

}  // namespace mb

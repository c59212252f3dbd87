#pragma once
// sine: y = amplitude·sin(2π·frequency_hz·t + phase) + bias (Simulink's Sine Wave, time based).

#include "engine/block.h"
#include "engine/registry.h"

namespace mb {

/// y(t) = A·sin(2π f t + φ) + b. Port: out "y". Parameters: amplitude A (default 1, unit free),
/// frequency_hz f [Hz] ≥ 0 (default 1), phase φ [rad] (default 0), bias b (default 0).
/// Continuous by default; with a `sampleTime` [Ts, offset] it is evaluated at the hits only and held in between.
class Sine final : public Block {
 public:
  explicit Sine(const BlockConfig& config);
  void CalcOutput(const BlockContext& context) const override;

 private:
  double amplitude_;
  double omega_;  // 2π f [rad/s]
  double phase_;
  double bias_;
};

}  // namespace mb

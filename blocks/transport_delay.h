#pragma once
// transport_delay: y(t) = u(t − d), a pure (transport, sampling or communication) delay, discrete with linear
// interpolation between stored samples (Simulink's Transport Delay at a fixed rate). The catalogue effect
// "time_delay" of the diagnosis (docs/diagnosis.md): the measurement lags the model by d; the delay is usually
// fitted (`motionblocks fit … --params delay.delay`).

#include "engine/block.h"
#include "engine/registry.h"

namespace mb {

/// Ports: in "u", out "y" (width 1, any unit). Parameters: delay d [s] ≥ 0. Requires a sampleTime [Ts, offset].
/// With d = (k + w)·Ts, k = floor(d/Ts), 0 ≤ w < 1, the output at hit n is
///   y[n] = (1 − w)·u[n − k] + w·u[n − k − 1],
/// u[j] the input sampled at hit j; before the first hit the input is taken as its first sample (the record is
/// extended backwards by a constant, as the diagnosis' regressor ŷ(t − d) is). u feeds through (it is read
/// for d < Ts and at the first hit). State: the last k + 1 samples (ring buffer) and their count; memory O(d/Ts).
/// @throws std::invalid_argument (from the loader) if d is negative or above 1000 s, or if d/Ts exceeds 10⁶ samples.
class TransportDelay final : public Block {
 public:
  explicit TransportDelay(const BlockConfig& config);
  void CalcOutput(const BlockContext& context) const override;
  void UpdateDiscrete(const BlockContext& context) const override;

 private:
  // u[n − j]: `current` for j = 0 or an empty buffer, else the stored sample (the oldest one beyond the start).
  double Past(const BlockContext& context, Eigen::Index j, double current) const;

  Eigen::Index whole_;     // k = floor(d/Ts)
  double fraction_;        // w = d/Ts − k
  Eigen::Index capacity_;  // K = k + 1 stored samples
};

}  // namespace mb

#pragma once
// time_periodic: a disturbance periodic in time, independent of the motion — a vibration from outside (a pump,
// a neighbouring machine, floor excitation) or the ripple of a supply:
//   y(t) = Σ_{h=1..H} a_h cos(2π h f t) + b_h sin(2π h f t).
// Linear in its coefficients (unlike sine's amplitude and phase), so a least-squares fit refits them jointly
// with the rest of the model. The catalogue effect "time_periodic" of the diagnosis (docs/diagnosis.md).

#include "engine/block.h"
#include "engine/registry.h"

namespace mb {

/// Port: out "y" (unit of the coefficients). Parameters: frequency_hz f [Hz] > 0, harmonics H ≥ 1,
/// cos_coefficients a_1…a_H and sin_coefficients b_1…b_H (empty = zeros). Time is the simulation time t [s].
/// Continuous; with a `sampleTime` [Ts, offset] it is evaluated at the hits and held in between.
/// @throws std::invalid_argument if a coefficient vector is neither empty nor of length H.
class TimePeriodic final : public Block {
 public:
  explicit TimePeriodic(const BlockConfig& config);
  void CalcOutput(const BlockContext& context) const override;

 private:
  double omega_;  // 2π f [rad/s]
  Eigen::VectorXd cos_, sin_;
};

}  // namespace mb

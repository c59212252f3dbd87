#pragma once
// time_periodic: a disturbance periodic in time, independent of the motion — a vibration from outside (a pump,
// a neighbouring machine, floor excitation) or the ripple of a supply:
//   y(t) = Σ_{h=1..H} a_h cos(h φ(t)) + b_h sin(h φ(t)),   φ(t) = 2π(f t + ½ ḟ t²),
// ḟ = 0 for a fixed frequency; ḟ ≠ 0 for a vibration whose frequency drifts (a fan speeding up: f(t) = f + ḟ t).
// Linear in its coefficients (unlike sine's amplitude and phase), so a least-squares fit refits them jointly
// with the rest of the model. The catalogue effects "time_periodic" and "drifting_vibration" of the diagnosis
// (docs/diagnosis.md).

#include "engine/block.h"
#include "engine/registry.h"

namespace mb {

/// Port: out "y" (unit of the coefficients). Parameters: frequency_hz f [Hz] > 0 (at t = 0), frequency_rate ḟ
/// [Hz/s] (default 0), harmonics H ≥ 1,
/// cos_coefficients a_1…a_H and sin_coefficients b_1…b_H (empty = zeros). Time is the simulation time t [s].
/// Continuous; with a `sampleTime` [Ts, offset] it is evaluated at the hits and held in between.
/// @throws std::invalid_argument if a coefficient vector is neither empty nor of length H.
class TimePeriodic final : public Block {
 public:
  explicit TimePeriodic(const BlockConfig& config);
  void CalcOutput(const BlockContext& context) const override;

 private:
  double omega_;  // 2π f [rad/s]
  double half_chirp_;  // π ḟ [rad/s²]: the phase is ω t + π ḟ t²
  Eigen::VectorXd cos_, sin_;
};

}  // namespace mb

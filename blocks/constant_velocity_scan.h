#pragma once
// constant_velocity_scan: the training motion of the paper's section 3.2 — back-and-forth strokes over the
// full travel (700 mm) at a set of constant velocities V = {v_1, …, v_n}, one stroke per velocity, alternating
// direction. Each stroke: half-sine-acceleration transition to ±v_i (duration T), constant velocity, the mirror
// transition to rest, then a dwell. Stroke i takes 2T + (L − v_i T)/v_i + dwell; the profile needs v_i·T ≤ L.
// Output "constant_velocity" is 1 on the constant-velocity sections (where the training windows of eq. 25 lie)
// and 0 elsewhere.

#include "blocks/paper_trajectory.h"
#include "engine/block.h"
#include "engine/registry.h"

namespace mb {

/// Ports: out "position" [m], "velocity" [m/s], "acceleration" [m/s²], "constant_velocity" (0/1). Parameters:
/// velocities [m/s] (> 0), stroke L [m], start_position [m] (one end of the stroke; the first stroke moves in +x),
/// start_time [s], transition_duration T [s], dwell [s]. Sample time optional.
/// @throws std::invalid_argument if a velocity is not positive or v_i·T > L.
class ConstantVelocityScan final : public Block {
 public:
  explicit ConstantVelocityScan(const BlockConfig& config);
  void CalcOutput(const BlockContext& context) const override;
  const SmoothVelocityProfile& profile() const { return profile_; }

 private:
  SmoothVelocityProfile profile_;
};

}  // namespace mb

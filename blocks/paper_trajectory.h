#pragma once
// paper_trajectory: the reference of the paper's Fig. 9 — 0 → 600 mm with constant-velocity sections at 150 and
// 350 mm/s, reached by smooth transitions with a half-sine acceleration over 0–0.2, 1.2–1.4 and 2.4–2.6 s:
//
//   during a transition from v₀ to v₁ starting at t_i (duration T, θ = π(t − t_i)/T):
//     a = (v₁ − v₀)·π/(2T)·sin θ,   v = v₀ + (v₁ − v₀)(1 − cos θ)/2,
//     x = x_i + v₀(t − t_i) + (v₁ − v₀)/2·((t − t_i) − (T/π) sin θ);
//   constant velocity between transitions. The defaults give exactly 15 + 150 + 50 + 350 + 35 = 600 mm.
//
// SmoothVelocityProfile (below) is the piecewise profile shared with constant_velocity_scan.

#include <vector>

#include "engine/block.h"
#include "engine/registry.h"

namespace mb {

/// A velocity profile made of constant-velocity sections joined by half-sine-acceleration transitions.
/// Immutable; Evaluate is noexcept and allocation-free.
class SmoothVelocityProfile final {
 public:
  struct Transition {
    double start_time;       ///< t_i [s]
    double duration;         ///< T [s] > 0
    double target_velocity;  ///< v after the transition [m/s]
  };
  /// Starts at rest at `start_position` [m]. @throws std::invalid_argument if a duration is not positive or the
  /// transitions overlap or are out of order (the message names the transition index).
  SmoothVelocityProfile(double start_position, std::vector<Transition> transitions);

  /// Position [m], velocity [m/s] and acceleration [m/s²] at time t [s] (rest before the first transition).
  void Evaluate(double t, double* position, double* velocity, double* acceleration) const noexcept;
  /// End of the last transition [s].
  double end_time() const noexcept;
  const std::vector<Transition>& transitions() const noexcept { return transitions_; }

 private:
  double start_position_;
  std::vector<Transition> transitions_;
  std::vector<double> position_at_start_;  // x(t_i)
  std::vector<double> velocity_before_;    // v just before transition i
};

/// Ports: out "position" [m], "velocity" [m/s], "acceleration" [m/s²]. Parameters: start_position [m],
/// velocities [m/s] (the velocity after each transition), transition_starts [s], transition_duration [s]
/// (one value, or one per transition), time_advance [s]: the outputs are the profile at t + time_advance. A
/// feedforward held over a sample period (ZOH) lags the continuous one by Ts/2; computing it from a copy of the
/// reference with time_advance = Ts/2 (mid-interval sampling) removes that lag to O(Ts²) (docs/paper.md).
/// Sample time optional (discrete when given).
class PaperTrajectory final : public Block {
 public:
  explicit PaperTrajectory(const BlockConfig& config);
  void CalcOutput(const BlockContext& context) const override;
  const SmoothVelocityProfile& profile() const { return profile_; }

 private:
  SmoothVelocityProfile profile_;
  double time_advance_;
};

}  // namespace mb

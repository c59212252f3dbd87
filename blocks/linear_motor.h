#pragma once
// linear_motor: the digital twin of the paper's iron-core linear-motor stage (section 2.1, 5.1, 5.3).
//
//   (M + m_p)·ẍ + B·ẋ = u + d,     d = F_cog(x, ẋ) − F_f(ẋ)                                       [N]
//   F_cog: cogging of eq. 2 with harmonics of the pole pitch τ (models/physics/cogging.h)
//   F_f:   Stribeck/Coulomb friction with velocity-dependent viscous term b₂ẋ|ẋ| (models/physics/stribeck.h)
//   x_enc = q_e·floor((x + q)/q_e): encoder with resolution q_e (0.2 µm), q an optional structural mode
//           (models/physics/resonance.h); q ≡ 0 when resonance_modal_gain = 0.
//
// The DOB's nominal model is M_n = 0.2621, B_n = 3 (DESIGN.md); the twin's true M, B may differ, and the
// payload m_p (section 5.3) adds to the moving mass only — so the DOB sees (M + m_p − M_n)ẍ + (B − B_n)ẋ − d as
// the lumped disturbance. A payload_time > 0 puts the payload on mid-run (a load picked up: the moving mass steps
// from M to M + m_p at that time, located as a zero crossing). Continuous; u does not feed through. Defaults: the calibration of docs/paper.md.

#include "engine/block.h"
#include "engine/registry.h"
#include "models/physics/cogging.h"
#include "models/physics/resonance.h"
#include "models/physics/stribeck.h"

namespace mb {

/// Ports: in "u" [N] (force command); out "x" [m] (encoder, quantised, includes the resonance), "x_true" [m]
/// (rigid-body position), "velocity" [m/s], "disturbance" [N] (d above). Continuous states [x, ẋ] (+ [q, q̇] with
/// a resonance). Parameters: see the registration (every one with its unit). @throws std::invalid_argument for
/// non-physical values (the message names the parameter).
class LinearMotor final : public Block {
 public:
  explicit LinearMotor(const BlockConfig& config);
  void Initialize(const BlockContext& context) const override;
  void CalcOutput(const BlockContext& context) const override;
  void CalcDerivatives(const BlockContext& context) const override;
  void CalcZeroCrossings(const BlockContext& context) const override;
  bool UpdateModes(const BlockContext& context) const override;

  /// d(x, ẋ) [N] (cogging minus friction).
  double Disturbance(double x, double xdot) const noexcept { return cogging_.Force(x, xdot) - friction_.Force(xdot); }
  /// M + m_p: the moving mass once the payload is on (from payload_time).
  double moving_mass() const { return mass_; }
  double damping() const { return damping_; }

 private:
  double mass_;  // M + m_p
  double mass_without_payload_;  // M: before payload_time
  // 1/(M + m_p) and 1/M: the derivative multiplies by them rather than dividing, which takes a division's latency
  // (≈ 15 cycles) off each RK4 stage's dependency chain; the result differs from the quotient by ≤ 2 ulp.
  double inverse_mass_;
  double inverse_mass_without_payload_;
  double payload_time_;          // the payload is on for t ≥ payload_time_ (mode in x_d(0) when > 0)
  double damping_;
  double initial_position_;
  double initial_velocity_;
  double encoder_resolution_;
  CoggingForce cogging_;
  StribeckFriction friction_;
  StructuralResonance resonance_;
};

}  // namespace mb

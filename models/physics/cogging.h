#pragma once
// Cogging force of an iron-core linear motor, periodic in position with the pole pitch τ, with a
// velocity-dependent amplitude α(ẋ) and offset β(ẋ) — the paper's eq. 1–2 generalised to harmonics of τ:
//
//   F_cog(x, ẋ) = α(ẋ) · Σ_{h=1..H} r_h · sin(2π h x/τ + φ_h) + β(ẋ)                      [N]
//   α(ẋ) = α_0 + α_1·|ẋ|,        β(ẋ) = β_0 + β_1·ẋ + β_2·ẋ·|ẋ|
//
// Source: Jung et al., eq. 1–2 (τ = 22.5 mm for the Kovery 2P-06 stage); harmonics of the pole pitch as in
// Tan et al. 2004 (force ripple of PM linear motors). With r = [1] and α_1 = β_* = 0 this is eq. 1.

#include <cmath>

#include <Eigen/Core>

namespace mb {

struct CoggingParameters {
  double pole_pitch = 0.0225;       ///< τ [m], > 0
  double amplitude = 0.0;           ///< α_0 [N]
  double amplitude_velocity = 0.0;  ///< α_1 [N·s/m]: amplitude growth with speed
  Eigen::VectorXd harmonics = Eigen::VectorXd::Ones(1);  ///< r_h, relative amplitude of harmonic h = 1..H
  Eigen::VectorXd phases = Eigen::VectorXd::Zero(1);     ///< φ_h [rad], same length as harmonics
  double offset = 0.0;              ///< β_0 [N]
  double offset_velocity = 0.0;     ///< β_1 [N·s/m]
  double offset_velocity_squared = 0.0;  ///< β_2 [N·s²/m²]
};

/// Evaluates F_cog. Immutable after construction; Force is noexcept and allocation-free.
class CoggingForce final {
 public:
  /// @throws std::invalid_argument if τ ≤ 0, the harmonic and phase vectors differ in length or are empty, or
  /// any value is not finite.
  explicit CoggingForce(CoggingParameters parameters);

  /// F_cog(x, ẋ) [N] at position x [m], velocity ẋ [m/s]. Inline with α and β (the plant's hot path: no calls
  /// around Shape on each derivative evaluation's dependency chain).
  double Force(double x, double xdot) const noexcept { return Amplitude(xdot) * Shape(x) + Offset(xdot); }
  /// The position-periodic shape Σ r_h sin(2π h x/τ + φ_h) (dimensionless).
  double Shape(double x) const noexcept;
  /// α(ẋ) [N] and β(ẋ) [N].
  double Amplitude(double xdot) const noexcept { return p_.amplitude + p_.amplitude_velocity * std::abs(xdot); }
  double Offset(double xdot) const noexcept {
    return p_.offset + p_.offset_velocity * xdot + p_.offset_velocity_squared * xdot * std::abs(xdot);
  }

  const CoggingParameters& parameters() const noexcept { return p_; }

 private:
  CoggingParameters p_;
  double wavenumber_;  // 2π/τ [rad/m]
  // r_h sin(hθ + φ_h) = (r_h cos φ_h) sin hθ + (r_h sin φ_h) cos hθ: one sin/cos pair per call, then the
  // angle-addition recurrence over h.
  Eigen::VectorXd sin_weight_, cos_weight_;
};

}  // namespace mb

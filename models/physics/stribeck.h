#pragma once
// Velocity-dependent friction of a linear guide: a Stribeck curve with a regularised sign, plus a
// velocity-dependent viscous term (the damping that "varies with velocity", paper §2.1):
//
//   F_f(ẋ) = s(ẋ)·[F_c + (F_s − F_c)·exp(−(ẋ/v_s)²)] + b_2·ẋ·|ẋ|                           [N]
//   s(ẋ) = tanh(ẋ / v_reg)
//
// The force opposes motion (the plant subtracts it). The linear viscous part B·ẋ belongs to the rigid body.
// Source: Armstrong-Hélouvry, Dupont & Canudas de Wit, "A survey of models, analysis tools and compensation
// methods for the control of machines with friction", Automatica 30(7), 1994 (Stribeck curve, eq. 4);
// the tanh regularisation is the usual smooth approximation (no stiction: at ẋ = 0 the force is 0). The law itself
// is RegularizedFriction of models/physics/friction.h (the friction block's regularization "tanh"), plus b_2·ẋ|ẋ|.
// Choose v_reg so that (F_s/v_reg)/M is well inside the solver's stability region (RK4: h·F_s/(v_reg·M) < 2.5).

namespace mb {

struct StribeckParameters {
  double coulomb = 0.0;               ///< F_c [N] ≥ 0
  double static_friction = 0.0;       ///< F_s [N] ≥ 0 (breakaway level; F_s = F_c gives pure Coulomb)
  double stribeck_velocity = 0.01;    ///< v_s [m/s] > 0
  double viscous_squared = 0.0;       ///< b_2 [N·s²/m²]
  double regularization_velocity = 1e-3;  ///< v_reg [m/s] > 0
};

class StribeckFriction final {
 public:
  /// @throws std::invalid_argument for negative levels, non-positive v_s or v_reg, non-finite values.
  explicit StribeckFriction(StribeckParameters parameters);
  /// F_f(ẋ) [N], opposing ẋ. noexcept, allocation-free.
  double Force(double xdot) const noexcept;
  const StribeckParameters& parameters() const noexcept { return p_; }

 private:
  StribeckParameters p_;
};

}  // namespace mb

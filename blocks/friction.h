#pragma once
// friction: viscous + Coulomb + Stribeck friction with a Karnopp stick model; the slip direction and the stick
// state are a discrete mode switched only at located events (models/physics/friction.h).

#include "engine/block.h"
#include "engine/registry.h"
#include "models/physics/friction.h"

namespace mb {

/// F = the friction force resisting the motion, positive along +v: connect it with a minus sign,
/// M·ẍ = f_applied − F (e.g. sum "+-" into rigid_body.f).
/// Ports: in "v" [m/s]; in "f_applied" [N] (only with stick_model "karnopp": the sum of all other forces on the
/// body, the force the friction balances while stuck); out "f" [N]. Both inputs feed through.
/// Parameters: viscous σ [N·s/m], coulomb F_c [N], static F_s [N] ≥ F_c (breakaway), stribeck_velocity v_s
/// [m/s] (0 = off), stick_model "karnopp" (default) or "none", stick_velocity [m/s] (default 1e-6).
/// Modes (discrete state x_d[0] = −1, 0, +1; models/physics/friction.h gives the equations and transitions):
///  - slipping in s = ±1: F = s·(F_c + (F_s − F_c)e^{−(v/v_s)²}) + σ v; zero crossing g_0 = v, g_1 = 1;
///  - stuck (karnopp): F = f_applied (the body does not accelerate); zero crossings g_0 = F_s − f_applied,
///    g_1 = F_s + f_applied (breakaway in either direction).
/// The right-hand side uses the mode, never sign(v); UpdateModes applies NextFrictionMode at each located
/// crossing and at every major step, and the engine iterates until the mode is consistent.
/// Initial mode: stuck; the first consistency check (at the start time) switches to slip when |v| >
/// stick_velocity or |f_applied| > F_s.
/// Stick band (Karnopp's DV, step-aware): a body that sticks keeps the velocity v_0 it had at the located crossing
/// (|v_0| within CVODE's root tolerance; up to a·h with fixed-step solvers, which locate a crossing only to the end
/// of a step h); it stays stuck while |v| ≤ max(stick_velocity, kStickBandFactor·|v_0|), so a fixed-step solver
/// does not chatter between stick and slip at every step (x_d[1] holds the band while stuck, 0 while slipping).
/// The stuck body drifts at v_0 (≤ a·h): use CVODE where that drift matters. With stick_model "none" (no f_applied input) the direction follows v at each crossing and a
/// body that should come to rest chatters; use it only for motions that keep moving.
/// Regularisation (regularization "tanh", stick_model "none"): no modes, no events, F = RegularizedFriction
/// (models/physics/friction.h) = tanh(v/v_reg)·(F_c + (F_s − F_c)e^{−(v/v_s)²}) + σv with v_reg =
/// regularization_velocity [m/s] > 0 — the same law as the linear_motor's Stribeck friction, smooth through v = 0
/// (what a fitted model of a machine that dwells at rest often needs). Default "none": the event-driven law above.
/// @throws std::invalid_argument for negative or non-finite parameters, static < coulomb, an unknown
/// stick_model, regularization "tanh" with stick_model "karnopp" or regularization_velocity 0.
class Friction final : public Block {
 public:
  explicit Friction(const BlockConfig& config);
  void CalcOutput(const BlockContext& context) const override;
  void CalcZeroCrossings(const BlockContext& context) const override;
  bool UpdateModes(const BlockContext& context) const override;

  /// The stick band is this multiple of the velocity at which the stick began (room for the small acceleration of
  /// forces the stick does not balance, e.g. an offset).
  static constexpr double kStickBandFactor = 2.0;

  /// The mode stored in a context's discrete state (for tests and inspection).
  static FrictionMode Mode(const BlockContext& context);

 private:
  double AppliedForce(const BlockContext& context) const { return stick_ ? context.u(1) : 0.0; }

  FrictionParameters friction_;
  bool stick_ = true;
  double stick_velocity_;
  double regularization_velocity_ = 0.0;  ///< > 0: regularization "tanh" (no modes)
};

}  // namespace mb

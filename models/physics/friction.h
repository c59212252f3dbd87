#pragma once
// Friction on one axis: viscous + Coulomb + Stribeck, with a Karnopp stick model kept as a discrete mode.
//
// Sign convention (used by the friction block and the plant models): F is the friction force RESISTING the
// motion, positive along +v: the body's equation is M·ẍ = f_applied − F. While slipping in direction s = ±1
//   F_slip(v, s) = s·(F_c + (F_s − F_c)·exp(−(v/v_s)²)) + σ·v          (Stribeck; v_s = 0 turns the hump off)
// with F_c the Coulomb force, F_s the static (breakaway) force ≥ F_c, v_s the Stribeck velocity and σ the
// viscous coefficient. While stuck (Karnopp 1985) the friction balances the applied force,
//   F_stick = f_applied  (|f_applied| ≤ F_s by construction of the mode),
// so the net force on the body is zero.
//
// The direction s is a MODE, frozen between events: the right-hand side never evaluates sign(v) (Modelica
// Standard Library's lesson, DESIGN.md). The event logic (NextFrictionMode) switches it when v reaches zero
// (slip → stick or reversal) and when |f_applied| exceeds F_s (stick → slip).
// Sources: D. Karnopp, "Computer simulation of stick-slip friction in mechanical dynamic systems", J. Dyn.
// Sys. Meas. Control 107 (1985); B. Armstrong-Hélouvry et al., "A survey of models, analysis tools and
// compensation methods for the control of machines with friction", Automatica 30(7) (1994) (Stribeck curve);
// Modelica.Mechanics.Translational.Components.MassWithStopAndFriction (mode handling).

#include <string>

namespace mb {

/// Friction parameters, SI units.
struct FrictionParameters {
  double viscous = 0.0;            ///< σ [N·s/m], ≥ 0
  double coulomb = 0.0;            ///< F_c [N], ≥ 0
  double breakaway = 0.0;          ///< F_s [N], ≥ F_c: the static friction a force must exceed to start motion
  double stribeck_velocity = 0.0;  ///< v_s [m/s], ≥ 0; 0 = no Stribeck hump (F_slip = s·F_c + σ·v)
};

/// Stick/slip mode, stored as a double in a block's discrete state (−1, 0, +1).
enum class FrictionMode : int { kSlipNegative = -1, kStuck = 0, kSlipPositive = 1 };

/// Throws std::invalid_argument, prefixed by `where` (e.g. "friction 'fr'"), unless every parameter is finite
/// and ≥ 0 and breakaway ≥ coulomb.
void ValidateFrictionParameters(const FrictionParameters& p, const std::string& where);

/// The Stribeck level F_c + (F_s − F_c)·exp(−(v/v_s)²) [N] (F_c when v_s = 0): the magnitude of the sliding friction
/// at velocity v [m/s], whatever gives its sign (the mode here, tanh(v/v_reg) in RegularizedFriction and
/// models/physics/stribeck.h). One law for every friction model of the project.
double StribeckLevel(double coulomb, double breakaway, double stribeck_velocity, double velocity) noexcept;

/// The regularised law, smooth through v = 0 and without modes (no stiction: F(0) = 0):
///   F(v) = tanh(v/v_reg)·(F_c + (F_s − F_c)·exp(−(v/v_s)²)) + σ·v   [N],  v_reg = regularization_velocity > 0.
/// The usual smooth approximation of Coulomb friction (e.g. Andersson, Söderberg & Björklund, "Friction models for
/// sliding dry, boundary and mixed lubricated contacts", Tribology International 40 (2007), eq. 6). Choose v_reg so
/// that σ_eff = F_s/v_reg keeps h·σ_eff/M inside a fixed-step solver's stability region.
double RegularizedFriction(const FrictionParameters& p, double regularization_velocity, double velocity) noexcept;

/// F_slip(v, s) [N] for a slip direction s (kSlipPositive or kSlipNegative) at velocity v [m/s]. Uses s, never
/// sign(v). kStuck gives σ·v (no Coulomb part).
double SlidingFriction(const FrictionParameters& p, FrictionMode mode, double velocity) noexcept;

/// The friction force [N] in `mode`: F_slip(v, s) while slipping, the applied force while stuck (clamped to
/// ±F_s, which only matters between a breakaway and its located event).
double FrictionForce(const FrictionParameters& p, FrictionMode mode, double velocity,
                     double applied_force) noexcept;

/// The mode consistent with the current velocity and applied force, starting from `mode` (one step of the
/// event iteration; call again until it returns its argument).
///  - slipping in s and s·v > 0: unchanged;
///  - slipping in s and s·v ≤ 0 (v reached zero or reversed): stuck if `stick` and |f_applied| < F_s, else
///    slip along f_applied (stick) or along v (no stick model; unchanged while v = 0 exactly);
///  - stuck: slip along f_applied if |f_applied| ≥ F_s (and f_applied ≠ 0), slip along v if |v| >
///    stick_velocity (a body started with a velocity, or a stick entered late by a fixed-step solver), else stuck.
/// The thresholds are asymmetric (≥ to break away, < to stick) so that a crossing located exactly on
/// |f_applied| = F_s (CVODE often returns g = 0 exactly) switches and the iteration cannot flip back and forth.
/// `stick` = false is the slip-only model (no applied-force input): the direction follows v at each event.
FrictionMode NextFrictionMode(const FrictionParameters& p, FrictionMode mode, double velocity,
                              double applied_force, bool stick, double stick_velocity) noexcept;

/// The static friction curve without modes, for fitting and diagnosis (not for simulation across v = 0):
/// F(v) = F_slip(v, sign v) for v ≠ 0 and 0 at v = 0.
double SteadyStateFriction(const FrictionParameters& p, double velocity) noexcept;

}  // namespace mb

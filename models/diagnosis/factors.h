#pragma once
// The factors of the diagnosis grammar (DIAGNOSIS.md, "Beyond the catalogue: effects as products of physical
// factors"): a candidate effect is a product of a factor of the position — periodic (period P, K harmonics) or local (a
// bump over a stretch of the travel) — with a factor of the motion or the force: 1, sign(v) (with the dead band), |v|,
// the model's force ŷ (the force constant; built from the measured motion, never from the compared output). The
// catalogue's effects are named special cases: velocity_dependent_ripple is |v| × periodic(x), friction_drift
// v × ramp(t). effects/factor_products.cc registers the products; docs/diagnosis.md holds the table from factor pairs
// to physics. What the factors share with the proposal rules — the period of a modulated ripple and the place of a
// local one — is here.
//
// Units: SI (x [m], v [m/s], periods and widths [m]); a multiplier's unit is its signal's.

#include <optional>
#include <string>

#include <functional>

#include <Eigen/Core>

#include "models/diagnosis/effect_catalogue.h"
#include "models/diagnosis/effect_proposal.h"

namespace mb {

/// The factor of the motion or the force that multiplies a position factor.
enum class Multiplier {
  kOne,         ///< 1: a force of the position alone
  kSlip,        ///< tanh(v/v_s), the direction of slip as a regularised Coulomb law has it: a friction
  kSpeed,       ///< |v|: a damping
  kVelocity,    ///< v: a damping (a viscous force)
  kAcceleration,  ///< a: an inertia
  kModelForce,  ///< ŷ, the model's force from the measured motion (equation-error mode): a force constant
};

/// The multiplier's column on the signals (N). kSlip needs `slip_velocity` v_s > 0 [m/s] (else std::invalid_argument);
/// kModelForce needs DiagnosisSignals::model_output (else std::invalid_argument naming `effect`).
Eigen::VectorXd MultiplierColumn(Multiplier multiplier, const DiagnosisSignals& signals, double slip_velocity,
                                 const std::string& effect);

/// The slip velocity v_s of a friction factor tanh(v/v_s): of the log grid dead_band·2^−k, k = 0..5 (the context's dead
/// band, 1 % of the top speed, down to 1/32 of it), the one whose `columns(tanh(v/v_s))` (N × k) leave the least of the
/// residual in a joint fit with the base. A friction of the generator's or the machine's own law near zero velocity: a
/// sign with a dead band leaves the approach to rest (0.5–2 mm/s) and the dwell wrong.
double BestSlipVelocity(const ProposalContext& context,
                        const std::function<Eigen::MatrixXd(const Eigen::VectorXd& slip)>& columns);

/// A column the diagram does not read (DiagnosisSignals::extra_columns) is no new signal when its squared correlation
/// with the compared output, the position or the velocity reaches this: the same signal in another unit (EMPS logs
/// input_V beside force_N, reference_m beside position_m).
inline constexpr double kDuplicateColumnCorrelation = 0.98;

/// What unread column k duplicates ("the compared output (the logged command)", "the position", "the velocity"), or
/// nullptr when it is a new signal. k < signals.extra_columns.size().
const char* UnreadColumnDuplicate(const DiagnosisSignals& signals, std::size_t k);

/// The unread column an effect's parameter "column" names (its index in DiagnosisSignals::extra_columns). Throws
/// std::invalid_argument when the index is not one of them (a record carried to another must hold the same columns).
const Eigen::VectorXd& UnreadColumn(const EffectInstance& effect, const DiagnosisSignals& signals);

/// `column` less its mean over the record (N): the grammar's factor of an unread column. Its constant part belongs to
/// the base — alone the offset, times v the viscous coefficient, times the direction of slip the Coulomb level — and
/// would make the product look "already in the model" (an oil temperature of 30 ± 4 °C times v is 99.5 % the base's v).
Eigen::VectorXd Centered(const Eigen::VectorXd& column);

/// The bump of a local factor: cos²(π(x − c)/(2w)) for |x − c| < w, else 0 — one at the centre c, zero with zero slope
/// at c ± w (a raised cosine of width 2w; N).
Eigen::VectorXd Bump(const Eigen::VectorXd& position, double center, double half_width);

/// The period of a position ripple that `modulation` multiplies (sign(v) for a friction along the pitch, ŷ for a
/// force-constant ripple), from the periodogram of the demodulated residual r/m over the samples moving faster than
/// the dead band whose |m| reaches its median there: periods from the periodogram's automatic minimum up to a third of
/// the travel (three cycles, DIAGNOSIS.md "Few cycles"). The strongest significant independent peak, its harmonics
/// flagged (at most CatalogueOptions::max_harmonics); nullopt when there is none or too few samples (< 256).
std::optional<ProposedPeriod> ModulatedPeriod(const ProposalContext& context, const Eigen::VectorXd& modulation);

/// A local factor's place: the centre and half-width minimising the joint fit of the residual on
/// [base, 1, m·Bump(x; c, w)], over half-widths of 1/40, 1/20 and 1/10 of the travel and centres every w/2 from 2w inside
/// either end of the travel (the axis passes through the stretch; at an end a bump is confounded with the reversals),
/// then refined by Brent's method (Boost.Math): the centre within ± w/2 of the grid's best, the half-width within
/// [w/√2, √2·w] but at most a tenth of the travel, the centre again (a grid of w/2 left a weak magnet's stretch 4.8 mm
/// off its 92 mm centre).
struct BumpPlace {
  double center = 0.0, half_width = 0.0;  ///< [m]
  double explained = 0.0;                 ///< share of the residual's sum of squares the bump removes, 0..1
};
/// `m` the multiplier's column (N). Throws nothing; explained 0 when the position does not move.
BumpPlace ScanBump(const ProposalContext& context, const Eigen::VectorXd& m);

/// A proposed position period of at least 16 cycles in the travel that holds at least 2 % of the residual's variance: a
/// ripple that a smooth function of the position (position_dependent_force, friction_along_travel) would only blur, so
/// the smooth one is not proposed while it is there (on EMPS the screw lead's 2.5 mm holds 8.3 %: the cubic took 18.6 %
/// and a cubic × sign(v) 11 % before the ripple; once the ripple is in the model, improve's next round proposes them).
/// nullopt when there is none.
std::optional<ProposedPeriod> RippleASmoothFunctionWouldBlur(const ProposalContext& context);

}  // namespace mb

#pragma once
// The factors of the diagnosis grammar (DIAGNOSIS.md, "Beyond the catalogue" and "Generated, not listed"; issue 45): a
// candidate effect is a product of a row of the multipliers' table — what the force is proportional to (1, the
// direction of slip, v, |v|, v·|v|, a, the model's force ŷ, ŷ·|ŷ|, |ŷ|·slip) — and a row of the modulators' table —
// what it varies with (1, periodic, local or smooth in the position, an unread log column or its rate, a ramp, a step,
// a window or a warm-up in time). The tables are in factor_tables.cc, their cross product in
// effects/factor_products.cc; what their shape scans share with the catalogue's proposal rules (the period of a
// modulated ripple, the place of a local one, the slip velocity) is here.
//
// Units: SI (x [m], v [m/s], t [s], periods and widths [m]); a multiplier's unit is its signal's.

#include <functional>
#include <map>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "models/diagnosis/effect_catalogue.h"
#include "models/diagnosis/effect_proposal.h"
#include "models/diagnosis/effect_registry.h"

namespace mb {

/// Shape parameters of a factor by name (SI), as EffectInstance::parameters holds them.
using FactorParameters = std::map<std::string, double>;

/// A row of the multipliers' table (issue 45): what the force is proportional to. Every row crosses every row of the
/// modulators' table (effects/factor_products.cc); a new physical multiplier is one row here and nothing else.
struct MultiplierRow {
  const char* id;       ///< stable: "slip" (compare.json's "multiplier")
  const char* noun;     ///< its part of a pair's name: "damping" (damping_ripple, damping_step, …)
  const char* phrase;   ///< in the field's words: "the Coulomb friction level"
  const char* formula;  ///< "tanh(v/v_s)"
  const char* physics;  ///< what it usually is on a machine
  const char* unit;     ///< the unit of what the modulator's coefficient multiplies: "" (a force), "m/s", "N"
  bool slip = false;    ///< holds the direction of slip tanh(v/v_s): the pair has the parameter slip_velocity
  /// Holds ŷ, the model's drive force: from the measured motion in equation-error mode, the simulated controller's in
  /// simulation mode (DiagnosisSignals::drive_force; not proposed when the comparison found none).
  bool model_force = false;
  bool odd_in_velocity = false;  ///< reverses with v: one way of travel, it is its even twin and is not proposed
  bool lagrange = false;  ///< a mass: times a factor of the position it acts as M(x)·a + ½M′(x)·v² (Lagrange)
  /// Its column (N) on the signals, given the direction of slip `slip` (N): tanh(v/v_s) in a regressor, sign(v) with
  /// the dead band in a shape scan. Throws std::invalid_argument naming `effect` when ŷ is needed and absent.
  std::function<Eigen::VectorXd(const DiagnosisSignals&, const Eigen::VectorXd& slip, const std::string& effect)> column;
  /// Its factor in a diagram: what a modulator's block is multiplied by when a pair has no block of its own (BlockFor,
  /// effect_block.h): a sign block of the velocity, the velocity, an abs block of it, the model's force, or a product of
  /// two; for "one" the constant 1 (fed to a gain scheduled in time).
  std::optional<MotionMultiplier> factor;
  /// Its constant part is no parameter of the rigid-body base (offset, Coulomb level, viscous coefficient, mass, force
  /// constant): a pair with a modulator that is not periodic carries it as a second column "<pair>.level", the
  /// multiplier's own column — "a force of |v| drifting from a to b" is |v|·(a + b·ramp), and without the level a
  /// ramp centred in the record is named a step (issue 45's confusion table). The base's multipliers need none: the
  /// base's refit takes their constant part.
  bool own_level = false;
};

/// A row of the modulators' table: what the force varies with. Its shape scan is shared by every multiplier (found
/// on the residual demodulated by each); a new physical modulator is one row here and nothing else.
struct ModulatorRow {
  const char* id;           ///< stable: "position_periodic" (compare.json's "modulator")
  const char* name_pattern; ///< a pair's name from the multiplier's noun: "{}_ripple", "local_{}", "{}"
  const char* phrase;       ///< "rippling along the travel": composed after the multiplier's phrase
  const char* formula;      ///< "cos/sin(2πkx/P), k = 1..K"
  const char* physics;      ///< what it usually is
  std::vector<EffectParameter> parameters;
  bool of_position = false;  ///< a function of the position: with a mass, Lagrange's ½M′(x)·v² (shape_derivative)
  Periodicity periodicity = Periodicity::kNone;
  /// Refinement of its shape parameter in the joint fit (EffectTraits::refined_parameter …), or none.
  std::function<void(EffectTraits*)> refine;
  /// Its columns G (N × k) scaled by `scale` (N) when given, named "<name>" or "<name>.<suffix>". Throws
  /// std::invalid_argument naming `name` when a parameter is missing or invalid.
  std::function<EffectRegressors(const FactorParameters&, const DiagnosisSignals&, const std::string& name,
                                 const Eigen::VectorXd* scale)>
      shape;
  /// dG/dx (N × k) scaled by `scale`, for a factor of the position (of_position), else empty.
  std::function<Eigen::MatrixXd(const FactorParameters&, const DiagnosisSignals&, const Eigen::VectorXd& scale)>
      shape_derivative;
  /// The shape scan: the parameter sets worth proposing for the multiplier column `m` (N), each a candidate; notes
  /// say why none is (ProposalContext::Note, naming `pair`). `kinetic` (N): for a mass times a factor of the position,
  /// ½v², which multiplies the shape's slope (Lagrange's ½M′(x)·v²), else null.
  std::function<std::vector<FactorParameters>(ProposalContext&, const Eigen::VectorXd& m,
                                              const Eigen::VectorXd* kinetic, const std::string& pair)>
      scan;
  /// Its words after the multiplier's phrase, with the figures: "ripples along the travel with period 22.5 mm",
  /// "follows 'oil_temperature_C': −8 per unit of it" — from the diagnosed parameters (SI; positions in
  /// `position_unit`), the coefficient of a single column with the multiplier's unit (MultiplierRow::unit), and the
  /// unread column's name ("" when none).
  std::function<std::string(const FactorParameters&, double coefficient, const std::string& coefficient_unit,
                            const std::string& column, const std::string& position_unit)>
      words;
  /// The modulators whose shapes are limits of this one's (a window that opens before the motion starts is a step): a
  /// pair of this row is chosen over the same multiplier's pair of one of them only where its held-out gain over it is
  /// significant (EffectTraits::nested_modulators).
  std::vector<std::string> nests;
};

/// The two tables, in the order of the candidates they make.
const std::vector<MultiplierRow>& Multipliers();
const std::vector<ModulatorRow>& Modulators();
/// A row by id; nullptr when there is none.
const MultiplierRow* FindMultiplier(std::string_view id);
const ModulatorRow* FindModulator(std::string_view id);

/// A pair's name from its rows: the modulator's name pattern filled with the multiplier's noun ("damping_ripple").
std::string PairName(const MultiplierRow& multiplier, const ModulatorRow& modulator);

/// The pair's words for a report: "the Coulomb friction level follows 'normal_force_N': +0.031 per unit of it",
/// "the viscous friction changes between 3.1 s and 7.9 s", … from the rows' phrases, the diagnosed parameters (SI,
/// positions in `position_unit`), the coefficient of a single column, and the unread column's name (or "").
std::string PairWords(const MultiplierRow& multiplier, const ModulatorRow& modulator, const FactorParameters& parameters,
                      double single_coefficient, const std::string& column_name, const std::string& position_unit);

/// The grammar in Markdown: the multipliers' table, the modulators' table and the cross product, each pair by the
/// name of the registered effect that holds it (docs/diagnosis.md, "The grammar"; `motionblocks grammar`).
std::string GrammarMarkdown();

/// The slip velocity v_s of a friction factor tanh(v/v_s): of the log grid dead_band·2^−k, k = 0..5 (the context's dead
/// band, 1 % of the top speed, down to 1/32 of it), the one whose `columns(tanh(v/v_s))` (N × k) leave the least of the
/// residual in a joint fit with the base, then refined between its neighbours (Brent's minimiser in log₂ v_s,
/// Boost.Math brent_find_minima with 6 bits, at most 8 fits more). A friction of the generator's or the machine's own
/// law near zero velocity: a sign with a dead band leaves the approach to rest (0.5–2 mm/s) and the dwell wrong.
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

/// dBump/dx (N, per metre): −(π/(2w))·sin(π(x − c)/w) for |x − c| < w, else 0.
Eigen::VectorXd BumpSlope(const Eigen::VectorXd& position, double center, double half_width);

/// The harmonic order k (1..CatalogueOptions::motion_harmonics) of the motion's own frequency
/// (CandidateSearch::motion_frequency_hz) that `frequency_hz` [Hz] lies within 1 % of, else 0. A time period locked to
/// the motion's repetition is every state-dependent effect's too: it is no vibration of time.
int MotionHarmonic(const ProposalContext& context, double frequency_hz);

/// The periodogram against `abscissa` (the position, or the time; N) of the residual demodulated by `modulation` (N),
/// r/m, over the samples moving faster than the dead band whose |m| reaches its median there. nullopt when fewer than
/// 256 samples are left or the periodogram cannot be made (an empty period range, a constant residual).
std::optional<Periodogram> DemodulatedPeriodogram(const ProposalContext& context, const Eigen::VectorXd& abscissa,
                                                  const Eigen::VectorXd& modulation, PeriodogramOptions options);

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
/// `m` the multiplier's column (N); `kinetic` (N) for a mass times the bump, ½v², which multiplies the bump's slope
/// (Lagrange: M(x)·a + ½M′(x)·v²; on a pass through the stretch at constant speed that term is all there is), else
/// null. Throws nothing; explained 0 when the position does not move.
BumpPlace ScanBump(const ProposalContext& context, const Eigen::VectorXd& m, const Eigen::VectorXd* kinetic = nullptr);

/// The stretch of the record's time [s] (`time`: N, increasing) that a time scan searches for `parameter`: a step's
/// "change_time" in the middle 80 % (Andrews' trimming of a break at an unknown time: a break nearer an end is one
/// with a constant), a window's "on_time" and "off_time" in the middle 90 % (ScanStep, ScanWindow). A change time
/// outside it is no change inside the record; the profile of a chosen effect's change time keeps to it
/// (PlaceChangeTimes). {0, 0} for fewer than two samples; throws nothing. Source: Andrews, "Tests for parameter
/// instability and structural change with unknown change point", Econometrica 61(4), 1993.
std::pair<double, double> TimeScanRange(std::string_view parameter, const Eigen::VectorXd& time);

/// A proposed position period of at least 16 cycles in the travel that holds at least 2 % of the residual's variance: a
/// ripple that a smooth function of the position (position_dependent_force, friction_along_travel) would only blur, so
/// the smooth one is not proposed while it is there (on EMPS the screw lead's 2.5 mm holds 8.3 %: the cubic took 18.6 %
/// and a cubic × sign(v) 11 % before the ripple; once the ripple is in the model, improve's next round proposes them).
/// nullopt when there is none.
std::optional<ProposedPeriod> RippleASmoothFunctionWouldBlur(const ProposalContext& context);

}  // namespace mb

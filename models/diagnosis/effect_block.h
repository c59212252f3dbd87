#pragma once
// What an effect's block template (EffectBlockTemplate::parameters, registered in the block's own file with
// MB_REGISTER_EFFECT_BLOCK) reads from the diagnosis: the effect's parameters and the joint fit's coefficients of
// its regressor columns, as block parameters.

#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "models/diagnosis/diagnosis.h"
#include "models/diagnosis/effect_registry.h"

namespace mb {

/// The block that adds `type` to a diagram: its own (EffectBlockTemplate registered with MB_REGISTER_EFFECT_BLOCK), else,
/// for a pair of the grammar (factors.h) that has none, the block of the pair one × its modulator with the multiplier
/// row's factor (MultiplierRow::factor; issue 45, item 5): a ripple of the position times |v|, a stretch's table times
/// tanh(v/v_s), a log column's gain times ŷ; for a time modulator, its gain scheduled in time with the factor as its
/// input (EffectBlockTemplate::multiplier_port; for 1 × a time shape the constant 1). nullopt when the modulator has no
/// such block or the pair is a mass of the position (M(x)·a + ½M′(x)·v² is no product: those register blocks of their
/// own, blocks/position_dependent_inertia.h and blocks/inertia_table_1d.h). Throws nothing.
std::optional<EffectBlockTemplate> BlockFor(const EffectType& type);


/// The joint fit's coefficient of column "<effect>.<suffix>", or of the single column "<effect>" when `suffix`
/// is empty; 0 if absent.
double BlockCoefficient(const DiagnosedEffect& effect, const std::string& suffix);

/// The diagnosed parameter `name`. Throws std::invalid_argument "effect 'x' without a 'name': cannot suggest a
/// block" when it is absent or not finite.
double BlockParameter(const DiagnosedEffect& effect, const std::string& name);

/// The diagnosed "harmonics" (an integer), else `fallback`.
int BlockHarmonics(const DiagnosedEffect& effect, int fallback);

/// The Fourier block parameters "harmonics", "cos_coefficients" a_h and "sin_coefficients" b_h (h = 1..harmonics)
/// from the columns "<effect>.cos<h>", "<effect>.sin<h>" (blocks/position_periodic.h, blocks/time_periodic.h).
nlohmann::json FourierBlockParameters(const DiagnosedEffect& effect, int harmonics);

/// A parameter with its unit: {"value": v, "unit": unit}.
nlohmann::json WithUnit(double value, const std::string& unit);

/// A position-periodic ripple element "ripple" of `block_type` (blocks/position_periodic.h,
/// blocks/velocity_dependent_ripple.h) on the position input (port "x", plus `extra_inputs`): its period from the
/// diagnosis (> 0, else std::invalid_argument), Fourier coefficients from the joint fit (free), `harmonics` the
/// diagnosed ones else `default_harmonics`; the period refinable, the position_offset (encoder zero) record-specific.
EffectBlockTemplate PositionRippleBlock(const std::string& block_type, int default_harmonics,
                                        const std::vector<std::pair<MotionInput, std::string>>& extra_inputs = {});

/// A local effect's bump (effects/factor_products.cc: c·cos²(π(x − x₀)/(2w)) over |x − x₀| < w) as a table of the
/// position: {"breakpoints", "table"} over [x₀ − span·w, x₀ + span·w], `per_half_width` breakpoints per half-width w,
/// the joint fit's coefficient c scaling it (blocks/lookup_table_1d.h). std::invalid_argument when w ≤ 0 or absent.
nlohmann::json LocalBumpTable(const DiagnosedEffect& effect, int per_half_width, double span);

/// A smooth effect's cubic (Σ_j c_j·ξ^j, ξ = (x − x₀)/h, j = 1..3: the position_smooth modulator) as a table of the
/// position: {"breakpoints", "table"} at `breakpoints` points over [x₀ − h, x₀ + h], c_j the joint fit's coefficients.
/// std::invalid_argument when h ≤ 0 or absent, or `breakpoints` < 2.
nlohmann::json SmoothCubicTable(const DiagnosedEffect& effect, int breakpoints);

/// The direction of slip of a friction as a multiplier: a sign block (blocks/sign.h) on the velocity input, regularised
/// tanh(v/v_s) with the diagnosed "slip_velocity" v_s (std::invalid_argument when it is absent or not > 0), v_s free
/// in the amended diagram's refit (MotionMultiplier::free).
MotionMultiplier SlipOfVelocity();

/// The measured motion `input` itself as a multiplier (the velocity of a damping, the acceleration of an inertia).
MotionMultiplier MeasuredMotion(MotionInput input);

/// The model's own force as a multiplier (MotionMultiplier::of_model_force: a force constant that changes with the
/// position or a logged temperature scales the force the model computes; equation-error mode only).
MotionMultiplier ModelForce();

/// The factor 1 (MotionMultiplier::one): what a gain scheduled in time multiplies for a force of time alone.
MotionMultiplier One();

/// The source of a third factor (models/diagnosis/amplitude_factor.h) as a multiplier: the time from a clock block when
/// `time`, else the log column the effect's amplitude follows (MotionMultiplier::clock, ::amplitude_column).
MotionMultiplier AmplitudeSourceFactor(bool time);

/// `factor` through an abs block (blocks/abs.h): |v|, |ŷ|.
MotionMultiplier AbsOf(MotionMultiplier factor);

/// `factor` through a sign block (blocks/sign.h, Simulink's Sign: no dead band): sign(ŷ), so that |ŷ| = ŷ·sign(ŷ) keeps
/// the model's force as the first factor (a friction that grows with the transmitted force, a share of the drive's
/// force: tools/workflow/suggest.cc).
MotionMultiplier SignOf(MotionMultiplier factor);

/// `first` times `second` (MotionMultiplier::times, a product element): v·|v|, ŷ·|ŷ|, |ŷ|·tanh(v/v_s).
MotionMultiplier Times(MotionMultiplier first, MotionMultiplier second);

}  // namespace mb

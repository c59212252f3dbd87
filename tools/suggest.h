#pragma once
// `compare --suggest`: the diagram amended with the block of a diagnosed missing effect, its parameters set
// from the diagnosis, its coefficients added to the diagram's free parameters so that the next compare refits
// them jointly with the base model (DIAGNOSIS.md step 1).

#include <string>

#include <nlohmann/json.hpp>

#include "models/diagnosis/diagnosis.h"

namespace mb {

/// Effects for which the block library has a block that SuggestAmendedDiagram can insert: position_periodic,
/// velocity_dependent_ripple, time_periodic, time_delay, mass_mismatch, stribeck_friction, viscous_friction,
/// coulomb_friction, constant_offset, resonance, quantization (not asymmetric_friction: a free offset and Coulomb
/// level already span it).
bool HasEffectBlock(const std::string& effect);

/// Returns the diagram with an element for `effect`, its parameters set from the diagnosis (period, frequency,
/// delay, Stribeck velocity; the joint fit's coefficients as initial values) and its coefficients appended to the
/// diagram's "free" list:
///   position_periodic          position_periodic "ripple" on the position input (unit "m")
///   velocity_dependent_ripple  velocity_dependent_ripple "ripple" on position and velocity ("m/s")
///   time_periodic              time_periodic "vibration" (its frequency_hz is free too)
///   time_delay                 transport_delay "delay" between the model and output `output` (sampleTime = the
///                              diagram's solver step or defaultExperiment.stepSize; delay free)
///   mass_mismatch              gain "payload" on the acceleration input ("m/s^2")
///   viscous_friction           gain "viscous_extra" on the velocity input
///   stribeck_friction          friction "stribeck" (slip model, Coulomb 0; static and stribeck_velocity free)
///   coulomb_friction           friction "coulomb_extra" (slip model; coulomb free)
///   constant_offset            constant "offset_extra"
///   resonance                  flexible_load "flexible_load" on the acceleration input (two-mass model: a load
///                              on a spring–damper behind the motor, F = m(2ζω s + ω²)/(s² + 2ζω s + ω²)·a;
///                              mass = the coefficient of the diagnosis' resonance.response column;
///                              mass, frequency_hz and damping_ratio free). For equation-error diagrams: the
///                              diagnosis excites the mode with the acceleration when it is given no input u.
///   quantization               quantizer "output_quantizer" between the model and output `output`, interval =
///                              the diagnosed step; NOT free (the cost is piecewise constant in the step, so a
///                              least-squares fit of it is ill-posed); the base parameters are refit through it
/// Additive elements are summed into the signal feeding output connector `output` through a new sum element.
/// @throws std::invalid_argument if the effect has no block, lacks its key parameter (or it is not positive: step,
/// frequency_hz, damping_ratio), has a negative delay, or the
/// diagram lacks the needed input connector or a connection into `output` (the message says what to add).
nlohmann::json SuggestAmendedDiagram(const nlohmann::json& diagram, const DiagnosedEffect& effect,
                                     const std::string& output);

/// The non-parametric fallback as a block: the diagram with a `gpr` element "residual_gp" (blocks/gpr.h) that loads
/// `model_path` (a TISO-GPR fitted to the residual, models/gpr/residual_gpr.h; pass an absolute path or one relative
/// to the diagram's folder), fed by the position ("m") and velocity ("m/s") input connectors, its posterior mean
/// summed into the signal feeding output connector `output`. Nothing is added to "free": the model is fitted.
/// @throws std::invalid_argument if the diagram lacks a position or velocity input connector or a connection into
/// `output` (the message says what to add).
nlohmann::json SuggestGprFallbackBlock(const nlohmann::json& diagram, const std::string& model_path,
                                       const std::string& output);

}  // namespace mb

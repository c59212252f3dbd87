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
/// coulomb_friction, constant_offset (not asymmetric_friction: a free offset and Coulomb level already span it;
/// not quantization or resonance yet).
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
/// Additive elements are summed into the signal feeding output connector `output` through a new sum element.
/// @throws std::invalid_argument if the effect has no block, lacks its key parameter, has a negative delay, or the
/// diagram lacks the needed input connector or a connection into `output` (the message says what to add).
nlohmann::json SuggestAmendedDiagram(const nlohmann::json& diagram, const DiagnosedEffect& effect,
                                     const std::string& output);

}  // namespace mb

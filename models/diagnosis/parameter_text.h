#pragma once
// An effect parameter's value in words with its unit, as the diagnosis text and the compare report show it
// (parameter_text.cc). One place, so that the summary and the report's table never disagree on a unit.

#include <string>

namespace mb {

/// The effect registry's unit of `effect`'s parameter `name` (EffectParameter::unit: SI, "m" standing for the
/// position's unit on a rotary axis), or "" when it has none or the effect or parameter is unknown.
std::string EffectParameterUnit(const std::string& effect, const std::string& name);

/// `value` (in `unit`, as EffectParameterUnit gives it) with its unit: a length [m] or speed [m/s] in mm or mm/s when
/// the position is in metres, else in the position's own unit (`position_unit`: "rad", "rev", "deg", … and "/s");
/// s and Hz as they are; a count (no unit and whole-valued, e.g. harmonics) as an integer; 4 significant digits.
/// "0.0025034", "m", "m" → "2.503 mm"; 2.0, "", "m" → "2".
std::string FormatParameterValue(double value, const std::string& unit, const std::string& position_unit);

/// An exception's message for a user's note: without the leading "FunctionName: " the numerics prefix to their
/// messages for developers ("LombScarglePeriodogram: the period range … is empty" → "the period range … is empty").
std::string NoteText(const std::string& what);

}  // namespace mb

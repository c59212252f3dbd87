#include "models/diagnosis/parameter_text.h"

#include <cctype>
#include <cmath>

#include <fmt/format.h>

#include "models/diagnosis/effect_registry.h"

namespace mb {

std::string EffectParameterUnit(const std::string& effect, const std::string& name) {
  if (const EffectType* type = EffectRegistry::Global().Find(effect)) {
    for (const auto& p : type->parameters) {
      if (p.name == name) return p.unit;
    }
  }
  return "";
}

std::string FormatParameterValue(double value, const std::string& unit, const std::string& position_unit) {
  if (unit == "m" || unit == "m/s") {
    const std::string per = unit == "m/s" ? "/s" : "";
    if (position_unit == "m") return fmt::format("{:.4g} mm{}", value * 1e3, per);
    return fmt::format("{:.4g} {}{}", value, position_unit, per);
  }
  if (unit.empty() && std::abs(value) < 1e15 && value == std::round(value)) {
    return fmt::format("{}", static_cast<long long>(value));
  }
  if (unit == "s" || unit == "Hz") return fmt::format("{:.4g} {}", value, unit);
  return fmt::format("{:.4g}", value);
}

std::string NoteText(const std::string& what) {
  const auto colon = what.find(": ");
  if (colon == std::string::npos || colon == 0 || !std::isupper(static_cast<unsigned char>(what[0]))) return what;
  for (std::size_t i = 0; i < colon; ++i) {
    if (!std::isalnum(static_cast<unsigned char>(what[i])) && what[i] != '_') return what;
  }
  return what.substr(colon + 2);
}

}  // namespace mb

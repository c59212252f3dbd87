#pragma once
// Units of motion signals, linear and rotary. The blocks declare their ports in linear SI units (m, m/s, m/s^2,
// N); a rotary axis uses the same blocks as their rotary analogues (inertia for mass, torque for force), and a
// drive logged in its own units (motor current Iq [A] in place of torque, as ODrive and most servo drives log
// it) uses them in those units: position in rad, rev or deg, velocity per second, acceleration per second
// squared, "force" in N·m or A. The diagram loader accepts such a signal on a linear port of the same quantity
// (PortAcceptsUnit); a port and a signal of different quantities (m and m/s, N and m) are still a mismatch.
// Spellings: "m/s^2", "m/s²" and "m/s2" are one unit; "N·m", "N*m", "Nm" are one unit.
//
// The one unit normaliser (ParseUnit, UnitFactor) serves both the parameters ({"value": 22.5, "unit": "mm"} for a
// parameter in m reads 0.0225: engine/parameters.cc) and the connectors (PortAcceptsUnit): a unit is a product of
// known factors, each with an optional exponent ("^2", "²", a trailing digit as in "s2"), separated by '*', '·' or
// a space, with '/' before each factor of the denominator ("N*s/m", "N·s/m", "N s/m" and "kg/s" are one unit).

#include <array>
#include <cmath>
#include <numbers>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

namespace mb {

/// What a unit measures, as far as the motion blocks care.
enum class MotionQuantity { kOther, kPosition, kVelocity, kAcceleration, kForce };

namespace units_detail {
inline constexpr std::array<std::string_view, 4> kPositionUnits{"m", "rad", "rev", "deg"};
// The unit with its acceleration spellings ("^2", "²", "2") folded to "^2", and the torque spellings to "N·m".
inline std::string Canonical(std::string_view unit) {
  std::string u(unit);
  for (std::string_view square : {"²", "s2"}) {
    if (const auto at = u.rfind(square); at != std::string::npos && at + square.size() == u.size()) {
      u = u.substr(0, at) + (square == "s2" ? "s^2" : "^2");
    }
  }
  if (u == "Nm" || u == "N*m" || u == "N m") u = "N·m";
  return u;
}

// Exponents of the base dimensions kg, m, s, A, rad (the angle is kept apart, so that rad never converts to 1).
using Dimension = std::array<int, 5>;
struct KnownUnit {
  std::string_view name;
  double scale;  // to the SI unit of its dimension
  Dimension dimension;
};
inline constexpr Dimension kMass{1, 0, 0, 0, 0}, kLength{0, 1, 0, 0, 0}, kTime{0, 0, 1, 0, 0}, kCurrent{0, 0, 0, 1, 0},
    kAngle{0, 0, 0, 0, 1}, kForce{1, 1, -2, 0, 0}, kFrequency{0, 0, -1, 0, 0}, kVoltage{1, 2, -3, -1, 0},
    kTorque{1, 2, -2, 0, 0}, kNone{0, 0, 0, 0, 0};
inline constexpr double kPi = std::numbers::pi;
inline constexpr std::array<KnownUnit, 31> kKnownUnits{{
    {"1", 1.0, kNone},        {"kg", 1.0, kMass},          {"g", 1e-3, kMass},         {"mg", 1e-6, kMass},
    {"m", 1.0, kLength},      {"cm", 1e-2, kLength},       {"mm", 1e-3, kLength},      {"um", 1e-6, kLength},
    {"µm", 1e-6, kLength},    {"μm", 1e-6, kLength},       {"nm", 1e-9, kLength},      {"s", 1.0, kTime},
    {"ms", 1e-3, kTime},      {"us", 1e-6, kTime},         {"µs", 1e-6, kTime},        {"min", 60.0, kTime},
    {"Hz", 1.0, kFrequency},  {"kHz", 1e3, kFrequency},    {"A", 1.0, kCurrent},       {"mA", 1e-3, kCurrent},
    {"N", 1.0, kForce},       {"Nm", 1.0, kTorque},        {"V", 1.0, kVoltage},       {"mV", 1e-3, kVoltage},
    {"rad", 1.0, kAngle},     {"mrad", 1e-3, kAngle},      {"urad", 1e-6, kAngle},     {"µrad", 1e-6, kAngle},
    {"deg", kPi / 180.0, kAngle}, {"°", kPi / 180.0, kAngle}, {"rev", 2.0 * kPi, kAngle},
}};

inline const KnownUnit* FindUnit(std::string_view name) {
  for (const KnownUnit& u : kKnownUnits) {
    if (u.name == name) return &u;
  }
  return nullptr;
}

// One factor "name", "name^e", "name²", "name³" or "name<digit>" (s2); nullopt when the name is not known.
inline std::optional<std::pair<const KnownUnit*, int>> ParseFactor(std::string_view f) {
  int exponent = 1;
  if (const auto caret = f.find('^'); caret != std::string_view::npos) {
    const std::string_view e = f.substr(caret + 1);
    f = f.substr(0, caret);
    const bool negative = !e.empty() && e.front() == '-';
    const std::string_view digits = negative ? e.substr(1) : e;
    if (digits.size() != 1 || digits.front() < '1' || digits.front() > '9') return std::nullopt;
    exponent = (negative ? -1 : 1) * (digits.front() - '0');
  } else if (f.ends_with("²") || f.ends_with("³")) {
    exponent = f.ends_with("²") ? 2 : 3;
    f.remove_suffix(std::string_view("²").size());
  } else if (f.size() > 1 && f.back() >= '2' && f.back() <= '9' && FindUnit(f.substr(0, f.size() - 1))) {
    exponent = f.back() - '0';
    f.remove_suffix(1);
  }
  const KnownUnit* u = FindUnit(f);
  if (u == nullptr) return std::nullopt;
  return std::pair{u, exponent};
}
}  // namespace units_detail

namespace units_detail {
// Calls `each(factor_text, sign)` for every factor of `unit` ('*', '·' or ' ' between factors; '/' before each factor
// of the denominator: sign -1 from there on). False when a factor is empty everywhere (no factor at all).
template <class Each>
bool ForEachFactor(std::string_view unit, Each&& each) {
  bool any = false;
  int sign = 1;
  std::size_t start = 0;
  for (std::size_t i = 0; i <= unit.size(); ++i) {
    const bool end = i == unit.size();
    const bool dot = !end && unit.substr(i, std::string_view("·").size()) == "·";
    if (!end && !dot && unit[i] != '*' && unit[i] != ' ' && unit[i] != '/') continue;
    if (i > start) {
      if (!each(unit.substr(start, i - start), sign)) return false;
      any = true;
    }
    if (!end && unit[i] == '/') sign = -1;
    start = dot ? i + std::string_view("·").size() : i + 1;
    if (dot) i += std::string_view("·").size() - 1;
  }
  return any;
}
}  // namespace units_detail

/// A unit parsed by ParseUnit: the factor to its SI unit and its dimension (exponents of kg, m, s, A, rad).
struct ParsedUnit {
  double scale = 1.0;
  units_detail::Dimension dimension{};
};

/// Parses a unit as written in a diagram ("mm", "N*s/m", "N·s/m", "N s/m", "m/s^2", "rev/s", "µm", "1/m").
/// nullopt when a factor is not a known unit or the text is empty.
inline std::optional<ParsedUnit> ParseUnit(std::string_view unit) {
  ParsedUnit parsed;
  const bool known = units_detail::ForEachFactor(unit, [&parsed](std::string_view text, int sign) {
    const auto factor = units_detail::ParseFactor(text);
    if (!factor) return false;
    parsed.scale *= std::pow(factor->first->scale, sign * factor->second);
    for (std::size_t k = 0; k < parsed.dimension.size(); ++k) {
      parsed.dimension[k] += sign * factor->second * factor->first->dimension[k];
    }
    return true;
  });
  if (!known) return std::nullopt;
  return parsed;
}

/// The factor that turns a value written in `given` into `declared` (value_declared = factor · value_given):
/// 22.5 mm → m is 1e-3; nullopt when either unit is unknown or they measure different quantities (N vs kg).
/// Units spelled alike (Canonical) give 1 even when unknown.
inline std::optional<double> UnitFactor(std::string_view given, std::string_view declared) {
  if (units_detail::Canonical(given) == units_detail::Canonical(declared)) return 1.0;
  const auto g = ParseUnit(given), d = ParseUnit(declared);
  if (!g || !d || g->dimension != d->dimension) return std::nullopt;
  const double factor = g->scale / d->scale;
  return std::abs(factor - 1.0) < 1e-12 ? 1.0 : factor;
}

/// True when two spellings name the same unit ("N*s/m" and "N·s/m", "m/s2" and "m/s^2", "Hz" and "1/s").
inline bool SameUnit(std::string_view a, std::string_view b) {
  const auto factor = UnitFactor(a, b);
  return factor && *factor == 1.0;
}

/// The quantity a unit measures: position (m, rad, rev, deg), velocity (those per s), acceleration (per s^2),
/// force (N, N·m, A: a drive's current stands for its torque); kOther for anything else (V, s, "", mm, …).
inline MotionQuantity QuantityOfUnit(std::string_view unit) {
  const std::string u = units_detail::Canonical(unit);
  if (u == "N" || u == "N·m" || u == "A") return MotionQuantity::kForce;
  for (std::string_view p : units_detail::kPositionUnits) {
    const std::string base(p);
    if (u == base) return MotionQuantity::kPosition;
    if (u == base + "/s") return MotionQuantity::kVelocity;
    if (u == base + "/s^2") return MotionQuantity::kAcceleration;
  }
  return MotionQuantity::kOther;
}

/// The names a connector's "quantity" key takes, in MotionQuantity's order after kOther (the schema's enum).
inline constexpr std::array<std::string_view, 4> kQuantityNames{"position", "velocity", "acceleration", "force"};

/// The quantity a connector declares with its "quantity" key: a signal whose unit is no motion unit (a voltage
/// standing for the position of an electronic oscillator, a plain number) says what it stands for, so that the
/// blocks take it on ports of that quantity and the diagnosis finds its position and force. kOther for any other text.
inline MotionQuantity QuantityNamed(std::string_view name) {
  for (std::size_t i = 0; i < kQuantityNames.size(); ++i) {
    if (name == kQuantityNames[i]) return static_cast<MotionQuantity>(i + 1);
  }
  return MotionQuantity::kOther;
}

/// The quantity a connector carries: the one it declares ("quantity", QuantityNamed), else its unit's.
inline MotionQuantity ConnectorQuantity(std::string_view unit, std::string_view declared) {
  const MotionQuantity named = QuantityNamed(declared);
  return named != MotionQuantity::kOther ? named : QuantityOfUnit(unit);
}

/// True when a signal in `signal_unit` may drive a port declared in `port_unit`: the same unit (spellings folded),
/// or the port in a linear unit (m, m/s, m/s^2, N) and the signal the rotary or drive unit of the same quantity.
inline bool PortAcceptsUnit(std::string_view port_unit, std::string_view signal_unit) {
  if (SameUnit(port_unit, signal_unit)) return true;
  const std::string port = units_detail::Canonical(port_unit);
  const bool linear_port = port == "m" || port == "m/s" || port == "m/s^2" || port == "N";
  const MotionQuantity q = QuantityOfUnit(port);
  return linear_port && q != MotionQuantity::kOther && q == QuantityOfUnit(signal_unit);
}

/// PortAcceptsUnit for a signal that may declare what it stands for (`declared`, QuantityNamed; kOther: nothing
/// declared): a signal in a unit of no motion quantity (V) declared a position drives a position port (m, rad).
inline bool PortAcceptsSignal(std::string_view port_unit, std::string_view signal_unit, MotionQuantity declared) {
  if (PortAcceptsUnit(port_unit, signal_unit)) return true;
  return declared != MotionQuantity::kOther && QuantityOfUnit(signal_unit) == MotionQuantity::kOther &&
         QuantityOfUnit(port_unit) == declared;
}

/// One revolution in a position unit: 1 (rev), 2π (rad), 360 (deg); 0 for a linear or unknown unit.
inline double RevolutionIn(std::string_view position_unit) {
  if (position_unit == "rev") return 1.0;
  if (position_unit == "rad") return 6.283185307179586;
  if (position_unit == "deg") return 360.0;
  return 0.0;
}

/// The units a diagram's motion is in (issue 40): its position unit (m; rad, rev, deg on a rotary axis; a declared
/// quantity's own unit, such as V) and its force unit (N; N·m for a torque; A for a drive's current). The blocks
/// declare their parameters in linear SI units (ParamSpec::unit: N·s/m, N, kg, m); on another axis each reads as its
/// analogue (AxisUnit): the number is the same, only what it is per changes.
struct MotionAxis {
  std::string position = "m";
  std::string force = "N";
  /// True for the linear axis in SI (m and N), where a parameter's unit reads as declared.
  bool is_linear() const { return SameUnit(position, "m") && SameUnit(force, "N"); }
  /// "rad, N·m".
  std::string ToString() const { return position + ", " + force; }
};

namespace units_detail {
using FactorList = std::vector<std::pair<std::string, int>>;
inline void AddFactor(FactorList* list, std::string_view name, int exponent) {
  for (auto& f : *list) {
    if (f.first == name) {
      f.second += exponent;
      return;
    }
  }
  list->emplace_back(std::string(name), exponent);
}
// A unit's factors with their exponents ("N·m" → N¹ m¹); the whole text as one factor when a factor is not known.
inline FactorList FactorsOf(std::string_view unit) {
  FactorList out;
  const bool known = ForEachFactor(unit, [&out](std::string_view text, int sign) {
    const auto factor = ParseFactor(text);
    if (!factor) return false;
    AddFactor(&out, factor->first->name, sign * factor->second);
    return true;
  });
  if (!known) return {{std::string(unit), 1}};
  return out;
}
inline std::string PowerText(const std::string& name, int exponent) {
  if (exponent == 1) return name;
  if (exponent == 2) return name + "²";
  if (exponent == 3) return name + "³";
  return name + "^" + std::to_string(exponent);
}
// "N·m·s/rad": the numerator's factors joined by '·', then '/' before each factor of the denominator ("1/rad" when
// the numerator is empty); "1" when nothing is left.
inline std::string UnitText(const FactorList& factors) {
  std::string numerator, denominator;
  for (const auto& [name, exponent] : factors) {
    if (exponent > 0) numerator += (numerator.empty() ? "" : "·") + PowerText(name, exponent);
    if (exponent < 0) denominator += "/" + PowerText(name, -exponent);
  }
  if (numerator.empty()) numerator = "1";
  return numerator + denominator;
}
}  // namespace units_detail

/// A parameter's unit on `axis`, from the linear SI unit it is declared in: each N becomes the axis's force unit,
/// each m its position unit and each kg (a mass: N·s²/m) force·s²/position; other factors (s, Hz, rad, V, A) stay,
/// and a factor of the force and the position alike cancels. On a rotary axis (rad, N·m): N·s/m → N·m·s/rad (a
/// rotary viscous coefficient), N → N·m, m/s → rad/s, N/m → N·m/rad, kg → kg·m² (an inertia, N·m·s²/rad); in a
/// drive's units (rev, A): N·s/m → A·s/rev, kg → A·s²/rev; with a voltage standing for both (V, V): N·s/m → s.
/// The linear axis, a unit with none of N, m and kg, an empty or unknown unit: returned as given. Throws nothing.
inline std::string AxisUnit(std::string_view linear_unit, const MotionAxis& axis) {
  if (linear_unit.empty() || axis.is_linear()) return std::string(linear_unit);
  const units_detail::FactorList force = units_detail::FactorsOf(axis.force);
  const units_detail::FactorList position = units_detail::FactorsOf(axis.position);
  units_detail::FactorList out;
  const auto add = [&out](const units_detail::FactorList& factors, int exponent) {
    for (const auto& [name, e] : factors) units_detail::AddFactor(&out, name, e * exponent);
  };
  bool mechanical = false;
  const bool known = units_detail::ForEachFactor(linear_unit, [&](std::string_view text, int sign) {
    const auto factor = units_detail::ParseFactor(text);
    if (!factor) return false;
    const std::string_view name = factor->first->name;
    const int e = sign * factor->second;
    if (name == "N") {
      add(force, e);
    } else if (name == "m") {
      add(position, e);
    } else if (name == "kg") {
      add(force, e);
      units_detail::AddFactor(&out, "s", 2 * e);
      add(position, -e);
    } else {
      units_detail::AddFactor(&out, name, e);
      return true;
    }
    mechanical = true;
    return true;
  });
  if (!known || !mechanical) return std::string(linear_unit);
  const std::string text = units_detail::UnitText(out);
  return text == "N·m·s²/rad" ? std::string("kg·m²") : text;  // rad is 1 in SI: an inertia
}

/// The axis of a diagram's motion signals, from its connectors' units and declared quantities (ConnectorQuantity;
/// the input connectors first, each as {unit, declared quantity}): the first position, velocity or acceleration
/// gives the position unit (rad/s → rad), the first force the force unit. A rotary position without a force
/// connector takes N·m, a torque without a position rad; nothing of either: the linear axis (m, N).
inline MotionAxis AxisOfConnectors(const std::vector<std::pair<std::string, std::string>>& unit_and_quantity) {
  std::string position, force;
  for (const auto& [unit, declared] : unit_and_quantity) {
    const std::string u = units_detail::Canonical(unit);
    const auto strip = [&u](std::string_view suffix) {
      return u.size() > suffix.size() && u.ends_with(suffix) ? u.substr(0, u.size() - suffix.size()) : std::string();
    };
    switch (ConnectorQuantity(unit, declared)) {
      case MotionQuantity::kPosition:
        if (position.empty()) position = u;
        break;
      case MotionQuantity::kVelocity:
        if (position.empty()) position = strip("/s");
        break;
      case MotionQuantity::kAcceleration:
        if (position.empty()) position = strip("/s^2");
        break;
      case MotionQuantity::kForce:
        if (force.empty()) force = u;
        break;
      case MotionQuantity::kOther:
        break;
    }
  }
  MotionAxis axis;
  const bool rotary = !position.empty() && RevolutionIn(position) > 0.0;
  if (!position.empty()) axis.position = position;
  if (!force.empty()) axis.force = force;
  if (force.empty() && rotary) axis.force = "N·m";
  if (position.empty() && force == "N·m") axis.position = "rad";
  return axis;
}

}  // namespace mb

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

/// A unit parsed by ParseUnit: the factor to its SI unit and its dimension (exponents of kg, m, s, A, rad).
struct ParsedUnit {
  double scale = 1.0;
  units_detail::Dimension dimension{};
};

/// Parses a unit as written in a diagram ("mm", "N*s/m", "N·s/m", "N s/m", "m/s^2", "rev/s", "µm", "1/m").
/// nullopt when a factor is not a known unit or the text is empty.
inline std::optional<ParsedUnit> ParseUnit(std::string_view unit) {
  ParsedUnit parsed;
  bool any = false;
  int sign = 1;
  std::size_t start = 0;
  for (std::size_t i = 0; i <= unit.size(); ++i) {
    const bool end = i == unit.size();
    const bool dot = !end && unit.substr(i, std::string_view("·").size()) == "·";
    if (!end && !dot && unit[i] != '*' && unit[i] != ' ' && unit[i] != '/') continue;
    if (i > start) {
      const auto factor = units_detail::ParseFactor(unit.substr(start, i - start));
      if (!factor) return std::nullopt;
      parsed.scale *= std::pow(factor->first->scale, sign * factor->second);
      for (std::size_t k = 0; k < parsed.dimension.size(); ++k) {
        parsed.dimension[k] += sign * factor->second * factor->first->dimension[k];
      }
      any = true;
    }
    if (!end && unit[i] == '/') sign = -1;
    start = dot ? i + std::string_view("·").size() : i + 1;
    if (dot) i += std::string_view("·").size() - 1;
  }
  if (!any) return std::nullopt;
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

}  // namespace mb

#pragma once
// Units of motion signals, linear and rotary. The blocks declare their ports in linear SI units (m, m/s, m/s^2,
// N); a rotary axis uses the same blocks as their rotary analogues (inertia for mass, torque for force), and a
// drive logged in its own units (motor current Iq [A] in place of torque, as ODrive and most servo drives log
// it) uses them in those units: position in rad, rev or deg, velocity per second, acceleration per second
// squared, "force" in N·m or A. The diagram loader accepts such a signal on a linear port of the same quantity
// (PortAcceptsUnit); a port and a signal of different quantities (m and m/s, N and m) are still a mismatch.
// Spellings: "m/s^2", "m/s²" and "m/s2" are one unit; "N·m", "N*m", "Nm" are one unit.

#include <array>
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
}  // namespace units_detail

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

/// True when a signal in `signal_unit` may drive a port declared in `port_unit`: the same unit (spellings folded),
/// or the port in a linear unit (m, m/s, m/s^2, N) and the signal the rotary or drive unit of the same quantity.
inline bool PortAcceptsUnit(std::string_view port_unit, std::string_view signal_unit) {
  const std::string port = units_detail::Canonical(port_unit), signal = units_detail::Canonical(signal_unit);
  if (port == signal) return true;
  const bool linear_port = port == "m" || port == "m/s" || port == "m/s^2" || port == "N";
  const MotionQuantity q = QuantityOfUnit(port);
  return linear_port && q != MotionQuantity::kOther && q == QuantityOfUnit(signal);
}

/// One revolution in a position unit: 1 (rev), 2π (rad), 360 (deg); 0 for a linear or unknown unit.
inline double RevolutionIn(std::string_view position_unit) {
  if (position_unit == "rev") return 1.0;
  if (position_unit == "rad") return 6.283185307179586;
  if (position_unit == "deg") return 360.0;
  return 0.0;
}

}  // namespace mb

#pragma once
// Sample times in Simulink's convention: continuous, discrete [period, offset], inherited, constant.
// Source: MathWorks, "What Is Sample Time?" (Simulink documentation); DESIGN.md "Semantics to get right".

#include <cmath>
#include <string>

namespace mb {

/// When a block computes. A discrete block has hits at t_k = offset + k·period, k = 0, 1, …; its outputs are
/// computed at hits and held (zero-order hold) in between. Continuous and inherited blocks are evaluated
/// whenever the solver needs outputs; constant blocks once at initialisation.
struct SampleTime {
  enum class Kind { kContinuous, kDiscrete, kInherited, kConstant };

  Kind kind = Kind::kInherited;
  double period = 0.0;  ///< [s], > 0 for discrete
  double offset = 0.0;  ///< [s], 0 ≤ offset < period for discrete

  static SampleTime Continuous() { return {Kind::kContinuous, 0.0, 0.0}; }
  static SampleTime Inherited() { return {Kind::kInherited, 0.0, 0.0}; }
  static SampleTime Constant() { return {Kind::kConstant, 0.0, 0.0}; }
  /// @throws std::invalid_argument unless period > 0 and 0 ≤ offset < period.
  static SampleTime Discrete(double period, double offset = 0.0);

  bool is_discrete() const { return kind == Kind::kDiscrete; }
  bool is_continuous() const { return kind == Kind::kContinuous; }

  /// Index k of the first hit at or after t (within a relative tolerance of 1e-9 periods).
  long long FirstHitIndexAtOrAfter(double t) const;
  /// Time of hit k: offset + k·period (computed from the integer so that long runs do not drift).
  double HitTime(long long k) const { return offset + static_cast<double>(k) * period; }
  /// True if t is a hit (within 1e-9 periods).
  bool IsHit(double t) const;

  /// "continuous", "inherited", "constant" or "discrete [0.001, 0]".
  std::string ToString() const;
};

}  // namespace mb

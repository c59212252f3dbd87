#pragma once
// switch: y = u1 where the control input u2 passes the criterion, else u3 — Simulink's Switch block. The clamping
// anti-windup of a PID built from gains (conditional integration: the integrator's input switched to 0 while the
// command is at its limit; Åström and Hägglund, Advanced PID Control, ISA 2006, §3.5) and a gain scheduled on a
// signal are made with it. Inherited sample time; all three inputs feed through.

#include "engine/block.h"
#include "engine/registry.h"

namespace mb {

/// y = u1 if u2 passes the criterion, else u3, element-wise on u1 and u3 (width n) with a scalar control u2.
/// Ports: in "u1", "u2" (width 1), "u3"; out "y" (width n). Parameters: criteria "u2 >= threshold" (default),
/// "u2 > threshold" or "u2 ~= 0" (Simulink's three criteria for passing the first input), threshold (default 0,
/// the unit of u2), width n. The output jumps where u2 crosses the threshold: a variable-step solver steps over it as
/// over Simulink's Switch with zero-crossing detection off (a fixed-step solver takes it at its next step).
/// @throws std::invalid_argument for a criterion not one of the three.
class Switch final : public Block {
 public:
  enum class Criterion { kGreaterOrEqual, kGreater, kNonZero };
  explicit Switch(const BlockConfig& config);
  void CalcOutput(const BlockContext& context) const override;

 private:
  Criterion criterion_;
  double threshold_;
};

}  // namespace mb

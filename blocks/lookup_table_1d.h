#pragma once
// lookup_table_1d: y = f(u) by linear interpolation in a table over strictly increasing breakpoints — Simulink's 1-D
// Lookup Table (interpolation "Linear point-slope"; extrapolation "Clip" by default: the end values hold beyond the
// breakpoints, or "Linear": the end segments extended). A force of one place of the travel, a friction or a force
// constant that varies along it. Inherited sample time; u feeds through.

#include <string>

#include <Eigen/Core>

#include "engine/block.h"
#include "engine/registry.h"

namespace mb {

/// The table of lookup_table_1d (and inertia_table_1d): linear interpolation over strictly increasing breakpoints b
/// (n ≥ 2, any unit) of the values y (n, the output's unit), clipped at the ends or extrapolated linearly
/// (`extrapolation` "clip" or "linear"). Source: MathWorks, Simulink "1-D Lookup Table" block reference.
/// @throws std::invalid_argument (constructor) as LookupTable1d below.
class LinearTable {
 public:
  LinearTable(Eigen::VectorXd breakpoints, Eigen::VectorXd table, const std::string& extrapolation);
  /// The value at u; noexcept, no allocation.
  double Interpolate(double u) const noexcept;
  /// dy/du at u: the slope of the segment holding u (the right one at a breakpoint; 0 beyond the ends when clipped).
  double Slope(double u) const noexcept;

 private:
  Eigen::Index Segment(double u) const noexcept;
  Eigen::VectorXd breakpoints_, table_;
  bool clip_ = true;
};

/// y = interpolation of (breakpoints, table) at u. Ports: in "u" (the breakpoints' unit, e.g. m), out "y" (the
/// table's unit). Parameters: breakpoints b_1 < … < b_n (n ≥ 2), table y_1 … y_n, extrapolation "clip" (default) or
/// "linear". Source: MathWorks, Simulink "1-D Lookup Table" block reference.
/// @throws std::invalid_argument when fewer than 2 breakpoints are given, they do not increase strictly or are not
/// finite, the table's length differs, or extrapolation is neither "clip" nor "linear" (each message says how to fix).
class LookupTable1d final : public Block {
 public:
  explicit LookupTable1d(const BlockConfig& config);
  void CalcOutput(const BlockContext& context) const override;
  /// The interpolated value at u (what CalcOutput writes); noexcept, no allocation.
  double Interpolate(double u) const noexcept { return table_.Interpolate(u); }

 private:
  LinearTable table_;
};

}  // namespace mb

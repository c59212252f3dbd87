#pragma once
// lookup_table_2d: y = f(u1, u2) by bilinear interpolation in a table over two sets of strictly increasing breakpoints
// — Simulink's 2-D Lookup Table (interpolation "Linear point-slope"; extrapolation "Clip" by default: the edge values
// hold beyond the breakpoints, or "Linear": the edge cells extended). A force that depends jointly on two signals (a
// friction map over position and velocity, a force constant over position and current). Inherited sample time; both
// inputs feed through.

#include <Eigen/Core>

#include "engine/block.h"
#include "engine/registry.h"

namespace mb {

/// y = bilinear interpolation of the table at (u1, u2). Ports: in "u1" (the row breakpoints' unit, e.g. m), in "u2"
/// (the column breakpoints' unit, e.g. m/s), out "y" (the table's unit). Parameters: row_breakpoints r_1 < … < r_m and
/// column_breakpoints c_1 < … < c_n (m, n ≥ 2), table the m × n values row by row (y at (r_i, c_j) is entry
/// i·n + j, zero-based: row-major, as Simulink's table with rows indexed by u1), extrapolation "clip" (default) or
/// "linear". Source: MathWorks, Simulink "2-D Lookup Table" block reference; Press et al., Numerical Recipes, 3rd ed.,
/// §3.6 (bilinear interpolation).
/// @throws std::invalid_argument when a set has fewer than 2 breakpoints, they do not increase strictly or are not
/// finite, the table does not hold m·n values, or extrapolation is neither "clip" nor "linear" (each says how to fix).
class LookupTable2d final : public Block {
 public:
  explicit LookupTable2d(const BlockConfig& config);
  void CalcOutput(const BlockContext& context) const override;
  /// The interpolated value at (u1, u2) (what CalcOutput writes); noexcept, no allocation.
  double Interpolate(double u1, double u2) const noexcept;

 private:
  Eigen::VectorXd rows_, columns_, table_;  // table_ row-major, rows_.size() × columns_.size()
  bool clip_ = true;
};

}  // namespace mb

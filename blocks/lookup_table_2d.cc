#include "blocks/lookup_table_2d.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

namespace mb {
namespace {

// Strictly increasing, finite, at least 2 entries; else std::invalid_argument naming the parameter.
void CheckBreakpoints(const Eigen::VectorXd& b, const char* name) {
  if (b.size() < 2) throw std::invalid_argument(fmt::format("{} has {} entries; give at least 2", name, b.size()));
  for (Eigen::Index i = 0; i < b.size(); ++i) {
    if (!std::isfinite(b(i)) || (i > 0 && !(b(i) > b(i - 1)))) {
      throw std::invalid_argument(fmt::format("{}[{}] = {} must be finite and above {}[{}] = {}: breakpoints must "
                                              "increase strictly",
                                              name, i, b(i), name, i > 0 ? i - 1 : 0, b(i > 0 ? i - 1 : 0)));
    }
  }
}

// The cell [b_k, b_{k+1}] holding u (the first or last beyond the ends) and u's fraction q along it; with clip, q is
// kept in [0, 1] so the edge values hold.
std::pair<Eigen::Index, double> Cell(const Eigen::VectorXd& b, double u, bool clip) noexcept {
  const Eigen::Index n = b.size();
  const double* begin = b.data();
  const auto upper = std::upper_bound(begin, begin + n, u);
  const Eigen::Index k = std::clamp<Eigen::Index>(static_cast<Eigen::Index>(upper - begin) - 1, 0, n - 2);
  const double q = (u - b(k)) / (b(k + 1) - b(k));
  return {k, clip ? std::clamp(q, 0.0, 1.0) : q};
}

}  // namespace

LookupTable2d::LookupTable2d(const BlockConfig& config)
    : Block(config.name),
      rows_(config.parameters.Vector("row_breakpoints")),
      columns_(config.parameters.Vector("column_breakpoints")),
      table_(config.parameters.Vector("table")) {
  const std::string& extrapolation = config.parameters.String("extrapolation");
  if (extrapolation != "clip" && extrapolation != "linear") {
    throw std::invalid_argument(fmt::format("extrapolation \"{}\": write \"clip\" (the edge values hold beyond the "
                                            "breakpoints, Simulink's default) or \"linear\"",
                                            extrapolation));
  }
  clip_ = extrapolation == "clip";
  CheckBreakpoints(rows_, "row_breakpoints");
  CheckBreakpoints(columns_, "column_breakpoints");
  if (table_.size() != rows_.size() * columns_.size()) {
    throw std::invalid_argument(fmt::format(
        "table has {} entries for {} row × {} column breakpoints; give {} values, row by row", table_.size(),
        rows_.size(), columns_.size(), rows_.size() * columns_.size()));
  }
  DeclareInputPort("u1");
  DeclareInputPort("u2");
  DeclareOutputPort("y");
}

double LookupTable2d::Interpolate(double u1, double u2) const noexcept {
  const auto [i, p] = Cell(rows_, u1, clip_);
  const auto [j, q] = Cell(columns_, u2, clip_);
  const Eigen::Index n = columns_.size();
  const auto at = [&](Eigen::Index r, Eigen::Index c) { return table_(r * n + c); };
  return (1.0 - p) * ((1.0 - q) * at(i, j) + q * at(i, j + 1)) + p * ((1.0 - q) * at(i + 1, j) + q * at(i + 1, j + 1));
}

void LookupTable2d::CalcOutput(const BlockContext& c) const { c.y(0) = Interpolate(c.u(0), c.u(1)); }

MB_REGISTER_BLOCK(LookupTable2d, BlockType{
    "lookup_table_2d",
    "y = f(u1, u2): bilinear interpolation in a table over two sets of strictly increasing breakpoints (Simulink's 2-D "
    "Lookup Table), clipped at the edges or extrapolated linearly. Inherits its sample time.",
    {Required("row_breakpoints", "", "r_1 < … < r_m, m ≥ 2, for u1 (unit of u1)", ParamType::kVector),
     Required("column_breakpoints", "", "c_1 < … < c_n, n ≥ 2, for u2 (unit of u2)", ParamType::kVector),
     Required("table", "", "the m × n values row by row: y(r_i, c_j) is entry i·n + j (unit of y)", ParamType::kVector),
     Optional("extrapolation", "clip", "", "\"clip\" (edge values hold) or \"linear\"", ParamType::kString)},
    SampleTimeRule::kNone,
    [](const BlockConfig& c) { return std::make_unique<LookupTable2d>(c); }})

}  // namespace mb

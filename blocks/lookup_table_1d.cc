#include "blocks/lookup_table_1d.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>

namespace mb {

LinearTable::LinearTable(Eigen::VectorXd breakpoints, Eigen::VectorXd table, const std::string& extrapolation)
    : breakpoints_(std::move(breakpoints)), table_(std::move(table)) {
  if (extrapolation != "clip" && extrapolation != "linear") {
    throw std::invalid_argument(fmt::format("extrapolation \"{}\": write \"clip\" (the end values hold beyond the "
                                            "breakpoints, Simulink's default) or \"linear\"",
                                            extrapolation));
  }
  clip_ = extrapolation == "clip";
  if (breakpoints_.size() < 2) {
    throw std::invalid_argument(fmt::format("breakpoints has {} entries; give at least 2", breakpoints_.size()));
  }
  if (table_.size() != breakpoints_.size()) {
    throw std::invalid_argument(fmt::format("table has {} entries for {} breakpoints; give one value per breakpoint",
                                            table_.size(), breakpoints_.size()));
  }
  for (Eigen::Index i = 0; i < breakpoints_.size(); ++i) {
    if (!std::isfinite(breakpoints_(i)) || (i > 0 && !(breakpoints_(i) > breakpoints_(i - 1)))) {
      throw std::invalid_argument(fmt::format("breakpoints[{}] = {} must be finite and above breakpoints[{}] = {}: "
                                              "breakpoints must increase strictly",
                                              i, breakpoints_(i), i > 0 ? i - 1 : 0, breakpoints_(i > 0 ? i - 1 : 0)));
    }
  }
}

// The segment [b_k, b_{k+1}] holding u (the first or last one beyond the ends).
Eigen::Index LinearTable::Segment(double u) const noexcept {
  const Eigen::Index n = breakpoints_.size();
  const double* begin = breakpoints_.data();
  const auto upper = std::upper_bound(begin, begin + n, u);
  return std::clamp<Eigen::Index>(static_cast<Eigen::Index>(upper - begin) - 1, 0, n - 2);
}

double LinearTable::Interpolate(double u) const noexcept {
  const Eigen::Index n = breakpoints_.size();
  if (clip_) {
    if (u <= breakpoints_(0)) return table_(0);
    if (u >= breakpoints_(n - 1)) return table_(n - 1);
  }
  const Eigen::Index k = Segment(u);
  const double q = (u - breakpoints_(k)) / (breakpoints_(k + 1) - breakpoints_(k));
  return table_(k) + q * (table_(k + 1) - table_(k));
}

double LinearTable::Slope(double u) const noexcept {
  const Eigen::Index n = breakpoints_.size();
  if (clip_ && (u < breakpoints_(0) || u >= breakpoints_(n - 1))) return 0.0;
  const Eigen::Index k = Segment(u);
  return (table_(k + 1) - table_(k)) / (breakpoints_(k + 1) - breakpoints_(k));
}

LookupTable1d::LookupTable1d(const BlockConfig& config)
    : Block(config.name),
      table_(config.parameters.Vector("breakpoints"), config.parameters.Vector("table"),
             config.parameters.String("extrapolation")) {
  DeclareInputPort("u");
  DeclareOutputPort("y");
}

void LookupTable1d::CalcOutput(const BlockContext& c) const { c.y(0) = Interpolate(c.u(0)); }

MB_REGISTER_BLOCK(LookupTable1d, BlockType{
    "lookup_table_1d",
    "y = f(u): linear interpolation in a table over strictly increasing breakpoints (Simulink's 1-D Lookup Table), "
    "clipped at the ends or extrapolated linearly. Inherits its sample time.",
    {Required("breakpoints", "", "b_1 < … < b_n, n ≥ 2 (unit of u)", ParamType::kVector),
     Required("table", "", "y_1 … y_n, one per breakpoint (unit of y)", ParamType::kVector),
     Optional("extrapolation", "clip", "", "\"clip\" (end values hold) or \"linear\"", ParamType::kString)},
    SampleTimeRule::kNone,
    [](const BlockConfig& c) { return std::make_unique<LookupTable1d>(c); }})

}  // namespace mb

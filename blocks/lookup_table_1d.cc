#include "blocks/lookup_table_1d.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>

#include "models/diagnosis/effect_block.h"

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

// The diagnosis' suggestions made with this block (MB_REGISTER_EFFECT_BLOCK, models/diagnosis/effect_registry.h).
namespace {

// The table spans [c − 1.5w, c + 1.5w] with 12 breakpoints per half-width w (37 in all): the refit may widen the
// stretch the scan found and give it edges as sharp as w/12 (a friction that sets in at one place: with 9 breakpoints
// over [c − w, c + w] the independent case's 10 mm stretch held out 1.34 × the noise floor, its edges smeared over 2 mm).
constexpr int kBreakpointsPerHalfWidth = 12;
constexpr double kSpan = 1.5;  // half-widths either side of the centre

// A local effect (effects/factor_products.cc: a bump over [c − w, c + w]) as a table of the position: the bump's shape
// scaled by the joint fit's coefficient, 0 beyond [c − w, c + w] and past the table's ends (clipped); the table free, so
// the refit shapes the stretch.
EffectBlockTemplate LocalTableBlock(const char* element_name) {
  EffectBlockTemplate block;
  block.block_type = "lookup_table_1d";
  block.element_name = element_name;
  block.inputs = {{MotionInput::kPosition, "u"}};
  block.parameters = [](const DiagnosedEffect& d) {
    return LocalBumpTable(d, kBreakpointsPerHalfWidth, kSpan);
  };
  block.free = {"table"};
  return block;
}

// local_friction: the table times the direction of slip tanh(v/v_s) (a friction at one place). A force of one place alone is not proposed: at
// the ends of the travel a bump is confounded with the reversals, and inside it position_dependent_force's smooth
// basis covers it.
EffectBlockTemplate LocalFrictionEffectBlock() {
  EffectBlockTemplate block = LocalTableBlock("local_friction");
  block.multiplier = SlipOfVelocity();
  return block;
}

}  // namespace

MB_REGISTER_EFFECT_BLOCK(local_friction, LocalFrictionEffectBlock())

// The grammar's local_force (one × position_local): the table alone, a force at one place. It is also the block every
// other multiplier × position_local pair without its own is made from (BlockFor, models/diagnosis/effect_block.h).
MB_REGISTER_EFFECT_BLOCK(local_force, LocalTableBlock("local_force"))

namespace {

// local_damping: the table times the measured velocity (viscous drag at one place).
EffectBlockTemplate LocalDampingEffectBlock() {
  EffectBlockTemplate block = LocalTableBlock("local_damping");
  block.multiplier = MeasuredMotion(MotionInput::kVelocity);
  return block;
}

}  // namespace

MB_REGISTER_EFFECT_BLOCK(local_damping, LocalDampingEffectBlock())

namespace {

// local_force_constant: the table times the model's force (a force constant that changes over one stretch: a chipped
// or demagnetised magnet).
EffectBlockTemplate LocalForceConstantEffectBlock() {
  EffectBlockTemplate block = LocalTableBlock("local_force_constant");
  block.multiplier = ModelForce();
  return block;
}

}  // namespace

MB_REGISTER_EFFECT_BLOCK(local_force_constant, LocalForceConstantEffectBlock())

}  // namespace mb

#include "blocks/inertia_table_1d.h"

#include "models/diagnosis/effect_block.h"

namespace mb {

InertiaTable1d::InertiaTable1d(const BlockConfig& config)
    : Block(config.name),
      mass_(config.parameters.Vector("breakpoints"), config.parameters.Vector("table"),
            config.parameters.String("extrapolation")),
      gain_(config.parameters.Number("gain")),
      acceleration_input_(config.parameters.Bool("acceleration_input")) {
  DeclareInputPort("x", 1, "m");
  DeclareInputPort("v", 1, "m/s");
  if (acceleration_input_) DeclareInputPort("a", 1, "m/s^2");
  DeclareOutputPort("y", 1, "N");
  DeclareOutputPort("mass", 1, "kg");
}

void InertiaTable1d::CalcOutput(const BlockContext& c) const {
  const double x = c.u(0), v = c.u(1), a = acceleration_input_ ? c.u(2) : 0.0;
  const double m = gain_ * mass_.Interpolate(x);
  c.y(0) = m * a + gain_ * 0.5 * mass_.Slope(x) * v * v;
  c.y(1) = m;
}

MB_REGISTER_BLOCK(InertiaTable1d, BlockType{
    "inertia_table_1d",
    "y = g·(M(x)·a + ½M′(x)·v²), M(x) interpolated linearly in a table of the position: the force of a moving mass "
    "that varies with position (Lagrange's equation). In: x [m], v [m/s], a [m/s²] (not with acceleration_input "
    "false: y = g·½M′(x)·v², g·M(x)·a left to a plant whose mass input reads \"mass\"). Out: y [N], mass g·M(x) "
    "[kg].",
    {Required("breakpoints", "m", "x_1 < … < x_n, n ≥ 2", ParamType::kVector),
     Required("table", "kg", "M_1 … M_n, the mass's variation at each breakpoint", ParamType::kVector),
     Optional("extrapolation", "clip", "", "\"clip\" (end values hold, M′ = 0 beyond) or \"linear\"",
              ParamType::kString),
     Optional("gain", 1.0, "", "g: scales the table (a fit of the mass's size alone, its shape kept)"),
     Optional("acceleration_input", true, "", "false: no input a, y = g·½M′(x)·v² (the plant takes g·M(x) as its mass)",
              ParamType::kBool)},
    SampleTimeRule::kNone,
    [](const BlockConfig& c) { return std::make_unique<InertiaTable1d>(c); }})

// The diagnosis' suggestions made with this block (MB_REGISTER_EFFECT_BLOCK, models/diagnosis/effect_registry.h).
namespace {

constexpr int kMassBreakpointsPerHalfWidth = 12;  // as lookup_table_1d's local tables
constexpr double kMassSpan = 1.5;                 // half-widths either side of the centre
constexpr int kTravelBreakpoints = 41;        // a cubic over the travel, sampled

// A mass over the position, on the measured position, velocity and acceleration; `free` the refit's parameters.
EffectBlockTemplate InertiaTableBlock(const char* element_name, const char* free) {
  EffectBlockTemplate block;
  block.block_type = "inertia_table_1d";
  block.element_name = element_name;
  block.inputs = {{MotionInput::kPosition, "x"}, {MotionInput::kVelocity, "v"}, {MotionInput::kAcceleration, "a"}};
  block.free = {free};
  return block;
}

// local_inertia (acceleration × position_local): a mass over one stretch, the diagnosed bump as the table, its size
// (the gain) refit: a table free over the stretch's flanks, which the motion may not reach, is not identified there,
// and a mass's slope M′ couples neighbouring entries.
EffectBlockTemplate LocalInertiaEffectBlock() {
  EffectBlockTemplate block = InertiaTableBlock("local_inertia", "gain");
  block.parameters = [](const DiagnosedEffect& d) {
    return LocalBumpTable(d, kMassBreakpointsPerHalfWidth, kMassSpan);
  };
  return block;
}

// inertia_along_travel (acceleration × position_smooth): a mass changing along the travel, the diagnosed cubic sampled
// over the record's travel, the table refit.
EffectBlockTemplate InertiaAlongTravelEffectBlock() {
  EffectBlockTemplate block = InertiaTableBlock("inertia_along_travel", "table");
  block.parameters = [](const DiagnosedEffect& d) { return SmoothCubicTable(d, kTravelBreakpoints); };
  return block;
}

}  // namespace

MB_REGISTER_EFFECT_BLOCK(local_inertia, LocalInertiaEffectBlock())
MB_REGISTER_EFFECT_BLOCK(inertia_along_travel, InertiaAlongTravelEffectBlock())

}  // namespace mb

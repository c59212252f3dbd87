#include "blocks/backlash_friction.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "models/diagnosis/effect_block.h"

namespace mb {

BacklashFriction::BacklashFriction(const BlockConfig& config)
    : Block(config.name),
      half_gap_(0.5 * config.parameters.Number("gap")),
      load_friction_(config.parameters.Number("load_friction")),
      dead_band_(config.parameters.Number("dead_band")) {
  if (!(half_gap_ > 0.0)) throw std::invalid_argument(fmt::format("gap must be > 0 (the full play) [m], got {}", 2.0 * half_gap_));
  if (!(dead_band_ >= 0.0)) throw std::invalid_argument(fmt::format("dead_band must be ≥ 0 [m/s], got {}", dead_band_));
  if (!config.sample_time) {
    throw std::invalid_argument("backlash_friction '" + config.name +
                                "' needs a sampleTime [Ts, offset]: the play's far side is updated at each hit");
  }
  DeclareInputPort("x", 1, "m");
  DeclareInputPort("v", 1, "m/s");
  DeclareOutputPort("f", 1, "N");
  DeclareDiscreteState(2);  // far side p [m]; 1 once p holds a position
  SetSampleTime(*config.sample_time);
}

double BacklashFriction::FarSide(const BlockContext& c) const {
  const double x = c.u(0);
  const auto state = c.discrete_state();
  if (state(1) == 0.0) return x;
  return std::clamp(state(0), x - half_gap_, x + half_gap_);
}

void BacklashFriction::CalcOutput(const BlockContext& c) const {
  const double x = c.u(0), v = c.u(1);
  const bool engaged = std::abs(x - FarSide(c)) >= half_gap_ * (1.0 - 1e-6);
  const double sign = std::abs(v) <= dead_band_ ? 0.0 : (v > 0.0 ? 1.0 : -1.0);
  c.y(0) = engaged ? load_friction_ * sign : 0.0;
}

void BacklashFriction::UpdateDiscrete(const BlockContext& c) const {
  const double far = FarSide(c);
  auto state = c.discrete_state();
  state(0) = far;
  state(1) = 1.0;
}

MB_REGISTER_BLOCK(BacklashFriction, BlockType{
    "backlash_friction",
    "f = F_l·s_db(v)·e_g(x): a load's friction felt through a play of gap g, only once the play is taken up after "
    "a reversal (gear, belt, coupling). In: x [m], v [m/s]. Discrete: needs sampleTime [Ts, offset].",
    {Bounded("gap", 1e-3, "m", "g: the full play crossed after each reversal", 1e-12, 1e3),
     Optional("load_friction", 0.0, "N", "F_l: the load's friction felt once the play is taken up"),
     Bounded("dead_band", 0.0, "m/s", "v_db: sign(v) is 0 below it", 0.0, 1e3)},
    SampleTimeRule::kRequired,
    [](const BlockConfig& c) { return std::make_unique<BacklashFriction>(c); }})

// The diagnosis' suggestion made with this block (MB_REGISTER_EFFECT_BLOCK, models/diagnosis/effect_registry.h).
namespace {

// Adds the diagnosed effect backlash (models/diagnosis/effects/backlash.cc): its coefficient is F_l; F_l and the gap
// are refit (the gap moves the switching instants: a refit that cannot move it keeps the diagnosis' value).
EffectBlockTemplate BacklashEffectBlock() {
  EffectBlockTemplate block;
  block.block_type = "backlash_friction";
  block.element_name = "backlash";
  block.output_port = "f";
  block.inputs = {{MotionInput::kPosition, "x"}, {MotionInput::kVelocity, "v"}};
  block.discrete = true;
  block.parameters = [](const DiagnosedEffect& d) {
    return nlohmann::json{{"gap", WithUnit(BlockParameter(d, "backlash"), "m")},
                          {"load_friction", WithUnit(BlockCoefficient(d, ""), "N")},
                          {"dead_band", WithUnit(BlockParameter(d, "dead_band"), "m/s")}};
  };
  block.free = {"load_friction"};
  block.refinable = {"gap"};
  return block;
}

}  // namespace

MB_REGISTER_EFFECT_BLOCK(backlash, BacklashEffectBlock())

}  // namespace mb

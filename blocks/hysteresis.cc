#include "blocks/hysteresis.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "models/diagnosis/effect_block.h"
#include "models/diagnosis/effect_regressors.h"

namespace mb {

namespace {
constexpr std::size_t kMaxHysteresisElements = 50;
}  // namespace

Hysteresis::Hysteresis(const BlockConfig& config)
    : Block(config.name),
      displacements_(config.parameters.Vector("breakaway_displacements")),
      forces_(config.parameters.Vector("breakaway_forces")) {
  if (displacements_.size() == 0 || displacements_.size() > static_cast<Eigen::Index>(kMaxHysteresisElements)) {
    throw std::invalid_argument(fmt::format("breakaway_displacements has {} entries; give 1 to {}",
                                            displacements_.size(), kMaxHysteresisElements));
  }
  if (forces_.size() != displacements_.size()) {
    throw std::invalid_argument(fmt::format("breakaway_forces has {} entries and breakaway_displacements {}: give one "
                                            "force per element",
                                            forces_.size(), displacements_.size()));
  }
  for (Eigen::Index i = 0; i < displacements_.size(); ++i) {
    if (!(displacements_[i] > 0.0) || !std::isfinite(displacements_[i])) {
      throw std::invalid_argument(fmt::format("breakaway_displacements[{}] = {}: each must be > 0 and finite [m]", i,
                                              displacements_[i]));
    }
    if (!std::isfinite(forces_[i])) {
      throw std::invalid_argument(fmt::format("breakaway_forces[{}] = {}: each must be finite [N]", i, forces_[i]));
    }
  }
  if (!config.sample_time) {
    throw std::invalid_argument("hysteresis '" + config.name +
                                "' needs a sampleTime [Ts, offset]: its elements' play positions are updated at each hit");
  }
  DeclareInputPort("x", 1, "m");
  DeclareOutputPort("f", 1, "N");
  DeclareDiscreteState(static_cast<int>(displacements_.size()) + 1);  // p_1 … p_n [m]; 1 once they hold positions
  SetSampleTime(*config.sample_time);
}

double Hysteresis::Play(const BlockContext& c, Eigen::Index i) const {
  const double x = c.u(0);
  const auto state = c.discrete_state();
  if (state(displacements_.size()) == 0.0) return x;
  return std::clamp(state(i), x - displacements_[i], x + displacements_[i]);
}

void Hysteresis::CalcOutput(const BlockContext& c) const {
  const double x = c.u(0);
  double f = 0.0;
  for (Eigen::Index i = 0; i < displacements_.size(); ++i) f += forces_[i] * (x - Play(c, i)) / displacements_[i];
  c.y(0) = f;
}

void Hysteresis::UpdateDiscrete(const BlockContext& c) const {
  auto state = c.discrete_state();
  for (Eigen::Index i = 0; i < displacements_.size(); ++i) state(i) = Play(c, i);
  state(displacements_.size()) = 1.0;
}

MB_REGISTER_BLOCK(Hysteresis, BlockType{
    "hysteresis",
    "f = Σ F_i·(x − p_i)/r_i, p_i the play of half-width r_i on x: a generalised Maxwell-slip model (a Prandtl–"
    "Ishlinskii sum of stop operators), the force following the stroke since the last reversal. In: x [m]. "
    "Discrete: needs sampleTime [Ts, offset].",
    {Required("breakaway_displacements", "m", "r_1 … r_n > 0: each element slides once stretched this far",
              ParamType::kVector),
     Required("breakaway_forces", "N", "F_1 … F_n: each element's force once it slides", ParamType::kVector)},
    SampleTimeRule::kRequired,
    [](const BlockConfig& c) { return std::make_unique<Hysteresis>(c); }})

// The diagnosis' suggestion made with this block (MB_REGISTER_EFFECT_BLOCK, models/diagnosis/effect_registry.h).
namespace {

// Adds the diagnosed effect hysteresis (models/diagnosis/effects/hysteresis.cc): its elements' break-away
// displacements, log-spaced from min_breakaway to max_breakaway as the diagnosis built them, and their forces the joint
// fit's coefficients of the columns hysteresis.r1 … r<n> (free: the next compare refits them with the base).
EffectBlockTemplate HysteresisEffectBlock() {
  EffectBlockTemplate block;
  block.block_type = "hysteresis";
  block.element_name = "hysteresis";
  block.output_port = "f";
  block.inputs = {{MotionInput::kPosition, "x"}};
  block.discrete = true;
  block.parameters = [](const DiagnosedEffect& d) {
    const double lo = BlockParameter(d, "min_breakaway"), hi = BlockParameter(d, "max_breakaway");
    const double elements = BlockParameter(d, "elements");
    if (!(lo > 0.0 && hi >= lo && elements >= 1.0 && elements <= static_cast<double>(kMaxHysteresisElements))) {
      throw std::invalid_argument(fmt::format("hysteresis with break-away displacements {} … {} over {} elements: "
                                              "cannot suggest a block",
                                              lo, hi, elements));
    }
    const std::vector<double> displacements = LogSpaced(lo, hi, static_cast<int>(elements));  // as the regressors
    nlohmann::json forces = nlohmann::json::array();
    for (std::size_t i = 0; i < displacements.size(); ++i) {
      forces.push_back(BlockCoefficient(d, fmt::format("r{}", i + 1)));
    }
    return nlohmann::json{{"breakaway_displacements", displacements}, {"breakaway_forces", forces}};
  };
  block.free = {"breakaway_forces"};
  return block;
}

}  // namespace

MB_REGISTER_EFFECT_BLOCK(hysteresis, HysteresisEffectBlock())

}  // namespace mb

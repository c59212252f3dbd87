#include "models/diagnosis/effect_block.h"

#include <cmath>
#include <memory>
#include <numbers>
#include <stdexcept>

#include <fmt/format.h>

#include "models/diagnosis/factors.h"

namespace mb {

using nlohmann::json;

double BlockCoefficient(const DiagnosedEffect& effect, const std::string& suffix) {
  for (std::size_t k = 0; k < effect.column_names.size(); ++k) {
    const auto& name = effect.column_names[k];
    if (name == effect.effect ? suffix.empty() : name.ends_with("." + suffix)) {
      return effect.coefficients(static_cast<Eigen::Index>(k));
    }
  }
  return 0.0;
}

double BlockParameter(const DiagnosedEffect& effect, const std::string& name) {
  const auto it = effect.parameters.find(name);
  if (it == effect.parameters.end() || !std::isfinite(it->second)) {
    throw std::invalid_argument(fmt::format("effect '{}' without a '{}': cannot suggest a block", effect.effect, name));
  }
  return it->second;
}

int BlockHarmonics(const DiagnosedEffect& effect, int fallback) {
  const auto it = effect.parameters.find("harmonics");
  return it == effect.parameters.end() ? fallback : static_cast<int>(it->second);
}

json FourierBlockParameters(const DiagnosedEffect& effect, int harmonics) {
  json cos_c = json::array(), sin_c = json::array();
  for (int h = 1; h <= harmonics; ++h) {
    cos_c.push_back(BlockCoefficient(effect, fmt::format("cos{}", h)));
    sin_c.push_back(BlockCoefficient(effect, fmt::format("sin{}", h)));
  }
  return {{"harmonics", harmonics}, {"cos_coefficients", cos_c}, {"sin_coefficients", sin_c}};
}

json WithUnit(double value, const std::string& unit) { return {{"value", value}, {"unit", unit}}; }

json LocalBumpTable(const DiagnosedEffect& d, int per_half_width, double span) {
  const double center = BlockParameter(d, "center"), half_width = BlockParameter(d, "half_width");
  if (!(half_width > 0.0)) {
    throw std::invalid_argument(fmt::format("{} with half_width {}: must be > 0 to suggest a table", d.effect,
                                            half_width));
  }
  const double coefficient = BlockCoefficient(d, "");
  json breakpoints = json::array(), table = json::array();
  const int last = static_cast<int>(2.0 * span * per_half_width);
  for (int i = 0; i <= last; ++i) {
    const double z = -span + 2.0 * span * i / last;  // (x − c)/w
    const double c = std::abs(z) < 1.0 ? std::cos(0.5 * std::numbers::pi * z) : 0.0;
    breakpoints.push_back(center + half_width * z);
    table.push_back(coefficient * c * c);
  }
  return {{"breakpoints", breakpoints}, {"table", table}};
}

json SmoothCubicTable(const DiagnosedEffect& d, int breakpoints) {
  const double center = BlockParameter(d, "center"), half_range = BlockParameter(d, "half_range");
  if (!(half_range > 0.0)) {
    throw std::invalid_argument(fmt::format("{} with half_range {}: must be > 0 to suggest a table", d.effect,
                                            half_range));
  }
  if (breakpoints < 2) throw std::invalid_argument(fmt::format("{}: a table needs at least 2 breakpoints", d.effect));
  json at = json::array(), table = json::array();
  for (int i = 0; i < breakpoints; ++i) {
    const double xi = -1.0 + 2.0 * i / (breakpoints - 1);
    double value = 0.0, power = 1.0;
    for (Eigen::Index j = 0; j < std::min<Eigen::Index>(d.coefficients.size(), 3); ++j) {
      power *= xi;
      value += d.coefficients(j) * power;
    }
    at.push_back(center + half_range * xi);
    table.push_back(value);
  }
  return {{"breakpoints", at}, {"table", table}};
}

EffectBlockTemplate PositionRippleBlock(const std::string& block_type, int default_harmonics,
                                        const std::vector<std::pair<MotionInput, std::string>>& extra_inputs) {
  EffectBlockTemplate block;
  block.block_type = block_type;
  block.element_name = "ripple";
  block.inputs = {{MotionInput::kPosition, "x"}};
  block.inputs.insert(block.inputs.end(), extra_inputs.begin(), extra_inputs.end());
  block.parameters = [default_harmonics](const DiagnosedEffect& d) {
    const double period = BlockParameter(d, "period");
    if (!(period > 0.0)) {
      throw std::invalid_argument(fmt::format("{} without a period: cannot suggest a block", d.effect));
    }
    json p = FourierBlockParameters(d, BlockHarmonics(d, default_harmonics));
    p["period"] = WithUnit(period, "m");
    return p;
  };
  block.free = {"cos_coefficients", "sin_coefficients"};
  block.refinable = {"period"};
  block.record_specific = {"position_offset"};
  return block;
}

MotionMultiplier SlipOfVelocity() {
  MotionMultiplier m;
  m.block_type = "sign";
  m.input = MotionInput::kVelocity;
  m.parameters = [](const DiagnosedEffect& d) {
    const double v_s = BlockParameter(d, "slip_velocity");
    if (!(v_s > 0.0)) {
      throw std::invalid_argument(
          fmt::format("{} with slip_velocity {}: must be > 0 to suggest its block", d.effect, v_s));
    }
    return json{{"regularization_velocity", v_s}};
  };
  m.free = {"regularization_velocity"};
  return m;
}

MotionMultiplier MeasuredMotion(MotionInput input) { return {"", input, nullptr, {}}; }

MotionMultiplier ModelForce() {
  MotionMultiplier m;
  m.of_model_force = true;
  return m;
}

MotionMultiplier One() {
  MotionMultiplier m;
  m.one = true;
  return m;
}

MotionMultiplier AmplitudeSourceFactor(bool time) {
  MotionMultiplier m;
  m.clock = time;
  m.amplitude_column = !time;
  return m;
}

MotionMultiplier AbsOf(MotionMultiplier factor) {
  factor.block_type = "abs";
  factor.parameters = [](const DiagnosedEffect&) { return json::object(); };
  return factor;
}

MotionMultiplier SignOf(MotionMultiplier factor) {
  factor.block_type = "sign";
  factor.parameters = [](const DiagnosedEffect&) { return json::object(); };
  return factor;
}

MotionMultiplier Times(MotionMultiplier first, MotionMultiplier second) {
  first.times = std::make_shared<const MotionMultiplier>(std::move(second));
  return first;
}

namespace {

MotionInput InputOf(const std::string& multiplier) {
  return multiplier == "acceleration" ? MotionInput::kAcceleration : MotionInput::kVelocity;
}

// The block a pair's modulator is made with: one × the modulator's, summed into the output alone; else a measured
// motion's (velocity or acceleration × the modulator: a gain scheduled in time whose input "u" is that motion).
// nullptr and `input_port` empty, or the template and its multiplying port.
const EffectBlockTemplate* ModulatorBlock(const std::string& modulator, std::string* input_port) {
  const EffectRegistry& registry = EffectRegistry::Global();
  const auto usable = [](const EffectType* e) {
    return e != nullptr && e->block && e->block->placement == BlockPlacement::kAddToOutput && !e->block->multiplier;
  };
  if (const EffectType* alone = registry.FindPair("one", modulator); usable(alone)) {
    input_port->clear();
    return &*alone->block;
  }
  for (const char* motion : {"velocity", "acceleration"}) {
    const EffectType* e = registry.FindPair(motion, modulator);
    if (!usable(e) || e->block->inputs.size() != 1 || e->block->inputs[0].first != InputOf(motion)) continue;
    *input_port = e->block->inputs[0].second;
    return &*e->block;
  }
  return nullptr;
}

}  // namespace

std::optional<EffectBlockTemplate> BlockFor(const EffectType& type) {
  if (type.block) return type.block;
  if (type.multiplier.empty()) return std::nullopt;
  if (type.multiplier == "acceleration" && type.modulator.starts_with("position_")) return std::nullopt;
  const MultiplierRow* row = FindMultiplier(type.multiplier);
  std::string port;
  const EffectBlockTemplate* modulator = ModulatorBlock(type.modulator, &port);
  if (row == nullptr || !row->factor || modulator == nullptr) return std::nullopt;
  // 1 × a modulator without a block of its own: only a gain scheduled in time, fed the constant 1.
  if (row->factor->one && port.empty()) return std::nullopt;
  EffectBlockTemplate block = *modulator;
  block.element_name = type.name;
  block.physical_range.clear();  // a range of the modulator's own effect; the factor changes what the gain means
  if (!port.empty()) {  // the factor is the block's input
    block.inputs.clear();
    block.multiplier_port = port;
  }
  block.multiplier = row->factor;
  return block;
}

}  // namespace mb

#include "blocks/friction.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "models/diagnosis/effect_block.h"

namespace mb {

Friction::Friction(const BlockConfig& config)
    : Block(config.name), stick_velocity_(config.parameters.Number("stick_velocity")) {
  const auto& p = config.parameters;
  // static = 0 (the default) means "equal to coulomb": no stiction, and a fit may move coulomb freely.
  const double breakaway = p.Number("static") > 0.0 ? p.Number("static") : p.Number("coulomb");
  friction_ = FrictionParameters{p.Number("viscous"), p.Number("coulomb"), breakaway, p.Number("stribeck_velocity")};
  ValidateFrictionParameters(friction_, "friction '" + config.name + "'");
  const std::string& model = p.String("stick_model");
  if (model != "karnopp" && model != "none") {
    throw std::invalid_argument("stick_model must be \"karnopp\" (stick while |f_applied| <= static) or \"none\" "
                                "(slip only), got \"" + model + "\"");
  }
  stick_ = model == "karnopp";
  if (p.String("regularization") == "tanh") {
    if (stick_) {
      throw std::invalid_argument("regularization \"tanh\" is a smooth law without stiction: set stick_model to "
                                  "\"none\" (no f_applied input), or regularization to \"none\" for Karnopp's stick");
    }
    regularization_velocity_ = p.Number("regularization_velocity");
    if (!(regularization_velocity_ > 0.0)) {
      throw std::invalid_argument("regularization_velocity must be > 0 m/s with regularization \"tanh\", got " +
                                  std::to_string(regularization_velocity_));
    }
  }
  DeclareInputPort("v", 1, "m/s");
  if (stick_) DeclareInputPort("f_applied", 1, "N");
  DeclareOutputPort("f", 1, "N");
  if (regularization_velocity_ == 0.0) {
    DeclareDiscreteState(2);  // the mode; the velocity band of the current stick (0 while slipping)
    DeclareZeroCrossings(2);
  }
  SetSampleTime(SampleTime::Continuous());
}

FrictionMode Friction::Mode(const BlockContext& c) {
  return static_cast<FrictionMode>(static_cast<int>(c.discrete_state()(0)));
}

void Friction::CalcOutput(const BlockContext& c) const {
  if (regularization_velocity_ > 0.0) {
    c.y(0) = RegularizedFriction(friction_, regularization_velocity_, c.u(0));
    return;
  }
  c.y(0) = FrictionForce(friction_, Mode(c), c.u(0), AppliedForce(c));
}

void Friction::CalcZeroCrossings(const BlockContext& c) const {
  if (regularization_velocity_ > 0.0) return;  // no modes
  auto g = c.zero_crossings();
  if (Mode(c) == FrictionMode::kStuck) {
    const double f = AppliedForce(c);
    g(0) = friction_.breakaway - f;
    g(1) = friction_.breakaway + f;
  } else {
    g(0) = c.u(0);
    g(1) = 1.0;
  }
}

bool Friction::UpdateModes(const BlockContext& c) const {
  if (regularization_velocity_ > 0.0) return false;
  auto xd = c.discrete_state();
  const FrictionMode old_mode = Mode(c);
  const double band = std::max(stick_velocity_, xd(1));
  const FrictionMode mode = NextFrictionMode(friction_, old_mode, c.u(0), AppliedForce(c), stick_, band);
  // Step-aware stick band: a stick entered at |v| (up to a·h with a fixed-step solver) holds while |v| stays
  // within kStickBandFactor·|v|; with CVODE |v| is at its root tolerance and the band stays stick_velocity.
  if (mode == FrictionMode::kStuck && old_mode != FrictionMode::kStuck) xd(1) = kStickBandFactor * std::abs(c.u(0));
  if (mode != FrictionMode::kStuck) xd(1) = 0.0;
  xd(0) = static_cast<double>(static_cast<int>(mode));
  return mode != old_mode;
}

MB_REGISTER_BLOCK(Friction, BlockType{
    "friction",
    "F = s·(F_c + (F_s − F_c)e^{−(v/v_s)²}) + σv while slipping in s = ±1, F = f_applied while stuck (Karnopp); "
    "ins v [m/s], f_applied [N]; out f [N] resisting the motion (M·ẍ = f_applied − f); the mode switches at "
    "located events; regularization \"tanh\": F = tanh(v/v_reg)·(F_c + (F_s − F_c)e^{−(v/v_s)²}) + σv, no modes.",
    {Bounded("viscous", 0.0, "N·s/m", "viscous coefficient σ", 0.0, std::numeric_limits<double>::infinity()),
     Bounded("coulomb", 0.0, "N", "Coulomb force F_c", 0.0, std::numeric_limits<double>::infinity()),
     Bounded("static", 0.0, "N", "static (breakaway) force F_s >= coulomb; 0 = equal to coulomb", 0.0,
             std::numeric_limits<double>::infinity()),
     Bounded("stribeck_velocity", 0.0, "m/s", "Stribeck velocity v_s (0 = no Stribeck hump)", 0.0,
             std::numeric_limits<double>::infinity()),
     Choice("stick_model", "karnopp", "\"karnopp\" (input f_applied) or \"none\" (slip only)",
            {"karnopp", "none"}),
     Bounded("stick_velocity", 1e-6, "m/s", "|v| above which a stuck body is taken to slip", 0.0,
             std::numeric_limits<double>::infinity()),
     Choice("regularization", "none",
            "\"none\" (the slip direction is a mode switched at events) or \"tanh\" (sign(v) ≈ tanh(v/v_reg), "
            "smooth, no stiction; needs stick_model \"none\")",
            {"none", "tanh"}),
     Bounded("regularization_velocity", 1e-3, "m/s", "v_reg of regularization \"tanh\"", 0.0,
             std::numeric_limits<double>::infinity())},
    SampleTimeRule::kNone,
    [](const BlockConfig& c) { return std::make_unique<Friction>(c); }})

// The diagnosis' suggestions made with this block (MB_REGISTER_EFFECT_BLOCK, models/diagnosis/effect_registry.h).
namespace {

// Adds the diagnosed effect coulomb_friction (models/diagnosis/effects/coulomb_friction.cc) to a diagram.
EffectBlockTemplate CoulombFrictionEffectBlock() {
  EffectBlockTemplate block;
  block.block_type = "friction";
  block.element_name = "coulomb_extra";
  block.output_port = "f";
  block.inputs = {{MotionInput::kVelocity, "v"}};
  // Forces are non-negative here, so a negative coefficient starts from 1 mN (not 0: the fit's central
  // differences would step below the bound) and the fit moves it.
  block.parameters = [](const DiagnosedEffect& d) {
    return nlohmann::json{
        {"viscous", 0.0}, {"coulomb", std::max(1e-3, BlockCoefficient(d, ""))}, {"stick_model", "none"}};
  };
  block.free = {"coulomb"};
  return block;
}

// Adds the diagnosed effect stribeck_friction (models/diagnosis/effects/stribeck_friction.cc) to a diagram: the hump
// tanh(v/v_reg)·F_s·exp(−(v/v_s)²), smooth through v = 0 (regularization "tanh", v_reg starting at a quarter of the
// diagnosis' dead band, as its regressor, free). With the slip direction as a mode (sign(v)) the full hump flips on the velocity noise while the
// machine dwells, and the refit shrinks F_s to a tenth to keep that chatter small (the independent Stribeck case:
// 0.7 N for 9 N, held-out error 1.6 × the floor).
EffectBlockTemplate StribeckFrictionEffectBlock() {
  EffectBlockTemplate block;
  block.block_type = "friction";
  block.element_name = "stribeck";
  block.output_port = "f";
  block.inputs = {{MotionInput::kVelocity, "v"}};
  block.parameters = [](const DiagnosedEffect& d) {
    const double dead_band = BlockParameter(d, "dead_band");
    const double hump = BlockCoefficient(d, "");
    if (!(hump > 0.0)) {  // a static level below zero is no friction block's: refused, not clamped into another effect
      throw std::invalid_argument(fmt::format(
          "the diagnosed low-speed friction is below the model's Coulomb law (a Stribeck hump of {:.3g} N), which a "
          "friction block's static level cannot be: the law near zero velocity is wrong in another way (try a lower "
          "Coulomb level, or --suggest-effect regularized_coulomb_friction when it is ranked)",
          hump));
    }
    return nlohmann::json{
        {"viscous", 0.0},
        {"coulomb", 0.0},
        {"stick_model", "none"},
        {"static", WithUnit(std::max(1e-3, hump), "N")},
        {"stribeck_velocity", WithUnit(BlockParameter(d, "stribeck_velocity"), "m/s")},
        {"regularization", "tanh"},
        // The diagnosis' regressor smooths the hump over a quarter of the dead band (stribeck_friction.cc).
        {"regularization_velocity", WithUnit(dead_band > 0.0 ? 0.25 * dead_band : 1e-3, "m/s")}};
  };
  block.free = {"static", "stribeck_velocity", "regularization_velocity"};
  return block;
}

// Adds the diagnosed effect regularized_coulomb_friction (models/diagnosis/effects/regularized_coulomb_friction.cc):
// the smooth law tanh(v/v_c) in place of sign(v).
EffectBlockTemplate RegularizedCoulombFrictionEffectBlock() {
  EffectBlockTemplate block;
  block.block_type = "friction";
  block.element_name = "smooth_coulomb";
  block.output_port = "f";
  block.inputs = {{MotionInput::kVelocity, "v"}};
  block.parameters = [](const DiagnosedEffect& d) {
    return nlohmann::json{{"viscous", 0.0},
                          {"coulomb", WithUnit(std::max(1e-3, BlockCoefficient(d, "")), "N")},
                          {"stick_model", "none"},
                          {"regularization", "tanh"},
                          {"regularization_velocity", WithUnit(BlockParameter(d, "regularization_velocity"), "m/s")}};
  };
  block.free = {"coulomb", "regularization_velocity"};
  return block;
}

}  // namespace

MB_REGISTER_EFFECT_BLOCK(coulomb_friction, CoulombFrictionEffectBlock())
MB_REGISTER_EFFECT_BLOCK(stribeck_friction, StribeckFrictionEffectBlock())
MB_REGISTER_EFFECT_BLOCK(regularized_coulomb_friction, RegularizedCoulombFrictionEffectBlock())

}  // namespace mb

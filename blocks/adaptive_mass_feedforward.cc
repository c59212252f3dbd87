#include "blocks/adaptive_mass_feedforward.h"

#include <algorithm>
#include <stdexcept>

#include <fmt/format.h>

#include "engine/block_roles.h"
#include "models/stability/dob_design.h"

namespace mb {

namespace {
// Discrete state layout: [Δm̂, P, started, Q{force} state (n), Q∘s²{x} state (n)].
constexpr int kMass = 0, kVariance = 1, kStarted = 2, kFilters = 3;
}  // namespace

AdaptiveMassFeedforward::AdaptiveMassFeedforward(const BlockConfig& config)
    : Block(config.name),
      initial_mass_(config.parameters.Number("initial_mass")),
      prior_variance_(config.parameters.Number("prior_std") * config.parameters.Number("prior_std")),
      noise_variance_(config.parameters.Number("noise_std") * config.parameters.Number("noise_std")),
      forgetting_(config.parameters.Number("forgetting")),
      min_mass_(config.parameters.Number("min_mass")),
      max_mass_(config.parameters.Number("max_mass")) {
  if (!(min_mass_ < max_mass_)) {
    throw std::invalid_argument(fmt::format("{}/min_mass: {:g} kg is not below max_mass {:g} kg: give min_mass < "
                                            "max_mass",
                                            config.name, min_mass_, max_mass_));
  }
  if (initial_mass_ < min_mass_ || initial_mass_ > max_mass_) {
    throw std::invalid_argument(fmt::format("{}/initial_mass: {:g} kg is outside [min_mass, max_mass] = [{:g}, {:g}] "
                                            "kg: start inside the clamp",
                                            config.name, initial_mass_, min_mass_, max_mass_));
  }
  const double ts = config.sample_time->period;
  const double cutoff_hz = config.parameters.Number("cutoff_hz");
  const int relative_degree = config.parameters.Integer("relative_degree");
  q_force_ = Discretize(BinomialLowPass(cutoff_hz, relative_degree), ts, Discretization::kZeroOrderHold);
  // Q∘s²: the DOB's Q∘P_n⁻¹ for a unit mass and no damping, i.e. Q{ẍ} from the sampled position.
  q_acceleration_ = Discretize(QNominalInverse(cutoff_hz, relative_degree, 1.0, 0.0), ts, Discretization::kTustin);
  DeclareInputPort("acceleration", 1, "m/s^2", /*direct_feedthrough=*/true);
  DeclareInputPort("x", 1, "m", /*direct_feedthrough=*/false);
  DeclareInputPort("d_hat", 1, "N", /*direct_feedthrough=*/false);
  DeclareOutputPort("force", 1, "N");
  DeclareOutputPort("mass", 1, "kg");
  DeclareDiscreteState(kFilters + q_force_.order() + q_acceleration_.order());
  SetSampleTime(*config.sample_time);
}

void AdaptiveMassFeedforward::Initialize(const BlockContext& c) const {
  auto s = c.discrete_state();
  s.setZero();
  s(kMass) = initial_mass_;
  s(kVariance) = prior_variance_;
}

void AdaptiveMassFeedforward::CalcOutput(const BlockContext& c) const noexcept {
  const double mass = c.discrete_state()(kMass);
  c.y(0) = mass * c.u(0);
  c.y(1) = mass;
}

void AdaptiveMassFeedforward::UpdateDiscrete(const BlockContext& c) const noexcept {
  auto s = c.discrete_state();
  double* q_force = s.data() + kFilters;
  double* q_acceleration = q_force + q_force_.order();
  const double a = c.u(0), x = c.u(1);
  if (s(kStarted) == 0.0) {  // the position filter starts at rest at the first sample, as the DOB's
    FilterSteadyState(q_acceleration_, x, q_acceleration);
    s(kStarted) = 1.0;
  }
  const double mass = s(kMass);
  const double phi = FilterOutput(q_acceleration_, x, q_acceleration);
  const double y = FilterOutput(q_force_, 0.0, q_force) - c.u(2);
  double p = std::min(s(kVariance) / forgetting_, prior_variance_);
  const double gain = p * phi / (noise_variance_ + phi * phi * p);
  s(kMass) = std::clamp(mass + gain * (y - phi * mass), min_mass_, max_mass_);
  p *= 1.0 - gain * phi;
  s(kVariance) = p;
  FilterUpdate(q_force_, mass * a, q_force);  // the force applied over this period: the output at this hit
  FilterUpdate(q_acceleration_, x, q_acceleration);
}

MB_REGISTER_BLOCK(AdaptiveMassFeedforward, BlockType{
    "adaptive_mass_feedforward",
    "Mass the nominal model lacks, learned online (RLS, forgetting) from the DOB estimate, times an acceleration: "
    "force = Δm̂·acceleration (the reference acceleration, or the command in acceleration units u_c/M_n), added to "
    "the plant's force beside u_c (the DOB does not see it). Regression Q{force} − d_hat = Δm·Q{ẍ}, Q{ẍ} = Q∘s²{x} "
    "with the DOB's Q-filter. sampleTime required.",
    {Bounded("initial_mass", 0.0, "kg", "initial estimate of the mass the nominal model lacks, Δm̂₀", -1e12, 1e12),
     Bounded("prior_std", 0.2, "kg", "prior standard deviation σ_Δm of Δm (also the cap of its variance)", 1e-12,
             1e12),
     Bounded("noise_std", 0.5, "N", "standard deviation σ_n of what the DOB estimate holds besides Δm·Q{ẍ}", 1e-12,
             1e12),
     Bounded("forgetting", 0.9999, "", "forgetting factor λ (memory ≈ Ts/(1 − λ)); 1 = none", 1e-6, 1.0),
     Bounded("min_mass", -0.1, "kg",
             "lower clamp of Δm̂; with the command scaled by (M_n + Δm̂)/M_n keep it well above −M_n", -1e12, 1e12),
     Bounded("max_mass", 1.0, "kg", "upper clamp of Δm̂ (bounds the added force)", -1e12, 1e12),
     Bounded("cutoff_hz", 30.0, "Hz", "the DOB's Q-filter cut-off f_q", 1e-9, 1e12),
     Bounded("relative_degree", 2, "", "the DOB's Q-filter relative degree n_r", 2, 8, ParamType::kInteger)},
    SampleTimeRule::kRequired,
    [](const BlockConfig& c) { return std::make_unique<AdaptiveMassFeedforward>(c); }})

// The parts of a motion loop this block can be (engine/block_roles.h; tools/workflow/loop_from_diagram.h).
MB_REGISTER_LOOP_ROLES(AdaptiveMassFeedforward, "adaptive_mass_feedforward", {"adaptive_feedforward"})

}  // namespace mb

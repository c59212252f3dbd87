#pragma once
// adaptive_mass_feedforward: the mass the nominal model lacks (a payload the loop was not designed for, paper
// section 5.3), learned online from the disturbance observer, and put where a motion-control engineer puts a mass.
//
// The payload's force −Δm·ẍ is a function of the acceleration, not of (x, ẋ), so no GP on (x, ẋ) holds it. The block
// estimates Δm [kg] by recursive least squares (a scalar Kalman filter on a random-walk weight) and outputs
//   force = Δm̂·a,
// to be ADDED to the force the plant receives, beside u_c (the DOB must not see it, as it does not see the GP term:
// u = u_c + force − d̂_g). What a is, is the diagram's choice (input "acceleration" [m/s²]):
//  - the reference acceleration a_r: an acceleration feedforward with the learned mass (the payload's force along
//    the reference; the feedback loop keeps its nominal-mass design);
//  - the command in acceleration units, a = u_c/M_n (a gain block on u_c): the whole controller output scaled by
//    (M_n + Δm̂)/M_n — mass scheduling, which restores the loop the PD, DOB and feedforward were designed for: from
//    u_c the plant then looks like M_n again (for Δm̂ = Δm), and its disturbance response with it
//    (diagrams/paper/gp_loop_adaptive_mass.json; docs/paper.md measures both).
//
// The regression (sign convention of docs/paper.md): the DOB, which sees u_c, estimates
//   d̂_d = Q{M_n ẍ + B_n ẋ − u_c} = Q{d_total + force},  d_total = −Δm·ẍ + (what else disturbs),
// so y = Q{force} − d̂_d = Δm·Q{ẍ} − Q{what else}: the compensation already applied, put back through the DOB's own
// Q, minus the observed disturbance, against the regressor φ = Q{ẍ} = Q∘s²{x} from the sampled position x. Q is the
// DOB's Q-filter (binomial of `relative_degree` at `cutoff_hz`, eq. 5) discretised as the DOB discretises its two
// paths: ZOH for Q{force} (like Q{u_c}), Tustin for Q∘s²{x} (like Q∘P_n⁻¹{x}). y does not depend on the block's
// own output, so the adaptation is an open-loop regression: it converges to Δm whatever the force already applies.
//
// Update at every sample hit k (Ts = the sampleTime), with the weight's variance P [kg²]:
//   P ← min(P/λ, σ_Δm²)                     forgetting λ, never beyond the prior (no wind-up at constant speed)
//   K = P·φ/(σ_n² + φ²·P);   Δm̂ ← clamp(Δm̂ + K·(y − φ·Δm̂), Δm_min, Δm_max);   P ← (1 − K·φ)·P
// (Ljung & Söderström, "Theory and Practice of Recursive Identification", 1983, RLS with exponential forgetting;
// Åström & Wittenmark, "Adaptive Control", 2nd ed., §2.2; mass scheduling of a DOB loop: Ohnishi, Shibata & Murakami,
// "Motion control for advanced mechatronics", IEEE/ASME Trans. Mechatronics 1(1), 1996, on the nominal mass.)
//
// Stability: with a = a_r and Δm̂ frozen, the output is a function of the reference only: a bounded exogenous input
// (|force| ≤ max(|Δm_min|, |Δm_max|)·max|a_r|) that leaves the loop's small-gain condition (ρ, eq. 58, and the "dob" decomposition of
// docs/paper.md) unchanged. With a = u_c/M_n and Δm̂ frozen, the loop is the designed one on a plant of mass
// (M + m_p)·M_n/(M_n + Δm̂) and damping B·M_n/(M_n + Δm̂): analyse that plant (`motionblocks stability --set ...`).
// `motionblocks stability` notes the block and its clamp; it does not cover the adaptation's own dynamics (a slowly
// varying gain, bounded by the clamp).

#include "engine/block.h"
#include "engine/registry.h"
#include "models/stability/lti.h"

namespace mb {

/// Ports: in "acceleration" [m/s²] (a_r or u_c/M_n; feeds through), "x" [m] (the sampled position the DOB reads)
/// and "d_hat" [N] (the DOB estimate) — both read only in the update, no feedthrough; out "force" [N] = Δm̂·a and
/// "mass" [kg] = Δm̂.
/// Parameters: initial_mass Δm̂₀ [kg], prior_std σ_Δm [kg] (> 0), noise_std σ_n [N] (> 0; what the DOB estimate
/// holds besides Δm·Q{ẍ}: friction, cogging the GP leaves), forgetting λ ∈ (0, 1], min_mass Δm_min and max_mass
/// Δm_max [kg] (the clamp; with the command scaled by (M_n + Δm̂)/M_n, Δm_min must stay well above −M_n, else the
/// loop gain collapses), cutoff_hz and relative_degree (≥ 2) of the DOB's Q-filter. Requires a sampleTime.
/// CalcOutput and UpdateDiscrete are noexcept and allocation-free.
/// @throws std::invalid_argument for bad parameters (naming them): min_mass ≥ max_mass, initial_mass outside them.
class AdaptiveMassFeedforward final : public Block {
 public:
  explicit AdaptiveMassFeedforward(const BlockConfig& config);
  void Initialize(const BlockContext& context) const override;
  void CalcOutput(const BlockContext& context) const noexcept override;
  void UpdateDiscrete(const BlockContext& context) const noexcept override;

  double min_mass() const noexcept { return min_mass_; }
  double max_mass() const noexcept { return max_mass_; }

 private:
  double initial_mass_, prior_variance_, noise_variance_, forgetting_, min_mass_, max_mass_;
  DiscreteTf q_force_;         ///< Q by ZOH (strictly proper), as the DOB's Q{u_c}
  DiscreteTf q_acceleration_;  ///< Q∘s² by Tustin, as the DOB's Q∘P_n⁻¹{x}
};

}  // namespace mb

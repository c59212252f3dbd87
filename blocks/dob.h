#pragma once
// dob: the disturbance observer of the paper (eq. 51), discrete at sampleTime [Ts, offset]:
//
//   d̂_d = Q∘P_n⁻¹{x} − Q{u_c}
//
// x: measured (quantised) position [m]; u_c: the force command WITHOUT the GP term, u_c = u + d̂_g =
// C_FF{x_d} + C_FB{e} − d̂_d (DESIGN.md sign convention, plant x = P(u + d)), so that the observer estimates
// only what the GP leaves, d − d̂_g (eq. 46).
//
// Discretisation (docs/paper.md): Q{u_c} by zero-order hold — exact, because u_c is held over each period, and
// strictly proper: the output at hit k depends on u_c up to hit k−1 only, so u_c has NO direct feedthrough and
// the loop u_c → d̂_d → u_c is not algebraic (the one-sample delay every real DOB has). Q∘P_n⁻¹{x}, a biproper
// filter on a sampled (not held) signal, by Tustin (default) or ZOH; x feeds through. Both filters have unit DC
// gain on their band (Q(1) = 1, Q∘P_n⁻¹ has a zero at z = 1), so a constant d is recovered exactly.
// The position filter starts at rest at x(0); Q{u_c} starts at zero (nothing commanded before t0).

#include "engine/block.h"
#include "engine/registry.h"
#include "models/stability/lti.h"

namespace mb {

/// Ports: in "x" [m] (direct feedthrough), "u_c" [N] (none); out "d_hat" [N]. Parameters: nominal_mass M_n
/// [kg], nominal_damping B_n [N·s/m], cutoff_hz f_q [Hz], relative_degree n_r ≥ 2, discretization of Q∘P_n⁻¹
/// ("tustin" | "zoh"). Requires a sampleTime. @throws std::invalid_argument for bad parameters.
class Dob final : public Block {
 public:
  explicit Dob(const BlockConfig& config);
  void CalcOutput(const BlockContext& context) const override;
  void UpdateDiscrete(const BlockContext& context) const override;

  const DiscreteTf& q_filter() const { return q_; }
  const DiscreteTf& q_nominal_inverse() const { return qp_; }

 private:
  DiscreteTf q_;   // Q, ZOH, strictly proper
  DiscreteTf qp_;  // Q∘P_n⁻¹
  int n_q_;
  int n_qp_;
};

}  // namespace mb

#include "blocks/dob.h"

#include "engine/block_roles.h"
#include "models/stability/dob_design.h"

namespace mb {

// Discrete state layout: [started, Q∘P_n⁻¹ state (n_qp), Q state (n_q)].
Dob::Dob(const BlockConfig& config) : Block(config.name) {
  const auto& p = config.parameters;
  const double ts = config.sample_time->period;
  const int nr = p.Integer("relative_degree");
  q_ = Discretize(BinomialLowPass(p.Number("cutoff_hz"), nr), ts, Discretization::kZeroOrderHold);
  qp_ = Discretize(QNominalInverse(p.Number("cutoff_hz"), nr, p.Number("nominal_mass"), p.Number("nominal_damping")),
                   ts, ParseDiscretization(p.String("discretization"), config.name + "/discretization"));
  n_q_ = q_.order();
  n_qp_ = qp_.order();
  DeclareInputPort("x", 1, "m", /*direct_feedthrough=*/true);
  DeclareInputPort("u_c", 1, "N", /*direct_feedthrough=*/false);
  DeclareOutputPort("d_hat", 1, "N");
  DeclareDiscreteState(1 + n_qp_ + n_q_);
  SetSampleTime(*config.sample_time);
}

void Dob::CalcOutput(const BlockContext& c) const {
  const auto s = c.discrete_state();
  const double x = c.u(0);
  // Before the first update the position filter has been at rest at x: its output is DC gain · x = 0.
  const double qpx = s(0) == 0.0 ? qp_.DcGain() * x : FilterOutput(qp_, x, s.data() + 1);
  // Q is strictly proper (b_0 = 0): its output is its state; u_c is not read here.
  const double qu = FilterOutput(q_, 0.0, s.data() + 1 + n_qp_);
  c.y(0) = qpx - qu;
}

void Dob::UpdateDiscrete(const BlockContext& c) const {
  auto s = c.discrete_state();
  const double x = c.u(0);
  if (s(0) == 0.0) {
    FilterSteadyState(qp_, x, s.data() + 1);
    s(0) = 1.0;
  }
  FilterUpdate(qp_, x, s.data() + 1);
  FilterUpdate(q_, c.u(1), s.data() + 1 + n_qp_);
}

MB_REGISTER_BLOCK(Dob, BlockType{
    "dob",
    "Disturbance observer (eq. 51): d_hat = Q∘P_n⁻¹{x} − Q{u_c}; u_c = force command without the GP term. "
    "Discrete (sampleTime required): Q by ZOH (strictly proper, u_c does not feed through: one-sample delay), "
    "Q∘P_n⁻¹ by \"tustin\" (default) or \"zoh\".",
    {Bounded("nominal_mass", 0.2621, "kg", "nominal mass M_n", 1e-12, 1e12),
     Bounded("nominal_damping", 3.0, "N*s/m", "nominal damping B_n", 0.0, 1e12),
     Bounded("cutoff_hz", 30.0, "Hz", "Q-filter cut-off f_q (ω_q = 2π f_q)", 1e-9, 1e12),
     Bounded("relative_degree", 2, "", "Q-filter relative degree n_r", 2, 8, ParamType::kInteger),
     Choice("discretization", "tustin", "Q∘P_n⁻¹ discretisation: \"tustin\" or \"zoh\"", {"tustin", "zoh"})},
    SampleTimeRule::kRequired,
    [](const BlockConfig& c) { return std::make_unique<Dob>(c); }})

// The parts of a motion loop this block can be (engine/block_roles.h; tools/workflow/loop_from_diagram.h).
MB_REGISTER_LOOP_ROLES(Dob, "dob", {"dob"})

}  // namespace mb

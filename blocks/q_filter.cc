#include "blocks/q_filter.h"

#include "models/stability/dob_design.h"

namespace mb {

QFilter::QFilter(const BlockConfig& config) : Block(config.name), discrete_(config.sample_time.has_value()) {
  const auto& p = config.parameters;
  const ContinuousTf q = BinomialLowPass(p.Number("cutoff_hz"), p.Integer("relative_degree"));
  const int n = q.order();
  if (discrete_) {
    filter_ = Discretize(q, config.sample_time->period,
                         ParseDiscretization(p.String("discretization"), config.name + "/discretization"));
    DeclareDiscreteState(n);
    SetSampleTime(*config.sample_time);
  } else {
    realization_ = Realize(q);
    DeclareContinuousState(n);
    SetSampleTime(SampleTime::Continuous());
  }
  const bool feedthrough = discrete_ ? !filter_.strictly_proper() : realization_.D != 0.0;
  DeclareInputPort("u", 1, "", feedthrough);
  DeclareOutputPort("y");
}

void QFilter::CalcOutput(const BlockContext& c) const {
  if (discrete_) {
    // A ZOH filter is strictly proper: b_0 = 0, so u is not read here (no direct feedthrough).
    c.y(0) = FilterOutput(filter_, filter_.strictly_proper() ? 0.0 : c.u(0), c.discrete_state().data());
  } else {
    c.y(0) = realization_.C.dot(c.continuous_state());
  }
}

void QFilter::CalcDerivatives(const BlockContext& c) const {
  c.derivatives().noalias() = realization_.A * c.continuous_state();
  c.derivatives() += realization_.B * c.u(0);
}

void QFilter::UpdateDiscrete(const BlockContext& c) const { FilterUpdate(filter_, c.u(0), c.discrete_state().data()); }

MB_REGISTER_BLOCK(QFilter, BlockType{
    "q_filter",
    "Binomial Q-filter (eq. 5) y = Q{u}, Q(s) = ω^n/(s+ω)^n, ω = 2π·cutoff_hz, n = relative_degree. Continuous "
    "without sampleTime; with sampleTime discretised by \"zoh\" (strictly proper) or \"tustin\".",
    {Bounded("cutoff_hz", 30.0, "Hz", "Q-filter cut-off frequency f_q (ω_q = 2π f_q)", 1e-9, 1e12),
     Bounded("relative_degree", 2, "", "relative degree n_r (binomial order)", 1, 8, ParamType::kInteger),
     Choice("discretization", "zoh", "\"zoh\" or \"tustin\" (discrete form only)", {"zoh", "tustin"})},
    SampleTimeRule::kOptional,
    [](const BlockConfig& c) { return std::make_unique<QFilter>(c); }})

}  // namespace mb

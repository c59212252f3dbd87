#include "blocks/nominal_inverse.h"

#include <stdexcept>

#include "engine/block_roles.h"
#include "models/stability/dob_design.h"

namespace mb {

NominalInverse::NominalInverse(const BlockConfig& config)
    : Block(config.name),
      nominal_mass_(config.parameters.Number("nominal_mass")),
      nominal_damping_(config.parameters.Number("nominal_damping")) {
  const auto& p = config.parameters;
  const std::string& form = p.String("form");
  if (form == "derivatives") {
    form_ = Form::kDerivatives;
    DeclareInputPort("velocity", 1, "m/s");
    DeclareInputPort("acceleration", 1, "m/s^2");
    if (config.sample_time) SetSampleTime(*config.sample_time);
  } else if (form == "filtered") {
    form_ = Form::kFiltered;
    const ContinuousTf f =
        QNominalInverse(p.Number("cutoff_hz"), p.Integer("relative_degree"), nominal_mass_, nominal_damping_);
    discrete_ = config.sample_time.has_value();
    if (discrete_) {
      filter_ = Discretize(f, config.sample_time->period,
                           ParseDiscretization(p.String("discretization"), config.name + "/discretization"));
      DeclareDiscreteState(1 + f.order());  // [started, filter state]
      SetSampleTime(*config.sample_time);
    } else {
      realization_ = Realize(f);
      DeclareContinuousState(f.order());
      SetSampleTime(SampleTime::Continuous());
    }
    DeclareInputPort("x", 1, "m", /*direct_feedthrough=*/true);
  } else {
    throw std::invalid_argument(config.name + "/form: '" + form + "' is unknown; use \"derivatives\" (feedforward "
                                "from the reference's v and a) or \"filtered\" (Q∘P_n⁻¹ on a position)");
  }
  DeclareOutputPort("y", 1, "N");
}

void NominalInverse::CalcOutput(const BlockContext& c) const {
  if (form_ == Form::kDerivatives) {
    c.y(0) = nominal_mass_ * c.u(1) + nominal_damping_ * c.u(0);
    return;
  }
  if (!discrete_) {
    c.y(0) = realization_.C.dot(c.continuous_state()) + realization_.D * c.u(0);
    return;
  }
  const auto xd = c.discrete_state();
  // Before the first update the filter has been at rest at the current position: y = DC gain · x = 0.
  c.y(0) = xd(0) == 0.0 ? filter_.DcGain() * c.u(0) : FilterOutput(filter_, c.u(0), xd.data() + 1);
}

void NominalInverse::CalcDerivatives(const BlockContext& c) const {
  if (form_ != Form::kFiltered || discrete_) return;
  c.derivatives().noalias() = realization_.A * c.continuous_state();
  c.derivatives() += realization_.B * c.u(0);
}

void NominalInverse::UpdateDiscrete(const BlockContext& c) const {
  if (form_ != Form::kFiltered) return;  // the derivatives form is static
  auto xd = c.discrete_state();
  if (xd(0) == 0.0) {
    FilterSteadyState(filter_, c.u(0), xd.data() + 1);
    xd(0) = 1.0;
  }
  FilterUpdate(filter_, c.u(0), xd.data() + 1);
}

MB_REGISTER_BLOCK(NominalInverse, BlockType{
    "nominal_inverse",
    "Nominal-plant inverse P_n⁻¹ = M_n s² + B_n s (eq. 4). form \"derivatives\": y = M_n·acceleration + "
    "B_n·velocity (feedforward C_FF on the reference). form \"filtered\": y = Q∘P_n⁻¹{x} (eq. 51), binomial Q of "
    "relative_degree ≥ 2, continuous or discretised (\"tustin\" default, \"zoh\").",
    {Bounded("nominal_mass", 0.2621, "kg", "nominal mass M_n", 1e-12, 1e12),
     Bounded("nominal_damping", 3.0, "N*s/m", "nominal damping B_n", 0.0, 1e12),
     Choice("form", "derivatives", "\"derivatives\" or \"filtered\"", {"derivatives", "filtered"}),
     Bounded("cutoff_hz", 30.0, "Hz", "Q-filter cut-off (form \"filtered\")", 1e-9, 1e12),
     Bounded("relative_degree", 2, "", "Q-filter relative degree n_r ≥ 2 (form \"filtered\")", 2, 8,
             ParamType::kInteger),
     Choice("discretization", "tustin", "\"tustin\" or \"zoh\" (form \"filtered\" with a sampleTime)",
            {"tustin", "zoh"})},
    SampleTimeRule::kOptional,
    [](const BlockConfig& c) { return std::make_unique<NominalInverse>(c); }})

// The parts of a motion loop this block can be (engine/block_roles.h; tools/workflow/loop_from_diagram.h).
MB_REGISTER_LOOP_ROLES(NominalInverse, "nominal_inverse", {"feedforward"})

}  // namespace mb

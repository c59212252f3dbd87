#include "blocks/integrator.h"

#include <stdexcept>

namespace mb {

Integrator::Integrator(const BlockConfig& config)
    : Block(config.name), initial_condition_(config.parameters.Vector("initial_condition")) {
  const int width = config.parameters.Integer("width");
  if (initial_condition_.size() == 1) initial_condition_ = Eigen::VectorXd::Constant(width, initial_condition_(0));
  if (initial_condition_.size() != width) {
    throw std::invalid_argument("initial_condition needs 1 or `width` entries");
  }
  DeclareInputPort("u", width, "", /*direct_feedthrough=*/false);
  DeclareOutputPort("y", width);
  DeclareContinuousState(width);
  SetSampleTime(SampleTime::Continuous());
}

void Integrator::Initialize(const BlockContext& c) const { c.continuous_state() = initial_condition_; }
void Integrator::CalcOutput(const BlockContext& c) const { c.output(0) = c.continuous_state(); }
void Integrator::CalcDerivatives(const BlockContext& c) const { c.derivatives() = c.input(0); }

MB_REGISTER_BLOCK(Integrator, BlockType{
    "integrator", "ẋ = u, y = x, x(0) = initial_condition. Continuous; no direct feedthrough.",
    {Optional("initial_condition", 0.0, "", "x(0) (scalar or vector)", ParamType::kVector),
     Bounded("width", 1, "", "signal width n", 1, 1e6, ParamType::kInteger)},
    SampleTimeRule::kNone,
    [](const BlockConfig& c) { return std::make_unique<Integrator>(c); }})

}  // namespace mb

#include "blocks/discrete_transfer_function.h"

#include <stdexcept>

namespace mb {

DiscreteTransferFunction::DiscreteTransferFunction(const BlockConfig& config) : Block(config.name) {
  Eigen::VectorXd num = config.parameters.Vector("numerator");
  Eigen::Index first = 0;
  while (first + 1 < num.size() && num(first) == 0.0) ++first;
  num = num.tail(num.size() - first).eval();
  const Eigen::VectorXd den = config.parameters.Vector("denominator");
  if (den.size() == 0 || den(0) == 0.0) {
    throw std::invalid_argument(
        "denominator must start with a non-zero coefficient of the highest power of z (descending powers), e.g. "
        "[1, -0.5] for z − 0.5");
  }
  const Eigen::Index n = den.size() - 1;
  if (num.size() - 1 > n) {
    throw std::invalid_argument("improper (non-causal) transfer function: numerator order " +
                                std::to_string(num.size() - 1) + " > denominator order " + std::to_string(n) +
                                "; add powers of z to the denominator (delays)");
  }
  Eigen::VectorXd b = Eigen::VectorXd::Zero(n + 1);
  b.tail(num.size()) = num / den(0);
  beta0_ = b(0);
  beta_ = b.tail(n);
  alpha_ = den.tail(n) / den(0);
  DeclareInputPort("u", 1, "", /*direct_feedthrough=*/beta0_ != 0.0);
  DeclareOutputPort("y");
  DeclareDiscreteState(static_cast<int>(n));
  SetSampleTime(*config.sample_time);
}

void DiscreteTransferFunction::CalcOutput(const BlockContext& c) const {
  const auto s = c.discrete_state();
  c.y(0) = beta0_ * c.u(0) + (s.size() > 0 ? s(0) : 0.0);
}

void DiscreteTransferFunction::UpdateDiscrete(const BlockContext& c) const {
  auto s = c.discrete_state();
  const Eigen::Index n = s.size();
  const double u = c.u(0);
  const double y = beta0_ * u + (n > 0 ? s(0) : 0.0);
  // In place, ascending i: s_i uses the old s_{i+1}, not yet overwritten.
  for (Eigen::Index i = 0; i + 1 < n; ++i) s(i) = beta_(i) * u - alpha_(i) * y + s(i + 1);
  if (n > 0) s(n - 1) = beta_(n - 1) * u - alpha_(n - 1) * y;
}

MB_REGISTER_BLOCK(DiscreteTransferFunction, BlockType{
    "discrete_transfer_function",
    "y = H(z)u, H = numerator/denominator in descending powers of z (Simulink's convention), proper; direct form "
    "II transposed. Discrete: needs sampleTime [Ts, offset].",
    {Optional("numerator", 1.0, "", "numerator coefficients, descending powers of z", ParamType::kVector),
     Optional("denominator", nlohmann::json::array({1.0, -0.5}), "",
              "denominator coefficients, descending powers of z (first non-zero)", ParamType::kVector)},
    SampleTimeRule::kRequired,
    [](const BlockConfig& c) { return std::make_unique<DiscreteTransferFunction>(c); }})

}  // namespace mb

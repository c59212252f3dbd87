#include "blocks/transfer_function.h"

#include <stdexcept>

namespace mb {

namespace {

// Drops leading zeros (a numerator written [0, 0, 1] means 1); keeps at least one entry.
Eigen::VectorXd TrimLeadingZeros(const Eigen::VectorXd& v) {
  Eigen::Index first = 0;
  while (first + 1 < v.size() && v(first) == 0.0) ++first;
  return v.tail(v.size() - first);
}

}  // namespace

TransferFunction::TransferFunction(const BlockConfig& config) : Block(config.name) {
  const Eigen::VectorXd num = TrimLeadingZeros(config.parameters.Vector("numerator"));
  const Eigen::VectorXd den_raw = config.parameters.Vector("denominator");
  if (den_raw.size() == 0 || den_raw(0) == 0.0) {
    throw std::invalid_argument(
        "denominator must start with a non-zero coefficient of the highest power of s (descending powers), e.g. "
        "[1, 2, 1] for s² + 2s + 1");
  }
  const Eigen::Index n = den_raw.size() - 1;
  if (num.size() - 1 > n) {
    throw std::invalid_argument("improper transfer function: numerator order " + std::to_string(num.size() - 1) +
                                " > denominator order " + std::to_string(n) +
                                "; add poles (e.g. a derivative filter) to make it proper");
  }
  const double a0 = den_raw(0);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(n + 1);
  b.tail(num.size()) = num / a0;
  a_ = den_raw.tail(n) / a0;
  d_ = b(0);
  c_ = b.tail(n) - a_ * d_;
  DeclareInputPort("u", 1, "", /*direct_feedthrough=*/d_ != 0.0);
  DeclareOutputPort("y");
  DeclareContinuousState(static_cast<int>(n));
  SetSampleTime(SampleTime::Continuous());
}

void TransferFunction::CalcOutput(const BlockContext& c) const {
  c.y(0) = c_.dot(c.continuous_state()) + d_ * c.u(0);
}

void TransferFunction::CalcDerivatives(const BlockContext& c) const {
  const auto x = c.continuous_state();
  auto dx = c.derivatives();
  const Eigen::Index n = x.size();
  if (n == 0) return;
  dx(0) = c.u(0) - a_.dot(x);
  dx.tail(n - 1) = x.head(n - 1);
}

MB_REGISTER_BLOCK(TransferFunction, BlockType{
    "transfer_function",
    "y = H(s)u, H = numerator/denominator in descending powers of s, proper; controllable canonical form; "
    "feeds through only when biproper.",
    {Optional("numerator", 1.0, "", "numerator coefficients, descending powers of s", ParamType::kVector),
     Optional("denominator", nlohmann::json::array({1.0, 1.0}), "",
              "denominator coefficients, descending powers of s (first non-zero)", ParamType::kVector)},
    SampleTimeRule::kNone,
    [](const BlockConfig& c) { return std::make_unique<TransferFunction>(c); }})

}  // namespace mb

#include "blocks/state_space.h"

#include <cmath>
#include <stdexcept>

namespace mb {

namespace {

// A rows×cols matrix from a row-major vector.
Eigen::MatrixXd RowMajor(const Eigen::VectorXd& v, Eigen::Index rows, Eigen::Index cols) {
  return Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(v.data(), rows,
                                                                                                   cols);
}

}  // namespace

StateSpace::StateSpace(const BlockConfig& config) : Block(config.name) {
  const auto& p = config.parameters;
  const Eigen::VectorXd a = p.Vector("A"), b = p.Vector("B"), c = p.Vector("C"), d = p.Vector("D");
  const auto n = static_cast<Eigen::Index>(std::llround(std::sqrt(static_cast<double>(a.size()))));
  if (n < 1 || n * n != a.size()) {
    throw std::invalid_argument("A has " + std::to_string(a.size()) +
                                " entries; it must be a square n×n matrix given row by row (n² entries, n ≥ 1)");
  }
  if (b.size() == 0 || b.size() % n != 0) {
    throw std::invalid_argument("B has " + std::to_string(b.size()) + " entries; it must be n×m = " +
                                std::to_string(n) + "×m, given row by row");
  }
  if (c.size() == 0 || c.size() % n != 0) {
    throw std::invalid_argument("C has " + std::to_string(c.size()) + " entries; it must be p×n = p×" +
                                std::to_string(n) + ", given row by row");
  }
  const Eigen::Index m = b.size() / n, outputs = c.size() / n;
  a_ = RowMajor(a, n, n);
  b_ = RowMajor(b, n, m);
  c_ = RowMajor(c, outputs, n);
  if (d.size() == 1 && d(0) == 0.0) {
    d_ = Eigen::MatrixXd::Zero(outputs, m);
  } else if (d.size() == outputs * m) {
    d_ = RowMajor(d, outputs, m);
  } else {
    throw std::invalid_argument("D has " + std::to_string(d.size()) + " entries; it must be p×m = " +
                                std::to_string(outputs) + "×" + std::to_string(m) + " (or 0)");
  }
  x0_ = p.Vector("x0");
  if (x0_.size() == 1) x0_ = Eigen::VectorXd::Constant(n, x0_(0));
  if (x0_.size() != n) {
    throw std::invalid_argument("x0 has " + std::to_string(x0_.size()) + " entries; give 1 or n = " +
                                std::to_string(n));
  }
  feedthrough_ = (d_.array() != 0.0).any();
  DeclareInputPort("u", static_cast<int>(m), "", feedthrough_);
  DeclareOutputPort("y", static_cast<int>(outputs));
  DeclareContinuousState(static_cast<int>(n));
  SetSampleTime(SampleTime::Continuous());
}

void StateSpace::Initialize(const BlockContext& c) const { c.continuous_state() = x0_; }

void StateSpace::CalcOutput(const BlockContext& c) const {
  auto y = c.output(0);
  y.noalias() = c_ * c.continuous_state();
  if (feedthrough_) y.noalias() += d_ * c.input(0);
}

void StateSpace::CalcDerivatives(const BlockContext& c) const {
  auto dx = c.derivatives();
  dx.noalias() = a_ * c.continuous_state();
  dx.noalias() += b_ * c.input(0);
}

MB_REGISTER_BLOCK(StateSpace, BlockType{
    "state_space",
    "ẋ = Ax + Bu, y = Cx + Du; matrices as row-major vectors (sizes from A, B, C); feeds through iff D ≠ 0.",
    {Required("A", "", "n×n state matrix, row by row", ParamType::kVector),
     Required("B", "", "n×m input matrix, row by row", ParamType::kVector),
     Required("C", "", "p×n output matrix, row by row", ParamType::kVector),
     Optional("D", 0.0, "", "p×m feedthrough matrix, row by row (0 = zeros)", ParamType::kVector),
     Optional("x0", 0.0, "", "initial state (scalar or n entries)", ParamType::kVector)},
    SampleTimeRule::kNone,
    [](const BlockConfig& c) { return std::make_unique<StateSpace>(c); }})

}  // namespace mb

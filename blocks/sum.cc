#include "blocks/sum.h"

#include <stdexcept>

namespace mb {

Sum::Sum(const BlockConfig& config) : Block(config.name) {
  const std::string& signs = config.parameters.String("signs");
  const int width = config.parameters.Integer("width");
  if (signs.empty()) throw std::invalid_argument("signs must list at least one '+' or '-'");
  for (char s : signs) {
    if (s != '+' && s != '-') {
      throw std::invalid_argument("signs may contain only '+' and '-', got \"" + signs + "\"");
    }
    signs_.push_back(s == '+' ? 1.0 : -1.0);
    DeclareInputPort("u" + std::to_string(signs_.size()), width);
  }
  DeclareOutputPort("y", width);
}

void Sum::CalcOutput(const BlockContext& c) const {
  // Element by element, in the inputs' order (the same sums as y = 0; y += s_i·u_i): no Eigen expression per
  // input, which costs more than the arithmetic at the usual width 1.
  auto y = c.output(0);
  for (Eigen::Index k = 0; k < y.size(); ++k) {
    double sum = 0.0;
    for (std::size_t i = 0; i < signs_.size(); ++i) sum += signs_[i] * c.u(static_cast<int>(i), static_cast<int>(k));
    y(k) = sum;
  }
}

MB_REGISTER_BLOCK(Sum, BlockType{
    "sum", "y = Σ s_i·u_i with signs like \"+-\"; inputs u1…uN. Inherits its sample time.",
    {Optional("signs", "++", "", "one '+' or '-' per input", ParamType::kString),
     Bounded("width", 1, "", "signal width n", 1, 1e6, ParamType::kInteger)},
    SampleTimeRule::kNone,
    [](const BlockConfig& c) { return std::make_unique<Sum>(c); },
    nlohmann::json{{"signs", "++"}},
    nlohmann::json{{"signs", "+-"}}})

}  // namespace mb

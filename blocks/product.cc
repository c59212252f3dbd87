#include "blocks/product.h"

#include <stdexcept>

namespace mb {

Product::Product(const BlockConfig& config) : Block(config.name) {
  const std::string& ops = config.parameters.String("ops");
  const int width = config.parameters.Integer("width");
  if (ops.empty()) throw std::invalid_argument("ops must list at least one '*' or '/'");
  for (char op : ops) {
    if (op != '*' && op != '/') {
      throw std::invalid_argument("ops may contain only '*' (multiply) and '/' (divide), got \"" + ops + "\"");
    }
    divide_.push_back(op == '/');
    DeclareInputPort("u" + std::to_string(divide_.size()), width);
  }
  DeclareOutputPort("y", width);
}

void Product::CalcOutput(const BlockContext& c) const {
  auto y = c.output(0);
  y.setOnes();
  for (std::size_t i = 0; i < divide_.size(); ++i) {
    const auto u = c.input(static_cast<int>(i));
    if (divide_[i]) {
      y.array() /= u.array();
    } else {
      y.array() *= u.array();
    }
  }
}

MB_REGISTER_BLOCK(Product, BlockType{
    "product", "y = Π u_i^{±1}, element-wise, with ops like \"*/\" (u1 / u2); inputs u1…uN. Inherits its sample time.",
    {Optional("ops", "**", "", "one '*' (multiply) or '/' (divide) per input", ParamType::kString),
     Bounded("width", 1, "", "signal width n", 1, 1e6, ParamType::kInteger)},
    SampleTimeRule::kNone,
    [](const BlockConfig& c) { return std::make_unique<Product>(c); }})

}  // namespace mb

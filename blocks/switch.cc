#include "blocks/switch.h"

#include <stdexcept>
#include <string>

namespace mb {
namespace {

Switch::Criterion CriterionOf(const std::string& name) {
  if (name == "u2 >= threshold") return Switch::Criterion::kGreaterOrEqual;
  if (name == "u2 > threshold") return Switch::Criterion::kGreater;
  if (name == "u2 ~= 0") return Switch::Criterion::kNonZero;
  throw std::invalid_argument("criteria must be \"u2 >= threshold\", \"u2 > threshold\" or \"u2 ~= 0\" (Simulink's "
                              "three), got \"" + name + "\"");
}

}  // namespace

Switch::Switch(const BlockConfig& config)
    : Block(config.name),
      criterion_(CriterionOf(config.parameters.String("criteria"))),
      threshold_(config.parameters.Number("threshold")) {
  const int width = config.parameters.Integer("width");
  DeclareInputPort("u1", width);
  DeclareInputPort("u2", 1);
  DeclareInputPort("u3", width);
  DeclareOutputPort("y", width);
}

void Switch::CalcOutput(const BlockContext& c) const {
  const double control = c.input(1)(0);
  bool first = false;
  switch (criterion_) {
    case Criterion::kGreaterOrEqual: first = control >= threshold_; break;
    case Criterion::kGreater: first = control > threshold_; break;
    case Criterion::kNonZero: first = control != 0.0; break;
  }
  c.output(0) = first ? c.input(0) : c.input(2);
}

MB_REGISTER_BLOCK(Switch, BlockType{
    "switch", "y = u1 where u2 passes the criterion, else u3 (Simulink's Switch). Inherits its sample time.",
    {Choice("criteria", "u2 >= threshold", "when u1 passes: \"u2 >= threshold\", \"u2 > threshold\" or \"u2 ~= 0\"",
            {"u2 >= threshold", "u2 > threshold", "u2 ~= 0"}),
     Optional("threshold", 0.0, "", "the control input's threshold (unit of u2)"),
     Bounded("width", 1, "", "width n of u1, u3 and y", 1, 1e6, ParamType::kInteger)},
    SampleTimeRule::kNone,
    [](const BlockConfig& c) { return std::make_unique<Switch>(c); }})

}  // namespace mb

#include "engine/registry.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "engine/closest_names.h"
#include "engine/json_schema.h"

namespace mb {

BlockRegistry& BlockRegistry::Global() {
  static BlockRegistry registry;
  return registry;
}

bool BlockRegistry::Add(BlockType type) {
  const std::string name = type.type_name;
  if (!types_.emplace(name, std::move(type)).second) {
    throw std::logic_error(fmt::format("block type '{}' registered twice", name));
  }
  return true;
}

const BlockType* BlockRegistry::Find(const std::string& type_name) const {
  auto it = types_.find(type_name);
  return it == types_.end() ? nullptr : &it->second;
}

std::vector<std::string> BlockRegistry::TypeNames() const {
  std::vector<std::string> names;
  for (const auto& [name, type] : types_) names.push_back(name);
  return names;
}

const BlockType& BlockRegistry::SumOfTwo() const {
  for (const auto& [name, type] : types_) {
    if (type.sum_of_two) return type;
  }
  throw std::logic_error("no registered block type adds two signals (sum_of_two): link mb_blocks into the program");
}

const BlockType& BlockRegistry::DifferenceOfTwo() const {
  for (const auto& [name, type] : types_) {
    if (type.difference_of_two) return type;
  }
  throw std::logic_error(
      "no registered block type subtracts two signals (difference_of_two): link mb_blocks into the program");
}

std::vector<std::string> BlockRegistry::Suggest(const std::string& type_name, std::size_t max_suggestions) const {
  return ClosestNames(type_name, TypeNames(), max_suggestions);
}

const BlockType& BlockRegistry::Get(const std::string& type_name) const {
  if (const BlockType* type = Find(type_name)) return *type;
  std::string close;
  for (const auto& name : Suggest(type_name)) close += (close.empty() ? "" : ", ") + name;
  throw std::invalid_argument(fmt::format("unknown block type '{}'{}: `motionblocks blocks` lists them", type_name,
                                          close.empty() ? "" : " (did you mean " + close + "?)"));
}

// ---- The block reference -----------------------------------------------------------------------------------------

namespace {

constexpr double kExampleSampleTime = 1e-3;  // [s], for types that require a sampleTime

std::string PortText(const PortSpec& port, bool input) {
  std::string attributes = port.unit.empty() ? "any" : port.unit;
  if (input && port.direct_feedthrough) attributes += ", direct feedthrough";
  return fmt::format("{}{} [{}]", port.name, port.width > 1 ? fmt::format("[{}]", port.width) : "", attributes);
}

std::string PortList(const std::vector<PortSpec>& ports, bool input) {
  std::string out;
  for (const auto& p : ports) out += (out.empty() ? "" : ", ") + PortText(p, input);
  return out.empty() ? "none" : out;
}

nlohmann::json Placeholder(const ParamSpec& p) {
  const double number = p.min && std::isfinite(*p.min) && *p.min > 1.0 ? *p.min : 1.0;
  switch (p.type) {
    case ParamType::kNumber: return number;
    case ParamType::kInteger: return static_cast<long>(std::ceil(number));
    case ParamType::kBool: return false;
    case ParamType::kString: return !p.choices.empty() ? p.choices.front() : p.file ? "FILE" : "TEXT";
    case ParamType::kVector: return nlohmann::json::array({number});
  }
  return nullptr;
}

const char* SampleTimeText(SampleTimeRule rule) {
  switch (rule) {
    case SampleTimeRule::kNone: return "none (continuous or inherited)";
    case SampleTimeRule::kRequired: return "required: Ts or [Ts, offset] in s (discrete)";
    case SampleTimeRule::kOptional: return "optional: Ts or [Ts, offset] in s makes it discrete";
  }
  return "";
}

}  // namespace

BlockTypePorts DefaultPorts(const BlockType& type) {
  BlockTypePorts ports;
  std::vector<std::string> missing;
  for (const auto& p : type.parameters) {
    if (!p.default_value) missing.push_back(p.name);
  }
  if (!missing.empty()) {
    ports.why_unknown = "ports depend on parameters (no default for " + missing.front();
    for (std::size_t i = 1; i < missing.size(); ++i) ports.why_unknown += ", " + missing[i];
    ports.why_unknown += ")";
    return ports;
  }
  try {
    std::vector<std::string> problems;
    auto values = ValidateParameters(type.parameters, nlohmann::json::object(), "", &problems);
    if (!problems.empty()) {
      ports.why_unknown = "ports depend on parameters (the defaults do not validate: " + problems.front() + ")";
      return ports;
    }
    std::optional<SampleTime> sample_time;
    if (type.sample_time_rule == SampleTimeRule::kRequired) sample_time = SampleTime::Discrete(kExampleSampleTime);
    const auto block = type.factory(BlockConfig{type.type_name, Parameters(type.type_name, std::move(values)),
                                                sample_time, {}});
    ports.inputs = block->input_ports();
    ports.outputs = block->output_ports();
    ports.known = true;
  } catch (const std::exception& e) {
    ports.why_unknown = fmt::format("ports not listed: the type does not build without a diagram ({})", e.what());
  }
  return ports;
}

std::string PortsSummary(const BlockTypePorts& ports) {
  if (!ports.known) return ports.why_unknown;
  return fmt::format("inputs {}; outputs {}", PortList(ports.inputs, true), PortList(ports.outputs, false));
}

nlohmann::json ExampleElement(const BlockType& type) {
  nlohmann::json parameters = nlohmann::json::object();
  for (const auto& p : type.parameters) {
    if (!p.default_value) parameters[p.name] = Placeholder(p);
  }
  nlohmann::json element = {{"name", type.type_name}, {"type", type.type_name}, {"parameters", parameters}};
  if (type.sample_time_rule == SampleTimeRule::kRequired) element["sampleTime"] = kExampleSampleTime;
  return element;
}

std::string BlockReference(const BlockType& type) {
  std::string out = fmt::format("{}\n    {}\n", type.type_name, type.description);
  const BlockTypePorts ports = DefaultPorts(type);
  if (!ports.known) {
    out += fmt::format("  {}\n", ports.why_unknown);
  } else {
    out += "  ports (built with the default parameters):\n";
    const auto add = [&out](const std::vector<PortSpec>& list, bool input) {
      for (std::size_t i = 0; i < list.size(); ++i) {
        const PortSpec& p = list[i];
        const char* feedthrough = !input ? "" : p.direct_feedthrough ? ", direct feedthrough" : ", no direct feedthrough";
        out += fmt::format("    {:<6} {}: {}{} [{}]{}\n", input ? "input" : "output", i, p.name,
                           p.width > 1 ? fmt::format(" (width {})", p.width) : "", p.unit.empty() ? "any unit" : p.unit,
                           feedthrough);
      }
    };
    add(ports.inputs, true);
    add(ports.outputs, false);
    if (ports.inputs.empty() && ports.outputs.empty()) out += "    none\n";
  }
  out += "  parameters:\n";
  for (const auto& p : type.parameters) {
    out += fmt::format("    - {} ({}{}){}: {}\n", p.name, ToString(p.type), p.unit.empty() ? "" : ", " + p.unit,
                       p.default_value ? " = " + p.default_value->dump() : " [required]", p.description);
  }
  if (type.parameters.empty()) out += "    none\n";
  // The units above are a linear axis's (m, N); on a rotary diagram the same numbers read in its units (AxisUnit).
  const MotionAxis rotary{"rad", "N·m"};
  std::string rotary_units;
  for (const auto& p : type.parameters) {
    if (const std::string unit = AxisUnit(p.unit, rotary); unit != p.unit) {
      rotary_units += fmt::format("{}{} [{}]", rotary_units.empty() ? "" : ", ", p.name, unit);
    }
  }
  if (!rotary_units.empty()) {
    out += fmt::format("  on a rotary diagram (connectors in rad and N·m) the same numbers are in: {}\n", rotary_units);
  }
  out += fmt::format("  sampleTime: {}\n", SampleTimeText(type.sample_time_rule));
  out += fmt::format("  example: {}\n", ExampleElement(type).dump());
  return out;
}

}  // namespace mb

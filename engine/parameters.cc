#include "engine/parameters.h"

#include <cmath>
#include <optional>
#include <stdexcept>

#include <fmt/format.h>

#include "engine/closest_names.h"
#include "engine/text_excerpt.h"
#include "engine/units.h"

namespace mb {

const char* ToString(ParamType type) {
  switch (type) {
    case ParamType::kNumber: return "number";
    case ParamType::kInteger: return "integer";
    case ParamType::kBool: return "bool";
    case ParamType::kString: return "string";
    case ParamType::kVector: return "vector";
  }
  return "unknown";
}

ParamSpec Required(std::string name, std::string unit, std::string description, ParamType type) {
  return ParamSpec{std::move(name), type, std::move(unit), std::nullopt, std::move(description), {}, {}, {}, false, {}};
}

ParamSpec Optional(std::string name, nlohmann::json default_value, std::string unit, std::string description,
                   ParamType type) {
  return ParamSpec{std::move(name), type, std::move(unit), std::move(default_value), std::move(description),
                   {}, {}, {}, false, {}};
}

ParamSpec Bounded(std::string name, nlohmann::json default_value, std::string unit, std::string description,
                  double min, double max, ParamType type) {
  ParamSpec spec =
      Optional(std::move(name), std::move(default_value), std::move(unit), std::move(description), type);
  spec.min = min;
  spec.max = max;
  return spec;
}

ParamSpec OnAxis(ParamSpec spec, const MotionAxis& axis) {
  if (!spec.linear_unit.empty()) return spec;  // already on an axis
  std::string unit = AxisUnit(spec.unit, axis);
  if (unit != spec.unit) {
    spec.linear_unit = std::move(spec.unit);
    spec.unit = std::move(unit);
  }
  return spec;
}

std::vector<ParamSpec> OnAxis(std::vector<ParamSpec> specs, const MotionAxis& axis) {
  if (axis.is_linear()) return specs;
  for (auto& spec : specs) spec = OnAxis(std::move(spec), axis);
  return specs;
}

MotionAxis DiagramAxis(const nlohmann::json& diagram) {
  if (!diagram.is_object() || !diagram.contains("connectors") || !diagram["connectors"].is_array()) return {};
  std::vector<std::pair<std::string, std::string>> units;
  for (const char* kind : {"input", "output"}) {
    for (const auto& c : diagram["connectors"]) {
      if (!c.is_object() || !c.contains("unit") || !c["unit"].is_string()) continue;
      const auto k = c.find("kind");
      if (k == c.end() || !k->is_string() || k->get<std::string>() != kind) continue;
      const auto q = c.find("quantity");
      units.emplace_back(c["unit"].get<std::string>(),
                         q != c.end() && q->is_string() ? q->get<std::string>() : std::string());
    }
  }
  return AxisOfConnectors(units);
}

ParamSpec FileName(std::string name, std::string description) {
  ParamSpec spec = Required(std::move(name), "", std::move(description), ParamType::kString);
  spec.file = true;
  return spec;
}

ParamSpec Choice(std::string name, std::string default_value, std::string description,
                 std::vector<std::string> choices) {
  ParamSpec spec = Optional(std::move(name), std::move(default_value), "", std::move(description), ParamType::kString);
  spec.choices = std::move(choices);
  return spec;
}

Parameters::Parameters(std::string block_name, std::map<std::string, nlohmann::json> values)
    : block_name_(std::move(block_name)), values_(std::move(values)) {}

const nlohmann::json& Parameters::Get(const std::string& name) const {
  auto it = values_.find(name);
  if (it == values_.end()) {
    throw std::logic_error(fmt::format("block '{}' reads undeclared parameter '{}'", block_name_, name));
  }
  return it->second;
}

double Parameters::Number(const std::string& name) const {
  const auto& v = Get(name);
  if (!v.is_number()) throw std::logic_error(fmt::format("block '{}': parameter '{}' is not a number", block_name_, name));
  return v.get<double>();
}

int Parameters::Integer(const std::string& name) const {
  const auto& v = Get(name);
  if (!v.is_number_integer()) {
    throw std::logic_error(fmt::format("block '{}': parameter '{}' is not an integer", block_name_, name));
  }
  return v.get<int>();
}

bool Parameters::Bool(const std::string& name) const {
  const auto& v = Get(name);
  if (!v.is_boolean()) throw std::logic_error(fmt::format("block '{}': parameter '{}' is not a bool", block_name_, name));
  return v.get<bool>();
}

const std::string& Parameters::String(const std::string& name) const {
  const auto& v = Get(name);
  if (!v.is_string()) throw std::logic_error(fmt::format("block '{}': parameter '{}' is not a string", block_name_, name));
  return v.get_ref<const std::string&>();
}

Eigen::VectorXd Parameters::Vector(const std::string& name) const {
  const auto& v = Get(name);
  if (v.is_number()) return Eigen::VectorXd::Constant(1, v.get<double>());
  if (!v.is_array()) throw std::logic_error(fmt::format("block '{}': parameter '{}' is not a vector", block_name_, name));
  Eigen::VectorXd out(static_cast<Eigen::Index>(v.size()));
  for (std::size_t i = 0; i < v.size(); ++i) out(static_cast<Eigen::Index>(i)) = v[i].get<double>();
  return out;
}

namespace {

bool IsFiniteNumber(const nlohmann::json& v) { return v.is_number() && std::isfinite(v.get<double>()); }

std::string CheckValue(const ParamSpec& spec, const nlohmann::json& v) {
  switch (spec.type) {
    case ParamType::kNumber:
      if (!v.is_number()) return fmt::format("must be a number [{}], got {}", spec.unit, v.dump());
      if (!IsFiniteNumber(v)) return "must be finite";
      break;
    case ParamType::kInteger:
      if (!v.is_number_integer()) return fmt::format("must be an integer, got {}", v.dump());
      break;
    case ParamType::kBool:
      if (!v.is_boolean()) return fmt::format("must be true or false, got {}", v.dump());
      break;
    case ParamType::kString:
      if (!v.is_string()) return fmt::format("must be a string, got {}", v.dump());
      break;
    case ParamType::kVector:
      if (v.is_number()) break;
      if (!v.is_array()) return fmt::format("must be an array of numbers [{}], got {}", spec.unit, v.dump());
      for (const auto& e : v) {
        if (!IsFiniteNumber(e)) return fmt::format("must be an array of finite numbers, got {}", v.dump());
      }
      break;
  }
  auto check_bounds = [&](double x) -> std::string {
    if (spec.min && x < *spec.min) return fmt::format("must be >= {} [{}], got {}", *spec.min, spec.unit, x);
    if (spec.max && x > *spec.max) return fmt::format("must be <= {} [{}], got {}", *spec.max, spec.unit, x);
    return {};
  };
  if (v.is_number()) return check_bounds(v.get<double>());
  if (v.is_array()) {
    for (const auto& e : v) {
      if (auto msg = check_bounds(e.get<double>()); !msg.empty()) return msg;
    }
  }
  return {};
}

// The factor from `unit` to `spec`'s unit: UnitFactor, or 1 for the linear unit a spec put OnAxis stands for.
std::optional<double> UnitFactorToSpec(const std::string& unit, const ParamSpec& spec) {
  if (const auto factor = UnitFactor(unit, spec.unit)) return factor;
  if (!spec.linear_unit.empty() && SameUnit(unit, spec.linear_unit)) return 1.0;
  return std::nullopt;
}

// Turns `value` written in `unit` into the spec's declared unit (engine/units.h: UnitFactor), numbers and arrays
// of numbers scaled; "" when done, else the message (without the pointer).
std::string ConvertToDeclaredUnit(const ParamSpec& spec, const nlohmann::json& unit_json, nlohmann::json* value) {
  const std::string unit = unit_json.is_string() ? unit_json.get<std::string>() : std::string("?");
  if (spec.unit.empty()) {
    if (unit.empty() || unit == "1") return {};
    return fmt::format("this parameter has no unit (a plain number), but \"unit\": \"{}\" is given; remove the "
                       "unit",
                       unit);
  }
  const std::optional<double> factor = UnitFactorToSpec(unit, spec);
  if (!factor) {
    if (spec.linear_unit.empty()) {
      return fmt::format("unit mismatch: given '{}', this parameter is in '{}' (SI)", unit, spec.unit);
    }
    return fmt::format("unit mismatch: given '{}', this parameter is in '{}' on this diagram's axis (SI; '{}' on a "
                       "linear axis)",
                       unit, spec.unit, spec.linear_unit);
  }
  if (*factor == 1.0) return {};
  if (value->is_number()) {
    *value = *factor * value->get<double>();
  } else if (value->is_array()) {
    for (auto& e : *value) {
      if (e.is_number()) e = *factor * e.get<double>();
    }
  }
  return {};
}

// A JSON pointer's reference token for `key` ("~" as "~0", "/" as "~1").
std::string PointerToken(const std::string& key) {
  std::string out;
  for (const char c : key) out += c == '~' ? std::string("~0") : c == '/' ? std::string("~1") : std::string(1, c);
  return out;
}

// The problems of a quantity object's keys: only "value" and "unit" ({"value": 500, "unti": "g"} would otherwise be
// read as 500 in the SI unit). Each is "<ptr>/<key>: …" with the closest key.
std::vector<std::string> QuantityKeyProblems(const ParamSpec& spec, const nlohmann::json& quantity,
                                             const std::string& ptr) {
  std::vector<std::string> problems;
  for (const auto& [key, unused] : quantity.items()) {
    if (key == "value" || key == "unit") continue;
    const auto close = ClosestNames(key, {"value", "unit"}, 1);
    problems.push_back(fmt::format(
        "{}/{}: a quantity takes only \"value\" and \"unit\", not '{}'{}; write {{\"value\": …, \"unit\": \"{}\"}}",
        ptr, PointerToken(Excerpt(key)), Excerpt(key),
        close.empty() ? "" : fmt::format(" (did you mean \"{}\"?)", close.front()), spec.unit.empty() ? "1" : spec.unit));
  }
  return problems;
}

// The value scaled by `factor` (a number, or each number of an array).
nlohmann::json Scaled(nlohmann::json value, double factor) {
  if (value.is_number()) return factor * value.get<double>();
  if (value.is_array()) {
    for (auto& e : value) {
      if (e.is_number()) e = factor * e.get<double>();
    }
  }
  return value;
}

bool IsNumberOrNumbers(const nlohmann::json& value) {
  if (value.is_number()) return true;
  if (!value.is_array()) return false;
  for (const auto& e : value) {
    if (!e.is_number()) return false;
  }
  return true;
}

// The factor from the unit of quantity `slot` to `spec`'s SI unit; nullopt when `slot` is no quantity with a unit,
// or the unit does not convert.
std::optional<double> QuantityFactor(const ParamSpec& spec, const nlohmann::json& slot) {
  if (!slot.is_object() || !slot.contains("value") || !slot.contains("unit") || !slot["unit"].is_string()) {
    return std::nullopt;
  }
  if (spec.unit.empty()) return std::nullopt;
  return UnitFactorToSpec(slot["unit"].get<std::string>(), spec);
}

}  // namespace

nlohmann::json ParameterValueInSi(const ParamSpec& spec, const nlohmann::json& slot) {
  if (!slot.is_object() || !slot.contains("value")) return slot;
  const auto factor = QuantityFactor(spec, slot);
  return factor && *factor != 1.0 ? Scaled(slot["value"], *factor) : slot["value"];
}

nlohmann::json ParameterSlotOnAxis(const ParamSpec& spec, const nlohmann::json& slot) {
  if (spec.linear_unit.empty() || !slot.is_object() || !slot.contains("value") || !slot.contains("unit") ||
      !slot["unit"].is_string()) {
    return slot;
  }
  const std::string unit = slot["unit"].get<std::string>();
  if (UnitFactor(unit, spec.unit) || !SameUnit(unit, spec.linear_unit)) return slot;
  nlohmann::json out = slot;
  out["unit"] = spec.unit;
  return out;
}

nlohmann::json ReplacedParameterSlot(const ParamSpec* spec, const nlohmann::json& slot, const nlohmann::json& value) {
  if (value.is_object() || !IsNumberOrNumbers(value)) return value;
  if (!slot.is_object() || !slot.contains("value")) return value;
  const auto factor = spec ? QuantityFactor(*spec, slot) : std::nullopt;
  if (!factor || !(*factor > 0.0)) return value;  // the SI number alone: its meaning needs no unit
  nlohmann::json out = slot;
  out["value"] = *factor == 1.0 ? value : Scaled(value, 1.0 / *factor);
  return out;
}

std::map<std::string, nlohmann::json> ValidateParameters(const std::vector<ParamSpec>& specs,
                                                         const nlohmann::json& raw,
                                                         const std::string& json_pointer,
                                                         std::vector<std::string>* errors) {
  std::map<std::string, nlohmann::json> out;
  const nlohmann::json empty = nlohmann::json::object();
  const nlohmann::json& given = raw.is_null() ? empty : raw;
  if (!given.is_object()) {
    errors->push_back(fmt::format("{}: parameters must be an object {{\"name\": value}}", json_pointer));
    return out;
  }
  for (const auto& [key, value] : given.items()) {
    bool known = false;
    for (const auto& s : specs) known = known || s.name == key;
    if (!known) {
      std::string names;
      for (const auto& s : specs) names += (names.empty() ? "" : ", ") + s.name;
      errors->push_back(fmt::format("{}/{}: unknown parameter '{}'; this block takes: {}", json_pointer, key, key,
                                    names.empty() ? "(none)" : names));
    }
  }
  for (const auto& spec : specs) {
    const std::string ptr = json_pointer + "/" + spec.name;
    nlohmann::json value;
    if (given.contains(spec.name)) {
      value = given.at(spec.name);
      if (value.is_object()) {
        if (const auto key_problems = QuantityKeyProblems(spec, value, ptr); !key_problems.empty()) {
          errors->insert(errors->end(), key_problems.begin(), key_problems.end());
          continue;
        }
        if (!value.contains("value")) {
          errors->push_back(fmt::format("{}: write a parameter as a value or as {{\"value\": …, \"unit\": \"{}\"}}",
                                        ptr, spec.unit));
          continue;
        }
        nlohmann::json written = value.at("value");
        if (value.contains("unit")) {
          if (auto msg = ConvertToDeclaredUnit(spec, value.at("unit"), &written); !msg.empty()) {
            errors->push_back(fmt::format("{}: {}", ptr, msg));
            continue;
          }
        }
        value = std::move(written);
      }
    } else if (spec.default_value) {
      value = *spec.default_value;
    } else {
      errors->push_back(fmt::format("{}: missing required parameter '{}' [{}] ({})", ptr, spec.name, spec.unit,
                                    spec.description));
      continue;
    }
    if (auto msg = CheckValue(spec, value); !msg.empty()) {
      errors->push_back(fmt::format("{}: {}", ptr, msg));
      continue;
    }
    out[spec.name] = value;
  }
  return out;
}

}  // namespace mb

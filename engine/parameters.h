#pragma once
// Typed block parameters with units and defaults, read from a diagram's JSON and overridable from the
// command line (`--set block.param=value`).

#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "engine/units.h"

namespace mb {

enum class ParamType { kNumber, kInteger, kBool, kString, kVector };

/// "number", "integer", "bool", "string" or "vector".
const char* ToString(ParamType type);

/// Declaration of one block parameter: name, type, SI unit ("" for dimensionless), default value (absent:
/// the parameter is required), and a one-line description for the block reference.
struct ParamSpec {
  std::string name;
  ParamType type = ParamType::kNumber;
  std::string unit;  ///< SI unit; "" = dimensionless or free (a value's written unit is then not checked)
  std::optional<nlohmann::json> default_value;
  std::string description;
  /// Optional closed bounds for numbers/integers/vector entries (checked on load).
  std::optional<double> min;
  std::optional<double> max;
  /// For string parameters with a fixed set of values: the allowed values (the JSON Schema's "enum", for
  /// editors). The block checks the value itself (with its own message); empty = any string.
  std::vector<std::string> choices;
  /// A string naming a file, relative to the diagram's folder (from_file.file, gpr.model): a diagram written to
  /// another folder gets it rewritten (DiagramDocument::RelocateFiles).
  bool file = false;
  /// Set by OnAxis when `unit` is the analogue on a diagram's axis of the linear SI unit declared (N·m·s/rad for
  /// N·s/m): that linear unit, still taken for a value with factor 1 (as a linear port takes a rotary signal). Empty:
  /// `unit` is the declared one.
  std::string linear_unit;
};

/// `spec` on a diagram's axis (engine/units.h MotionAxis): its unit the axis's analogue of the declared linear one
/// (AxisUnit: N·s/m → N·m·s/rad, N → N·m, kg → kg·m² on a rotary axis in rad and N·m), the declared one kept in
/// `linear_unit`; unchanged on the linear axis or for a unit with none of N, m, kg. The value keeps its meaning (a
/// number is in `unit`, which is what the block computes with). Throws nothing.
ParamSpec OnAxis(ParamSpec spec, const MotionAxis& axis);
std::vector<ParamSpec> OnAxis(std::vector<ParamSpec> specs, const MotionAxis& axis);

/// The axis of a diagram (a JSON object with "connectors", as in a diagram file): AxisOfConnectors over its input
/// connectors, then its output connectors. The linear axis (m, N) when it has none of motion units. Throws nothing.
MotionAxis DiagramAxis(const nlohmann::json& diagram);

/// Builder helpers for readable block specs: Required("mass", "kg", "moving mass").
ParamSpec Required(std::string name, std::string unit, std::string description,
                   ParamType type = ParamType::kNumber);
ParamSpec Optional(std::string name, nlohmann::json default_value, std::string unit, std::string description,
                   ParamType type = ParamType::kNumber);
/// Same as Optional with bounds [min, max] (use ±infinity for one-sided).
ParamSpec Bounded(std::string name, nlohmann::json default_value, std::string unit, std::string description,
                  double min, double max, ParamType type = ParamType::kNumber);

/// A required string parameter naming a file relative to the diagram's folder (ParamSpec::file).
ParamSpec FileName(std::string name, std::string description);

/// A string parameter taking one of `choices` (default first or given): Choice("method", "tustin", "…",
/// {"backward_euler", "tustin"}).
ParamSpec Choice(std::string name, std::string default_value, std::string description,
                 std::vector<std::string> choices);

/// The validated parameter values of one block instance. Access by name; the type was checked on load, so a
/// wrong-type access is a programming error in the block and throws std::logic_error.
class Parameters {
 public:
  Parameters() = default;
  Parameters(std::string block_name, std::map<std::string, nlohmann::json> values);

  double Number(const std::string& name) const;
  int Integer(const std::string& name) const;
  bool Bool(const std::string& name) const;
  const std::string& String(const std::string& name) const;
  /// A vector parameter; a scalar given where a vector is expected becomes a 1-vector.
  Eigen::VectorXd Vector(const std::string& name) const;
  bool Has(const std::string& name) const { return values_.count(name) != 0; }
  const std::map<std::string, nlohmann::json>& values() const { return values_; }

 private:
  const nlohmann::json& Get(const std::string& name) const;
  std::string block_name_;
  std::map<std::string, nlohmann::json> values_;
};

/// Validates raw JSON parameter values against the specs: unknown (extra) names, missing required ones,
/// wrong types, unit mismatch (a value may be written as a quantity {"value": 94, "unit": "kg"}, converted from any
/// unit of the declared one's quantity: engine/units.h; for specs put OnAxis, a unit of the axis's quantity
/// ({"value": 0.5, "unit": "N*m*s/rad"} for a rotary friction's viscous coefficient) or the linear unit itself; a
/// quantity with another key, such as "unti", is refused with the closest key), bounds, NaN. Each problem is
/// appended to `errors` as "<pointer>: <message>" where pointer is `json_pointer` + "/<param>". Returns the values
/// with defaults filled in (and units stripped).
std::map<std::string, nlohmann::json> ValidateParameters(const std::vector<ParamSpec>& specs,
                                                         const nlohmann::json& raw,
                                                         const std::string& json_pointer,
                                                         std::vector<std::string>* errors);

/// The one meaning of a number (issue 30): a bare number (or array of numbers) given for a parameter is in the
/// parameter's SI unit (ParamSpec::unit), whatever unit the diagram wrote; a quantity {"value": v, "unit": "g"} is
/// in its own unit. The two functions below read and write a parameter's slot (its JSON as written in a diagram's
/// "parameters") by that rule; the loader (ValidateParameters) converts the same way.

/// The value of `slot` in `spec`'s SI unit: a quantity's value converted from its unit, a bare value as it is. A
/// quantity whose unit does not convert (unknown, or of another quantity) gives its value unconverted: loading the
/// diagram reports it. Throws nothing.
nlohmann::json ParameterValueInSi(const ParamSpec& spec, const nlohmann::json& slot);

/// The slot that holds `value` for a parameter now written as `slot` (`spec` null when the parameter's spec is not
/// known, as for a subsystem's inner overrides). A quantity object `value` replaces the slot as given. A number or
/// array of numbers is in SI: when `slot` is a quantity whose unit converts to `spec`'s, the value is written in that
/// unit (2 kg into {"value": 2000, "unit": "g"} stays in g: {"value": 2000, "unit": "g"}), so that the diagram keeps
/// the unit its author chose; otherwise the bare `value` replaces the slot. Throws nothing.
nlohmann::json ReplacedParameterSlot(const ParamSpec* spec, const nlohmann::json& slot, const nlohmann::json& value);

/// `slot` (a parameter's JSON as written in a diagram) for `spec` put OnAxis: a quantity in the linear unit the spec
/// stands for ({"value": 0.5, "unit": "N·s/m"} for a rotary friction's viscous coefficient) is written in the axis's
/// unit with the same value ({"value": 0.5, "unit": "N·m·s/rad"}), so that a diagram on a rotary axis reads in its own
/// units; any other slot as it is. Throws nothing.
nlohmann::json ParameterSlotOnAxis(const ParamSpec& spec, const nlohmann::json& slot);

}  // namespace mb

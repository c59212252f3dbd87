#include "engine/json_schema.h"

#include "engine/closest_names.h"

#include <algorithm>
#include <set>
#include <stdexcept>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <valijson/adapters/nlohmann_json_adapter.hpp>
#include <valijson/schema.hpp>
#include <valijson/schema_parser.hpp>
#include <valijson/validation_results.hpp>
#include <valijson/validator.hpp>

namespace mb {

using nlohmann::json;

std::string SchemaProblem::Text() const { return fmt::format("{}: {}", pointer.empty() ? "/" : pointer, message); }

std::vector<std::string> MergeProblems(std::vector<std::string> own, const std::vector<SchemaProblem>& schema,
                                       bool own_covers_descendants) {
  std::vector<std::string> own_pointers;
  for (const auto& p : own) own_pointers.push_back(p.substr(0, p.find(": ")));
  std::vector<std::string> out = std::move(own);
  for (const auto& sp : schema) {
    const std::string pointer = sp.pointer.empty() ? "/" : sp.pointer;
    const bool covered = std::any_of(own_pointers.begin(), own_pointers.end(), [&](const std::string& o) {
      return o == pointer || (own_covers_descendants && o != "/" && pointer.rfind(o + "/", 0) == 0);
    });
    if (!covered) out.push_back(sp.Text());
  }
  return out;
}

std::vector<std::string> PointerTokens(const std::string& pointer) {
  std::vector<std::string> tokens;
  for (auto p = json::json_pointer(pointer); !p.empty(); p = p.parent_pointer()) tokens.insert(tokens.begin(), p.back());
  return tokens;
}

namespace {

// ---- The schema nodes that apply at a place in the document (for the allowed keys and values) -----------

std::string PointerToken(const std::string& token) {
  std::string out;
  for (char c : token) out += c == '~' ? std::string("~0") : c == '/' ? std::string("~1") : std::string(1, c);
  return out;
}

/// Whether `instance` satisfies an "if" of the form the generators write: {"properties": {k: {"const": v}}}.
bool IfHolds(const json& condition, const json& instance) {
  if (!instance.is_object()) return false;
  const json properties = condition.value("properties", json::object());
  for (const auto& [key, sub] : properties.items()) {
    if (!instance.contains(key) || !sub.contains("const") || instance[key] != sub["const"]) return false;
  }
  return true;
}

/// `node` with its $ref resolved, plus the nodes its allOf, anyOf, oneOf and matching if/then add.
void Expand(const json& root, const json* node, const json& instance, std::vector<const json*>* out, int depth = 0) {
  if (!node->is_object() || depth > 16) return;
  if (node->contains("$ref") && (*node)["$ref"].is_string()) {
    const std::string ref = (*node)["$ref"];
    node = &root.at(json::json_pointer(ref.substr(1)));  // local references only: "#/…"
  }
  out->push_back(node);
  for (const char* key : {"allOf", "anyOf", "oneOf"}) {
    if (!node->contains(key) || !(*node)[key].is_array()) continue;
    for (const auto& sub : (*node)[key]) Expand(root, &sub, instance, out, depth + 1);  // pointers into the schema
  }
  if (node->contains("if") && node->contains("then") && IfHolds((*node)["if"], instance)) {
    Expand(root, &(*node)["then"], instance, out, depth + 1);
  }
}

/// The schema nodes that apply to the value at `pointer` (empty if the pointer leaves the schema).
std::vector<const json*> NodesAt(const json& root, const json& document, const json::json_pointer& pointer) {
  std::vector<const json*> nodes;
  Expand(root, &root, document, &nodes);
  const json* instance = &document;
  json::json_pointer walked;
  for (const std::string& token : PointerTokens(pointer.to_string())) {
    walked /= token;
    if (!document.contains(walked)) return {};
    const json& child = document.at(walked);
    std::vector<const json*> next;
    for (const json* n : nodes) {
      const json* sub = nullptr;
      if (instance->is_object() && n->contains("properties") && (*n)["properties"].contains(token)) {
        sub = &(*n)["properties"][token];
      } else if (instance->is_object() && n->contains("additionalProperties") &&
                 (*n)["additionalProperties"].is_object()) {
        sub = &(*n)["additionalProperties"];
      } else if (instance->is_array() && n->contains("items")) {
        sub = &(*n)["items"];
      }
      if (sub) Expand(root, sub, child, &next);
    }
    nodes = std::move(next);
    instance = &child;
  }
  return nodes;
}

/// The keys some node lists and none forbids (`"key": false`, e.g. sampleTime on a continuous block).
std::vector<std::string> AllowedKeys(const std::vector<const json*>& nodes) {
  std::set<std::string> keys, forbidden;
  for (const json* n : nodes) {
    const json properties = n->value("properties", json::object());
    for (const auto& [key, sub] : properties.items()) {
      (sub.is_boolean() && !sub.get<bool>() ? forbidden : keys).insert(key);
    }
  }
  std::vector<std::string> out;
  for (const auto& k : keys) {
    if (!forbidden.count(k)) out.push_back(k);
  }
  return out;
}

std::vector<json> AllowedValues(const std::vector<const json*>& nodes) {
  std::vector<json> values;
  for (const json* n : nodes) {
    if (n->contains("const")) values.push_back((*n)["const"]);
    for (const auto& v : n->value("enum", json::array())) values.push_back(v);
  }
  return values;
}

std::string TypeName(const json& v) {
  if (v.is_number_integer()) return "an integer";
  if (v.is_number()) return "a number";
  if (v.is_string()) return "a string";
  if (v.is_boolean()) return "true or false";
  if (v.is_array()) return "an array";
  if (v.is_object()) return "an object";
  return "null";
}

std::string AllowedTypes(const std::vector<const json*>& nodes) {
  std::set<std::string> types;
  for (const json* n : nodes) {
    if (!n->contains("type")) continue;
    const json& t = (*n)["type"];
    for (const auto& name : t.is_array() ? t : json::array({t})) types.insert(name.get<std::string>());
  }
  return types.empty() ? "another type" : fmt::format("{}", fmt::join(types, " or "));
}

std::string Abbreviated(const json& v) {
  std::string text = v.dump();
  return text.size() > 60 ? text.substr(0, 57) + "…" : text;
}

// ---- Wording valijson's errors -------------------------------------------------------------------------

bool StartsWith(const std::string& s, const char* prefix) { return s.rfind(prefix, 0) == 0; }

/// valijson's context ("<root>", "[key]", "[0]", …) as a JSON pointer.
std::string ContextPointer(const std::vector<std::string>& context) {
  std::string out;
  for (const auto& c : context) {
    if (c.size() >= 2 && c.front() == '[' && c.back() == ']') out += "/" + PointerToken(c.substr(1, c.size() - 2));
  }
  return out;
}

class ProblemWording {
 public:
  ProblemWording(const json& schema, const json& document) : schema_(schema), document_(document) {}

  void Add(const std::string& pointer, const std::string& description) {
    if (StartsWith(description, "Failed to validate") || StartsWith(description, "Cannot validate item")) return;
    const json::json_pointer ptr(pointer);
    if (!document_.contains(ptr)) return;
    const json& value = document_.at(ptr);
    const auto nodes = NodesAt(schema_, document_, ptr);
    if (StartsWith(description, "Object contains a property that could not be validated")) {
      return UnknownKeys(pointer, value, nodes);
    }
    if (StartsWith(description, "Value type not permitted")) {
      return Push({pointer, fmt::format("must be {}, got {}", AllowedTypes(nodes), TypeName(value)), true});
    }
    if (description == "Failed to match against any enum values." ||
        description == "Failed to match expected value set by 'const' constraint.") {
      return NotAllowedValue(pointer, value, nodes);
    }
    if (StartsWith(description, "Missing required property '")) {
      const std::string key = description.substr(27, description.size() - 29);
      return Push({pointer, fmt::format("the key '{}' is required here", key), false});
    }
    if (StartsWith(description, "Elements at indexes #")) {
      return Push({pointer, fmt::format("{}; list each entry once", description.substr(0, description.size() - 1)),
                   false});
    }
    Push({pointer, fmt::format("{} (value {})", description, Abbreviated(value)), false});
  }

  /// The problems, without type complaints about a value whose inside is also reported (an anyOf branch of
  /// another type failed, but a branch of the right type explains more precisely what is wrong).
  std::vector<SchemaProblem> Take() {
    std::vector<SchemaProblem> out;
    for (const auto& p : problems_) {
      const bool explained_below = p.wrong_type && std::any_of(problems_.begin(), problems_.end(), [&](const auto& q) {
                                     return StartsWith(q.pointer, (p.pointer + "/").c_str());
                                   });
      if (!explained_below) out.push_back(p);
    }
    return out;
  }

 private:
  void Push(SchemaProblem p) {
    for (const auto& q : problems_) {
      if (q.pointer == p.pointer && q.message == p.message) return;
    }
    problems_.push_back(std::move(p));
  }

  void UnknownKeys(const std::string& pointer, const json& value, const std::vector<const json*>& nodes) {
    const auto allowed = AllowedKeys(nodes);
    for (const auto& [key, v] : value.items()) {
      if (std::find(allowed.begin(), allowed.end(), key) != allowed.end()) continue;
      const auto close = ClosestNames(key, allowed, 1);
      Push({pointer + "/" + PointerToken(key),
            fmt::format("unknown key '{}'{}; the keys here are: {}", key,
                        close.empty() ? "" : fmt::format(" (did you mean '{}'?)", close.front()),
                        allowed.empty() ? "(none)" : fmt::format("{}", fmt::join(allowed, ", "))),
            false});
    }
  }

  void NotAllowedValue(const std::string& pointer, const json& value, const std::vector<const json*>& nodes) {
    const auto allowed = AllowedValues(nodes);
    std::vector<std::string> texts, names;
    for (const auto& v : allowed) {
      texts.push_back(v.dump());
      if (v.is_string()) names.push_back(v.get<std::string>());
    }
    const auto close = value.is_string() ? ClosestNames(value.get<std::string>(), names, 1) : std::vector<std::string>{};
    Push({pointer,
          fmt::format("{} is not allowed here{}; use {}", Abbreviated(value),
                      close.empty() ? "" : fmt::format(" (did you mean \"{}\"?)", close.front()),
                      texts.size() == 1 ? texts.front() : fmt::format("one of {}", fmt::join(texts, ", "))),
          false});
  }

  const json& schema_;
  const json& document_;
  std::vector<SchemaProblem> problems_;
};

}  // namespace

JsonSchemaValidator::JsonSchemaValidator(json schema)
    : schema_json_(std::move(schema)), schema_(std::make_unique<valijson::Schema>()) {
  try {
    valijson::SchemaParser parser(valijson::SchemaParser::kDraft7);
    valijson::adapters::NlohmannJsonAdapter adapter(schema_json_);
    parser.populateSchema(adapter, *schema_);
  } catch (const std::exception& e) {
    throw std::invalid_argument(fmt::format("the JSON Schema cannot be read: {}", e.what()));
  }
}

JsonSchemaValidator::~JsonSchemaValidator() = default;

std::vector<SchemaProblem> JsonSchemaValidator::Validate(const json& document) const {
  valijson::Validator validator;
  valijson::ValidationResults results;
  valijson::adapters::NlohmannJsonAdapter target(document);
  if (validator.validate(*schema_, target, &results)) return {};
  ProblemWording wording(schema_json_, document);
  valijson::ValidationResults::Error error;
  while (results.popError(error)) wording.Add(ContextPointer(error.context), error.description);
  return wording.Take();
}

}  // namespace mb

// Loading a diagram file (diagram_loader.h): the file read as JSON (size-limited, duplicate keys refused, comments
// allowed), --set overrides applied, then built (diagram_builder.cc) after its subsystems are expanded
// (subsystem_expansion.cc).
#include "engine/diagram_loader.h"

#include <sstream>

#include <fmt/format.h>

#include "engine/diagram_document.h"
#include "engine/file_access.h"
#include "engine/file_error.h"
#include "engine/input_file.h"
#include "engine/json_limits.h"
#include "engine/json_parsing.h"
#include "engine/parameters.h"
#include "engine/registry.h"
#include "engine/text_excerpt.h"

namespace mb {

namespace fs = std::filesystem;
using nlohmann::json;

DiagramError::DiagramError(const std::string& source, std::vector<std::string> problems)
    : std::runtime_error([&] {
        std::string msg = fmt::format("{}: {} problem{} in the diagram:", source, problems.size(),
                                      problems.size() == 1 ? "" : "s");
        for (const auto& p : problems) msg += "\n  " + p;
        return msg;
      }()),
      problems_(std::move(problems)) {}

ParameterOverride ParameterOverride::Parse(const std::string& text) {
  const auto eq = text.find('=');
  const auto dot = text.find('.');
  if (eq == std::string::npos || dot == std::string::npos || dot > eq || dot == 0 || dot + 1 == eq) {
    throw std::invalid_argument(
        fmt::format("'{}': write a parameter override as block.parameter=value, e.g. plant.payload_mass=21",
                    Excerpt(text)));
  }
  ParameterOverride o;
  // Block names may contain '/' (subsystems) but not '.', so the first '.' separates block and parameter.
  o.block = text.substr(0, dot);
  o.parameter = text.substr(dot + 1, eq - dot - 1);
  const std::string value = text.substr(eq + 1);
  o.value = json::parse(value, nullptr, /*allow_exceptions=*/false);
  if (o.value.is_discarded()) o.value = value;
  return o;
}

namespace {

// The spec of parameter `parameter` of block type `type`; null for an unknown type (a subsystem) or parameter.
const ParamSpec* FindParamSpec(const std::string& type, const std::string& parameter) {
  const BlockType* bt = BlockRegistry::Global().Find(type);
  if (bt == nullptr) return nullptr;
  for (const auto& spec : bt->parameters) {
    if (spec.name == parameter) return &spec;
  }
  return nullptr;
}

}  // namespace

void ApplyOverrides(json* diagram, const std::vector<ParameterOverride>& overrides, const std::string& source) {
  std::vector<std::string> problems;
  for (const auto& o : overrides) {
    if (DiagramDocument::IsSettingSection(o.block)) {  // solver.type=cvode, defaultExperiment.stopTime=2
      if (!diagram->contains(o.block) || !(*diagram)[o.block].is_object()) (*diagram)[o.block] = json::object();
      (*diagram)[o.block][o.parameter] = o.value;
      continue;
    }
    bool found = false;
    const MotionAxis axis = DiagramAxis(*diagram);
    if (diagram->contains("elements") && (*diagram)["elements"].is_array()) {
      for (auto& element : (*diagram)["elements"]) {
        if (element.value("name", "") != o.block) continue;
        found = true;
        auto& params = element["parameters"];
        if (params.is_null()) params = json::object();
        auto& slot = params[o.parameter];
        const ParamSpec* declared = FindParamSpec(element.value("type", ""), o.parameter);
        const std::optional<ParamSpec> spec =
            declared != nullptr ? std::optional<ParamSpec>(OnAxis(*declared, axis)) : std::nullopt;
        slot = ReplacedParameterSlot(spec ? &*spec : nullptr, slot, o.value);
      }
    }
    if (!found) {
      std::string names;
      for (const auto& element : diagram->value("elements", json::array())) {
        names += (names.empty() ? "" : ", ") + element.value("name", "?");
      }
      problems.push_back(fmt::format("--set {}.{}: no element named '{}'; the diagram has: {}", o.block, o.parameter,
                                     o.block, names));
    }
  }
  if (!problems.empty()) throw DiagramError(source, problems);
}

namespace {

// Counts the entries of the top-level "elements" array while the text is read (a SAX pass that builds nothing) and
// stops once there are more than kMaxDiagramElements: a diagram of a million blocks is refused after reading a fifth
// of it, not after parsing, checking and building all of it (issue 41: more than 30 s without a word).
class ElementCounter final : public nlohmann::json_sax<json> {
 public:
  bool null() override { return Value(); }
  bool boolean(bool) override { return Value(); }
  bool number_integer(number_integer_t) override { return Value(); }
  bool number_unsigned(number_unsigned_t) override { return Value(); }
  bool number_float(number_float_t, const string_t&) override { return Value(); }
  bool string(string_t&) override { return Value(); }
  bool binary(binary_t&) override { return Value(); }
  bool start_object(std::size_t) override { return Open(); }
  bool key(string_t& key) override {
    in_elements_key_ = depth_ == 1 && key == "elements";
    return true;
  }
  bool end_object() override { return Close(); }
  bool start_array(std::size_t) override {
    if (depth_ == 1 && in_elements_key_) in_elements_ = true;
    return Open();
  }
  bool end_array() override {
    if (depth_ == 2) in_elements_ = false;
    return Close();
  }
  bool parse_error(std::size_t, const std::string&, const nlohmann::detail::exception&) override {
    return false;  // the real parse reports it
  }
  std::size_t count() const { return count_; }

 private:
  bool Value() {
    if (in_elements_ && depth_ == 2) ++count_;
    return count_ <= kMaxDiagramElements;
  }
  bool Open() {
    const bool go_on = Value();
    return ++depth_ <= kMaxJsonDepth && go_on;  // too deep: the depth check reports it
  }
  bool Close() {
    --depth_;
    return true;
  }
  int depth_ = 0;
  bool in_elements_key_ = false;
  bool in_elements_ = false;
  std::size_t count_ = 0;
};

void RequireAtMostMaxElements(const std::string& text, const fs::path& path) {
  if (text.size() < kMaxDiagramElements * 16) return;  // an element takes more than 16 bytes: nothing to count
  ElementCounter counter;
  json::sax_parse(text, &counter, json::input_format_t::json, /*strict=*/false);
  if (counter.count() > kMaxDiagramElements) {
    throw DiagramError(path.string(), {TooManyElementsProblem(counter.count(), /*or_more=*/true, false)});
  }
}

}  // namespace

// Also refuses (DiagramError naming the file) a file that holds no JSON object: null, an array, a number.
json ReadDiagramJson(const fs::path& path) {
  CheckInputFile(path, "diagram file");  // a regular file within the size limit: /dev/zero or a FIFO is never opened
  if (!fs::exists(path)) {
    throw FileOpenError(fmt::format("{}: cannot open the diagram file (does it exist?)", path.string()));
  }
  const std::string text = ReadInputFile(path, "diagram file");
  RequireAtMostMaxElements(text, path);
  std::istringstream in(text);
  try {
    // Plain JSON, as the schema, editors and Python's json module read it: no comments (issue 41).
    json j = ParseJsonRejectingDuplicateKeys(in, path.string(), /*ignore_comments=*/false);
    if (!j.is_object()) {  // named here, where the file is known (the documents built from it say only "diagram")
      throw DiagramError(path.string(), {fmt::format("/: a diagram is a JSON object {{…}}, but this file holds {}",
                                                     j.is_null() ? "null" : j.is_array() ? "an array" : fmt::format("a {}", j.type_name()))});
    }
    return j;
  } catch (const json::parse_error& e) {
    throw std::runtime_error(
        fmt::format("{}: not valid JSON: {}{}", path.string(), JsonErrorText(e), JsonCommentHint(text, e.byte)));
  } catch (const DuplicateKeyError& e) {
    throw DiagramError(path.string(), e.problems());
  }
}

Diagram LoadDiagram(const fs::path& path, const std::vector<ParameterOverride>& overrides) {
  json j = ReadDiagramJson(path);
  ApplyOverrides(&j, overrides, path.string());
  Diagram d = BuildDiagram(j, path.parent_path(), path.string());
  return d;
}

}  // namespace mb

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
    if (diagram->contains("elements") && (*diagram)["elements"].is_array()) {
      for (auto& element : (*diagram)["elements"]) {
        if (element.value("name", "") != o.block) continue;
        found = true;
        auto& params = element["parameters"];
        if (params.is_null()) params = json::object();
        auto& slot = params[o.parameter];
        slot = ReplacedParameterSlot(FindParamSpec(element.value("type", ""), o.parameter), slot, o.value);
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

// Also refuses (DiagramError naming the file) a file that holds no JSON object: null, an array, a number.
json ReadDiagramJson(const fs::path& path) {
  CheckInputFile(path, "diagram file");  // a regular file within the size limit: /dev/zero or a FIFO is never opened
  if (!fs::exists(path)) {
    throw FileOpenError(fmt::format("{}: cannot open the diagram file (does it exist?)", path.string()));
  }
  std::istringstream in(ReadInputFile(path, "diagram file"));
  try {
    json j = ParseJsonRejectingDuplicateKeys(in, path.string(), /*ignore_comments=*/true);
    if (!j.is_object()) {  // named here, where the file is known (the documents built from it say only "diagram")
      throw DiagramError(path.string(), {fmt::format("/: a diagram is a JSON object {{…}}, but this file holds {}",
                                                     j.is_null() ? "null" : j.is_array() ? "an array" : fmt::format("a {}", j.type_name()))});
    }
    return j;
  } catch (const json::parse_error& e) {
    throw std::runtime_error(fmt::format("{}: not valid JSON: {}", path.string(), JsonErrorText(e)));
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

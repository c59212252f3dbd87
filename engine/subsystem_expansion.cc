// Subsystem expansion (subsystem_expansion.h): the inner diagrams spliced into the outer one, with where each part
// was written.
#include "engine/subsystem_expansion.h"

#include <optional>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "engine/diagram_loader.h"
#include "engine/diagram_schema.h"
#include "engine/file_access.h"
#include "engine/text_excerpt.h"

namespace mb {

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

/// Where a part of a diagram was written: "" for the file being loaded, "<subsystem file>: " for a subsystem
/// file, plus the JSON pointer of the diagram inside that file ("" or ".../diagram" for an inline subsystem).
struct Place {
  std::string file;     ///< "" or "<file>: "
  std::string pointer;  ///< JSON pointer of the diagram in that file
  /// The subsystem files being expanded, outermost first (canonical paths): a file that appears again is a cycle.
  std::vector<std::string> files;
  std::string At(const std::string& section, std::size_t index) const {
    return fmt::format("{}{}/{}/{}", file, pointer, section, index);
  }
};

/// Deepest nesting of subsystems (ExpandSubsystemElement refuses a deeper one, naming where).
constexpr int kMaxSubsystemDepth = 16;

/// A diagram with its subsystems expanded, and for each element, connection and logged signal where the user
/// wrote it (so that problems found after expansion point into the right file).
using Expansion = SubsystemExpansion;

Expansion ExpandSubsystemsImpl(const json& diagram, const fs::path& base, const std::string& source,
                               const Place& place, int depth, std::vector<std::string>* problems);

/// The expanded inner diagram of subsystem element `element` (at `ptr` in `place`), or nothing after a problem.
std::optional<Expansion> ExpandSubsystemElement(const json& element, const fs::path& base, const std::string& source,
                                                const Place& place, const std::string& ptr, int depth,
                                                std::vector<std::string>* problems) {
  json inner;
  fs::path inner_base = base;
  Place inner_place{place.file, ptr + "/diagram", place.files};
  const std::string where = place.file + ptr;
  if (depth >= kMaxSubsystemDepth) {
    problems->push_back(fmt::format("{}: subsystems nest deeper than {} levels; flatten the nesting (a diagram that "
                                    "includes itself is named as a cycle)",
                                    where, kMaxSubsystemDepth));
    return std::nullopt;
  }
  if (element.contains("diagram") && element["diagram"].is_string()) {
    fs::path file;
    try {
      file = ResolveDiagramFile(element["diagram"].get<std::string>(), base);
    } catch (const std::exception& e) {
      problems->push_back(fmt::format("{}/diagram: {}", where, e.what()));
      return std::nullopt;
    }
    std::error_code error;
    const std::string key = fs::weakly_canonical(file, error).string();
    const auto again = std::find(place.files.begin(), place.files.end(), key);
    if (again != place.files.end()) {
      std::vector<std::string> cycle(again, place.files.end());
      cycle.push_back(key);
      problems->push_back(fmt::format("{}/diagram: the subsystem files include each other in a cycle: {}; a "
                                      "subsystem cannot contain itself: break the cycle",
                                      where, Excerpt(fmt::format("{}", fmt::join(cycle, " → ")))));
      return std::nullopt;
    }
    try {
      inner = ReadDiagramJson(file);
    } catch (const std::exception& e) {
      problems->push_back(fmt::format("{}/diagram: {}", where, e.what()));
      return std::nullopt;
    }
    inner_base = file.parent_path();
    inner_place = Place{file.string() + ": ", "", place.files};
    inner_place.files.push_back(key);
    // The subsystem file as the user wrote it (an inline diagram is checked with its parent).
    const auto schema_problems = DiagramSchemaProblems(inner);
    for (const auto& p : schema_problems) problems->push_back(inner_place.file + p.Text());
    if (!schema_problems.empty()) return std::nullopt;
  } else if (element.contains("diagram") && element["diagram"].is_object()) {
    inner = element["diagram"];
  } else {
    problems->push_back(fmt::format("{}: a subsystem needs \"diagram\": a file name or an inline diagram", where));
    return std::nullopt;
  }
  if (element.contains("parameters")) {
    // Parameters of a subsystem element are overrides "inner_block.param": value.
    std::vector<ParameterOverride> overrides;
    for (const auto& [key, value] : element["parameters"].items()) {
      try {
        auto o = ParameterOverride::Parse(key + "=0");
        o.value = value;
        overrides.push_back(o);
      } catch (const std::exception& e) {
        problems->push_back(fmt::format("{}/parameters/{}: {}", where, key, e.what()));
      }
    }
    try {
      ApplyOverrides(&inner, overrides, source + ptr);
    } catch (const DiagramError& e) {
      for (const auto& p : e.problems()) problems->push_back(p);
    }
  }
  return ExpandSubsystemsImpl(inner, inner_base, source, inner_place, depth + 1, problems);
}

/// A connection with the place it was written.
struct PlacedConnection {
  json connection;
  std::string origin;
};

/// Splices the subsystem `name` (expanded as `inner`) into `connections` of its parent: a connection to one of
/// its ports is rewired to the inner element behind the port; inner element-to-element connections are
/// appended to `inner_connections`.
void SpliceSubsystem(const std::string& name, const Expansion& inner, std::vector<PlacedConnection>* connections,
                     std::vector<PlacedConnection>* inner_connections, std::vector<std::string>* problems) {
  const std::string prefix = name + "/";
  std::vector<json> from_port;  // inner connector (input) → inner element
  std::vector<json> to_port;    // inner element → inner connector (output)
  const json inner_list = inner.diagram.value("connections", json::array());
  for (std::size_t k = 0; k < inner_list.size(); ++k) {
    const json& c = inner_list[k];
    const std::string se = c.value("startElement", "");
    const std::string ee = c.value("endElement", "");
    json p = c;
    if (!se.empty()) p["startElement"] = prefix + se;
    if (!ee.empty()) p["endElement"] = prefix + ee;
    if (se.empty()) {
      from_port.push_back(p);
    } else if (ee.empty()) {
      to_port.push_back(p);
    } else {
      inner_connections->push_back({p, inner.origins.at("connections").at(k)});
    }
  }
  std::vector<PlacedConnection> rewired;
  for (const auto& [c, origin] : *connections) {
    bool consumed = false;
    if (c.value("endElement", "") == name) {
      for (const json& f : from_port) {
        if (f.value("startConnector", "") != c.value("endConnector", "")) continue;
        json n = c;
        n["endElement"] = f["endElement"];
        n["endConnector"] = f.value("endConnector", "");
        rewired.push_back({n, origin});
        consumed = true;
      }
      if (!consumed) {
        problems->push_back(fmt::format("{}: connection into subsystem '{}' port '{}': the subsystem has no input "
                                        "connector of that name (or it is connected to nothing inside)",
                                        origin, name, c.value("endConnector", "")));
        consumed = true;
      }
    }
    if (c.value("startElement", "") == name) {
      bool matched = false;
      for (const json& t : to_port) {
        if (t.value("endConnector", "") != c.value("startConnector", "")) continue;
        json n = c;
        n["startElement"] = t["startElement"];
        n["startConnector"] = t.value("startConnector", "");
        rewired.push_back({n, origin});
        matched = true;
      }
      if (!matched) {
        problems->push_back(fmt::format("{}: connection from subsystem '{}' port '{}': the subsystem has no output "
                                        "connector of that name",
                                        origin, name, c.value("startConnector", "")));
      }
      consumed = true;
    }
    if (!consumed) rewired.push_back({c, origin});
  }
  *connections = std::move(rewired);
}

Expansion ExpandSubsystemsImpl(const json& diagram, const fs::path& base, const std::string& source,
                               const Place& place, int depth, std::vector<std::string>* problems) {
  Expansion out{diagram, {}};
  auto placed = [&](const char* section) {
    std::vector<std::string> origins;
    if (diagram.contains(section) && diagram[section].is_array()) {
      for (std::size_t i = 0; i < diagram[section].size(); ++i) origins.push_back(place.At(section, i));
    }
    return origins;
  };
  out.origins["connections"] = placed("connections");
  out.origins["log"] = placed("log");
  if (!diagram.contains("elements") || !diagram["elements"].is_array()) return out;
  out.diagram["elements"] = json::array();
  std::vector<PlacedConnection> connections;  // the parent's, rewired below
  for (const auto& c : diagram.value("connections", json::array())) {
    connections.push_back({c, out.origins["connections"][connections.size()]});
  }
  std::vector<PlacedConnection> inner_connections;  // element-to-element inside subsystems
  auto& element_origins = out.origins["elements"];
  for (std::size_t i = 0; i < diagram["elements"].size(); ++i) {
    const json& element = diagram["elements"][i];
    if (element.value("type", "") != kSubsystemType) {
      out.diagram["elements"].push_back(element);
      element_origins.push_back(place.At("elements", i));
      continue;
    }
    const std::string ptr = fmt::format("{}/elements/{}", place.pointer, i);
    const std::string name = element.value("name", "");
    const auto inner = ExpandSubsystemElement(element, base, source, place, ptr, depth, problems);
    if (!inner) continue;
    const std::string prefix = name + "/";
    const json inner_elements = inner->diagram.value("elements", json::array());
    for (std::size_t k = 0; k < inner_elements.size(); ++k) {
      json e = inner_elements[k];
      e["name"] = prefix + e.value("name", "");
      out.diagram["elements"].push_back(e);
      element_origins.push_back(inner->origins.at("elements").at(k));
    }
    SpliceSubsystem(name, *inner, &connections, &inner_connections, problems);
    // Signals inside may be logged as "<subsystem>/<element>.<port>".
    const json inner_log = inner->diagram.value("log", json::array());
    for (std::size_t k = 0; k < inner_log.size(); ++k) {
      if (!inner_log[k].is_string()) continue;
      out.diagram["log"].push_back(prefix + inner_log[k].get<std::string>());
      out.origins["log"].push_back(inner->origins.at("log").at(k));
    }
  }
  out.diagram["connections"] = json::array();
  out.origins["connections"].clear();
  connections.insert(connections.end(), inner_connections.begin(), inner_connections.end());
  for (const auto& [c, origin] : connections) {
    out.diagram["connections"].push_back(c);
    out.origins["connections"].push_back(origin);
  }
  return out;
}

}  // namespace

SubsystemExpansion ExpandSubsystemsWithOrigins(const json& diagram, const fs::path& base_directory,
                                               const std::string& source, std::vector<std::string>* problems) {
  return ExpandSubsystemsImpl(diagram, base_directory, source, Place{}, 0, problems);
}

json ExpandSubsystems(const json& diagram, const fs::path& base_directory, const std::string& source) {
  std::vector<std::string> problems;
  SubsystemExpansion out = ExpandSubsystemsWithOrigins(diagram, base_directory, source, &problems);
  if (!problems.empty()) throw DiagramError(source, problems);
  return out.diagram;
}

}  // namespace mb

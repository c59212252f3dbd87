#include "hw/hil_diagram.h"

#include <stdexcept>

#include <fmt/format.h>

namespace mb {

SubsystemReplacement SubsystemReplacement::Parse(const std::string& text) {
  const auto eq = text.find('=');
  if (eq == std::string::npos || eq == 0 || eq + 1 == text.size()) {
    throw std::invalid_argument(fmt::format("--replace '{}': write ELEMENT=FILE, e.g. plant=diagrams/hil/subsystems/"
                                            "hil_io.json",
                                            text));
  }
  return {text.substr(0, eq), std::filesystem::absolute(text.substr(eq + 1))};
}

nlohmann::json ReplaceSubsystem(const nlohmann::json& diagram, const SubsystemReplacement& replacement,
                                const std::string& source, std::vector<std::string>* dropped) {
  nlohmann::json out = diagram;
  if (!out.contains("elements") || !out["elements"].is_array()) {
    throw std::invalid_argument(fmt::format("{}: no \"elements\" array, nothing to replace", source));
  }
  bool found = false;
  std::string names;
  for (auto& element : out["elements"]) {
    const std::string name = element.value("name", "");
    names += (names.empty() ? "" : ", ") + name;
    if (name != replacement.element) continue;
    if (element.value("type", "") != "subsystem") {
      throw std::invalid_argument(fmt::format(
          "{}: element '{}' is a '{}', not a subsystem; put the plant in its own file and use it as "
          "{{\"name\": \"{}\", \"type\": \"subsystem\", \"diagram\": \"plant.json\"}} so that it can be swapped",
          source, name, element.value("type", "?"), name));
    }
    element["diagram"] = replacement.file.string();
    if (element.contains("parameters")) {
      for (const auto& [key, value] : element["parameters"].items()) {
        dropped->push_back(fmt::format("parameter override {}.{} = {}", name, key, value.dump()));
      }
      element.erase("parameters");
    }
    found = true;
  }
  if (!found) {
    throw std::invalid_argument(fmt::format("{}: --replace {}=…: no element named '{}'; the diagram has: {}", source,
                                            replacement.element, replacement.element, names));
  }
  if (out.contains("log") && out["log"].is_array()) {
    nlohmann::json kept = nlohmann::json::array();
    const std::string prefix = replacement.element + "/";
    for (const auto& entry : out["log"]) {
      if (entry.is_string() && entry.get<std::string>().rfind(prefix, 0) == 0) {
        dropped->push_back(fmt::format("logged signal {}", entry.get<std::string>()));
      } else {
        kept.push_back(entry);
      }
    }
    out["log"] = kept;
  }
  return out;
}

}  // namespace mb

#include "hw/hil_diagram.h"

#include <stdexcept>

#include <fmt/format.h>

#include "engine/diagram_document.h"

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
  DiagramDocument document(diagram, {}, source);
  if (!document.Has(replacement.element)) {
    std::string names;
    for (const auto& name : document.ElementNames()) names += (names.empty() ? "" : ", ") + name;
    throw std::invalid_argument(fmt::format("{}: --replace {}=…: no element named '{}'; the diagram has: {}", source,
                                            replacement.element, replacement.element, names));
  }
  for (const auto& o : document.SetSubsystemDiagram(replacement.element, replacement.file)) {
    dropped->push_back("parameter override " + o);
  }
  std::vector<std::string> kept;
  const std::string prefix = replacement.element + "/";
  for (const auto& signal : document.LoggedSignals()) {
    if (signal.rfind(prefix, 0) == 0) {
      dropped->push_back(fmt::format("logged signal {}", signal));
    } else {
      kept.push_back(signal);
    }
  }
  if (document.json().contains("log")) document.SetLoggedSignals(kept);
  return document.json();
}

}  // namespace mb

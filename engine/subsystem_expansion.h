#pragma once
// Subsystem expansion, inside the loader (diagram_loader.h: ExpandSubsystems is the public call): every element of
// type "subsystem" replaced by its inner diagram (inline or a file beside the diagram, --set overrides applied), its
// elements renamed "<subsystem>/<element>", its connectors spliced into the outer connections; nested subsystems
// expanded in turn (16 levels at most, a file that includes itself refused). Where each element, connection and
// logged signal was written is kept, so that the builder's problems point into the right file.

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace mb {

/// A diagram with its subsystems expanded, and for each element, connection and logged signal where the user wrote
/// it: "elements", "connections", "log" → one place per entry ("" for the file being loaded, "<subsystem file>: "
/// plus the JSON pointer of the inner diagram).
struct SubsystemExpansion {
  nlohmann::json diagram;
  std::map<std::string, std::vector<std::string>> origins;
};

/// Expands `diagram`'s subsystems (subsystem files read relative to `base_directory`; `source` names the diagram in
/// messages). Problems (a missing file, a cycle, too deep a nesting, an unknown connector) are appended to `problems`
/// with where they are, and the expansion goes on where it can: the caller throws DiagramError with all of them.
/// @throws as ReadDiagramJson for a subsystem file that cannot be read.
SubsystemExpansion ExpandSubsystemsWithOrigins(const nlohmann::json& diagram,
                                               const std::filesystem::path& base_directory, const std::string& source,
                                               std::vector<std::string>* problems);

}  // namespace mb

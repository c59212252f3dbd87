#pragma once
// Preparing a diagram for hardware in the loop: the plant subsystem is swapped for an I/O subsystem (the
// HIL blocks, e.g. diagrams/hil/subsystems/hil_io.json) and the rest of the diagram is left unchanged.

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace mb {

/// A `--replace element=FILE` request.
struct SubsystemReplacement {
  std::string element;          ///< name of a subsystem element of the diagram, e.g. "plant"
  std::filesystem::path file;   ///< the diagram file that takes its place
  /// Parses "element=FILE"; FILE is made absolute against the current directory.
  /// @throws std::invalid_argument on a malformed text.
  static SubsystemReplacement Parse(const std::string& text);
};

/// Returns `diagram` with the subsystem element `replacement.element` now reading `replacement.file`. Its
/// "parameters" (overrides of the old inner blocks) are dropped, and so are entries of the top-level "log"
/// that name the old inner blocks ("<element>/…"); each dropped item is appended to `dropped`.
/// Connections to the subsystem's ports stay: the new file must have input and output connectors of the same
/// names (the loader reports any that are missing).
/// @throws std::invalid_argument if there is no such element or it is not a subsystem (with the fix).
nlohmann::json ReplaceSubsystem(const nlohmann::json& diagram, const SubsystemReplacement& replacement,
                                const std::string& source, std::vector<std::string>* dropped);

}  // namespace mb

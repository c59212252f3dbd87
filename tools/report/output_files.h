#pragma once
// Writing what commands produce: logged signals as CSV, JSON summaries, diagrams (the progress line: progress.h).

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/simulator.h"
#include "tools/report/progress.h"

namespace mb {

/// Writes the log as CSV: time_s, then one column per logged signal. @throws std::runtime_error.
void WriteSignalLog(const SignalLog& log, const std::filesystem::path& path);

/// Writes pretty JSON (2-space indent). @throws std::runtime_error if the file cannot be written.
void WriteJsonFile(const nlohmann::json& j, const std::filesystem::path& path);

/// Writes `diagram` — read from (or amended from) a diagram in `diagram_folder` — to `path`, its file names
/// rewritten to name the same files from path's folder (DiagramDocument::RelocateFiles), so that the copy loads
/// wherever it is written. Returns the names that lie outside path's folder ("element.parameter: name"): the copy
/// reads those only with --allow-path. @throws std::runtime_error if the file cannot be written.
std::vector<std::string> WriteDiagramFile(const nlohmann::json& diagram, const std::filesystem::path& diagram_folder,
                                          const std::filesystem::path& path);

}  // namespace mb

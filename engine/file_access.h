#pragma once
// Which files a diagram may read. Users open other people's diagrams, so a file parameter (`from_file.file`,
// `gpr.model`, a subsystem's `diagram`) is resolved against the diagram's own folder and must stay inside
// it, be a regular file, and exist; folders the user trusts besides are allowed explicitly
// (`motionblocks … --allow-path DIR`). STYLE.md, "Outside processes and files".

#include <filesystem>
#include <string>
#include <vector>

namespace mb {

/// Allows file parameters of every diagram loaded afterwards to name files under `directory` (made absolute
/// and canonical now) although it lies outside the diagram's folder. Process-wide, like the block registry:
/// call it while setting up (command line, scripts), not while diagrams are being built on other threads.
/// @throws std::invalid_argument if `directory` is not an existing folder.
void AllowDiagramFilesUnder(const std::filesystem::path& directory);

/// The folders allowed so far (canonical), in the order given.
std::vector<std::filesystem::path> AllowedDiagramFileFolders();

/// Forgets every allowed folder (tests).
void ClearAllowedDiagramFileFolders();

/// Resolves the file name `written` as it appears in a diagram: relative names against `base_directory`
/// (the diagram's folder; empty = the current directory), then symbolic links and "..", and checks the result.
/// Returns the canonical path of a regular file inside `base_directory` or an allowed folder.
/// @throws std::invalid_argument when `written` is empty, the file does not exist, is not a regular file (a
/// folder, device, FIFO or socket: /dev/zero never reaches a reader), or lies outside those folders; the message
/// names the path as written and as resolved and says how to fix it, and never shows the file's content.
/// `owner` names the file that wrote the path in the messages ("the diagram's folder"; a sweep file's "diagram" is
/// resolved the same way with "sweep file").
std::filesystem::path ResolveDiagramFile(const std::string& written, const std::filesystem::path& base_directory,
                                         const std::string& owner = "diagram");

}  // namespace mb

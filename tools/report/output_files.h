#pragma once
// Writing what commands produce: logged signals as CSV, JSON summaries, diagrams (the progress line: progress.h),
// and the one check that what a command writes never replaces what it reads (RefuseOutputsOverInputs).

#include <filesystem>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/simulator.h"
#include "tools/report/progress.h"

namespace mb {

/// Writes the log as CSV: time_s, then one column per logged signal. @throws std::runtime_error.
void WriteSignalLog(const SignalLog& log, const std::filesystem::path& path);

/// Creates the folder `file` is to be written in, if missing (as `run --out` creates its folder); nothing for a file
/// name without a folder. @throws std::filesystem::filesystem_error if it cannot be created.
void CreateParentFolder(const std::filesystem::path& file);

/// Writes pretty JSON (2-space indent). @throws std::runtime_error if the file cannot be written.
void WriteJsonFile(const nlohmann::json& j, const std::filesystem::path& path);

/// Writes `diagram` — read from (or amended from) a diagram in `diagram_folder` — to `path`, its file names
/// rewritten to name the same files from path's folder (DiagramDocument::RelocateFiles), so that the copy loads
/// wherever it is written. Returns the names that lie outside path's folder ("element.parameter: name"): the copy
/// reads those only with --allow-path. @throws std::runtime_error if the file cannot be written.
std::vector<std::string> WriteDiagramFile(const nlohmann::json& diagram, const std::filesystem::path& diagram_folder,
                                          const std::filesystem::path& path);

// ---- Outputs never replace inputs (issue 30) -------------------------------------------------------------------

/// A file a command reads or writes, with what names it on the command line ("DIAGRAM", "--measurement", "-o",
/// "--suggest"). An empty path is no file (an option not given) and is skipped.
struct CommandFile {
  std::string option;
  std::filesystem::path path;
};

/// The files a command writes into a folder (--out DIR): their names relative to it, each exact ("compare.json") or
/// a pattern in which '*' stands for any characters of a file name ("signal_*.png"), possibly in a subfolder
/// ("plot/*.dat": '*' never stands for a '/'), as the writers name them (e.g. CompareOutputNames).
struct OutputFolder {
  std::string option;
  std::filesystem::path folder;
  std::vector<std::string> names;
};

/// An output that would replace one of the command's inputs: bad usage (exit code 2).
class OutputReplacesInputError : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

/// Refuses (std::invalid_argument, exit 2) an output folder whose path holds '?', '#', '*', '[' or ']' (issue 41): a
/// browser reads '?' and '#' in report.html's address as the end of its path, so the report's pictures went missing
/// while the command said it had written them, and a shell expands '*', '?' and "[…]" in the commands printed to
/// redraw them. `option` names it ("--out"). RefuseOutputsOverInputs calls it for every folder it is given.
void RequireReportFolderName(const std::string& option, const std::filesystem::path& folder);

/// Refuses, before a command does any work, an output that would replace one of its inputs: an output file that is an
/// input (the same path once "..", "." and symbolic links are resolved: std::filesystem::weakly_canonical; or the
/// same file under another name, a hard link: std::filesystem::equivalent), or an input that lies in an output folder
/// under a name the command writes there. Paths need not exist.
/// @throws OutputReplacesInputError naming the output and the input as given and how to fix it (another output):
/// "-o d.json is the input DIAGRAM d.json: writing it would destroy the input; nothing was done: write the output
/// elsewhere (another -o)".
void RefuseOutputsOverInputs(const std::vector<CommandFile>& inputs, const std::vector<CommandFile>& outputs,
                             const std::vector<OutputFolder>& folders = {});

/// Whether file name `name` matches `pattern`, in which '*' stands for any run of characters ("signal_*.png").
bool FileNameMatches(std::string_view name, std::string_view pattern);

/// The regular files in `folder` and its subfolders that `names` (as OutputFolder::names: "report.html",
/// "plot/*.gp") name, and those a writer killed midway left ("<name>.tmp<pid>", engine/output_file.h): what an
/// earlier run of a command left in its output folder. Symbolic links to files count; folders are not followed
/// beyond the subfolders the names give. A missing folder or subfolder holds none.
std::vector<std::filesystem::path> OutputFilesIn(const std::filesystem::path& folder,
                                                 const std::vector<std::string>& names);

}  // namespace mb

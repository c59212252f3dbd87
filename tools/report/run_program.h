#pragma once
// Starting another program (gnuplot for figures) without a shell: the argument vector goes to the child as
// it is, so no name, path or title from a diagram can be read as a command (STYLE.md, "Outside processes").

#include <filesystem>
#include <string>
#include <vector>

namespace mb {

/// Runs `argv[0]` (looked up in PATH, as execvp does) with the arguments `argv`, no shell involved, and waits
/// for it. The child's standard input is /dev/null; its standard output and error go to `log_file` (created or
/// truncated; a relative name is taken from this process's working folder). A non-empty `working_directory` is the
/// child's working folder (posix_spawn_file_actions_addchdir_np, glibc >= 2.29), so that the relative paths in a
/// script it runs resolve there. Returns the exit status (0 = success), or −1 when the program could not be started
/// (not installed, or no such working folder) or ended by a signal. Never throws for the child's failure;
/// @throws std::invalid_argument if `argv` is empty.
int RunProgram(const std::vector<std::string>& argv, const std::filesystem::path& log_file,
               const std::filesystem::path& working_directory = {});

}  // namespace mb

#pragma once
// Runs the motionblocks executable (MB_MOTIONBLOCKS_EXE) as users call it, capturing exit code and output.

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>
#include <utility>

#include <nlohmann/json.hpp>

#include "tests/process_temp_dir.h"

#include <fcntl.h>
#include <spawn.h>
#include <sys/wait.h>
#include <unistd.h>

#include <vector>

extern char** environ;

namespace mb::testing {

struct CommandResult {
  int exit_code = -1;
  std::string output;  // stdout and stderr
};

/// `motionblocks ARGUMENTS` through the shell; the output is captured in a file of this process.
inline CommandResult RunMotionblocks(const std::string& arguments) {
  const auto log = ProcessTempDir("mb_command") / "output.log";
  const std::string command =
      std::string("\"") + MB_MOTIONBLOCKS_EXE + "\" " + arguments + " > \"" + log.string() + "\" 2>&1";
  CommandResult r;
  const int status = std::system(command.c_str());
  r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  std::ifstream in(log);
  r.output.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  return r;
}

/// The program `argv[0]` (looked up in PATH unless it names a path) with the arguments `argv`, no shell in between
/// (each argument reaches the program as written, backquotes and `$(…)` included), in the working directory
/// `directory`; stdout and stderr are captured. Exit code −1: not started, or ended by a signal.
inline CommandResult RunProgramIn(const std::filesystem::path& directory, std::vector<std::string> argv) {
  const auto log = ProcessTempDir("mb_command") / "output.log";
  std::vector<char*> args;
  for (auto& a : argv) args.push_back(a.data());
  args.push_back(nullptr);
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addchdir_np(&actions, directory.c_str());
  posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  pid_t pid = 0;
  CommandResult r;
  if (posix_spawnp(&pid, args[0], &actions, nullptr, args.data(), environ) == 0) {
    int status = 0;
    waitpid(pid, &status, 0);
    r.exit_code = WIFEXITED(status) ? WEXITSTATUS(status) : -1;
  }
  posix_spawn_file_actions_destroy(&actions);
  std::ifstream in(log);
  r.output.assign(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
  return r;
}

/// `motionblocks ARGUMENTS` with no shell in between, in the working directory `directory` (RunProgramIn).
inline CommandResult RunMotionblocksIn(const std::filesystem::path& directory, const std::vector<std::string>& arguments) {
  std::vector<std::string> argv = {MB_MOTIONBLOCKS_EXE};
  argv.insert(argv.end(), arguments.begin(), arguments.end());
  return RunProgramIn(directory, std::move(argv));
}

/// A JSON file the command wrote (compare.json, fit.json, …); throws nlohmann::json::parse_error if it is not JSON.
inline nlohmann::json ReadJsonFile(const std::filesystem::path& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

}  // namespace mb::testing

#pragma once
// Runs the motionblocks executable (MB_MOTIONBLOCKS_EXE) as users call it, capturing exit code and output.

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include <nlohmann/json.hpp>

#include <sys/wait.h>
#include <unistd.h>

namespace mb::testing {

struct CommandResult {
  int exit_code = -1;
  std::string output;  // stdout and stderr
};

/// A folder of this test process's own under the temporary directory (ctest runs test cases as parallel
/// processes: fixed names would collide).
inline std::filesystem::path ProcessTempDir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / (name + "_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  return dir;
}

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

/// A JSON file the command wrote (compare.json, fit.json, …); throws nlohmann::json::parse_error if it is not JSON.
inline nlohmann::json ReadJsonFile(const std::filesystem::path& path) {
  std::ifstream in(path);
  return nlohmann::json::parse(in);
}

}  // namespace mb::testing

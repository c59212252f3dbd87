#pragma once
// A folder of the test process's own under the temporary directory, removed with what it holds when the process ends.

#include <algorithm>
#include <filesystem>
#include <string>
#include <system_error>
#include <vector>

#include <unistd.h>

namespace mb::testing {

/// The folders ProcessTempDir made, removed with what they hold when the test process ends (each test case is a
/// process of its own under ctest): a run of the suite leaves nothing in the temporary directory.
class ProcessTempDirs {
 public:
  ProcessTempDirs() = default;
  ProcessTempDirs(const ProcessTempDirs&) = delete;
  ProcessTempDirs& operator=(const ProcessTempDirs&) = delete;
  ~ProcessTempDirs() {
    for (const auto& dir : made_) {
      std::error_code ignored;  // a folder a test removed itself, or one still open elsewhere: nothing to report
      std::filesystem::remove_all(dir, ignored);
    }
  }
  void Add(const std::filesystem::path& dir) {
    if (std::find(made_.begin(), made_.end(), dir) == made_.end()) made_.push_back(dir);
  }

 private:
  std::vector<std::filesystem::path> made_;
};

/// `<temporary directory>/<name>_<process id>`, created (ctest runs test cases as parallel processes: fixed names
/// would collide) and removed when the process ends.
inline std::filesystem::path ProcessTempDir(const std::string& name) {
  static ProcessTempDirs made;
  const auto dir = std::filesystem::temp_directory_path() / (name + "_" + std::to_string(::getpid()));
  std::filesystem::create_directories(dir);
  made.Add(dir);
  return dir;
}

}  // namespace mb::testing

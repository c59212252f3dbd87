#pragma once
// The fuzzers' inputs as the readers meet them: a regular file in a folder of its own (the readers take paths
// and resolve a diagram's file parameters against its folder).

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>
#include <system_error>

namespace mb::fuzz {

/// A private folder under the temporary directory, made once per fuzzing process and removed when it exits.
class FuzzFolder {
 public:
  FuzzFolder()
      : path_(std::filesystem::temp_directory_path() / ("motionblocks-fuzz-" + std::to_string(::getpid()))) {
    std::filesystem::create_directories(path_);
  }
  ~FuzzFolder() {
    std::error_code ignored;
    std::filesystem::remove_all(path_, ignored);
  }
  FuzzFolder(const FuzzFolder&) = delete;
  FuzzFolder& operator=(const FuzzFolder&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

/// Writes the fuzzer's input as the file `name` in the process's FuzzFolder and returns its path.
inline std::filesystem::path WriteFuzzInput(const uint8_t* data, std::size_t size, const std::string& name) {
  static const FuzzFolder folder;
  const auto path = folder.path() / name;
  std::ofstream(path, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(data),
                                                                 static_cast<std::streamsize>(size));
  return path;
}

}  // namespace mb::fuzz

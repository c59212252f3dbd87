#pragma once
// The fuzzers' inputs as the readers meet them: a regular file in a folder of its own (the readers take paths
// and resolve a diagram's file parameters against its folder).

#include <unistd.h>

#include <cstddef>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <string>

namespace mb::fuzz {

/// A private folder under the temporary directory, made once per fuzzing process, holding `name`.
inline std::filesystem::path WriteFuzzInput(const uint8_t* data, std::size_t size, const std::string& name) {
  static const std::filesystem::path folder = [] {
    auto dir = std::filesystem::temp_directory_path() / ("motionblocks-fuzz-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir);
    return dir;
  }();
  const auto path = folder / name;
  std::ofstream(path, std::ios::binary | std::ios::trunc).write(reinterpret_cast<const char*>(data),
                                                                 static_cast<std::streamsize>(size));
  return path;
}

}  // namespace mb::fuzz

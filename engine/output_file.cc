#include "engine/output_file.h"

#include <fstream>
#include <stdexcept>
#include <system_error>

#include <fmt/format.h>
#include <unistd.h>

namespace mb {

namespace fs = std::filesystem;

namespace {

void WriteThrough(const fs::path& path, std::string_view text) {
  std::ofstream out(path, std::ios::binary | std::ios::app);  // no truncation of a device; opens an existing path
  if (!out || !out.write(text.data(), static_cast<std::streamsize>(text.size())) || !out.flush()) {
    throw std::runtime_error(fmt::format("{}: cannot write (a pipe or device that refused the data)", path.string()));
  }
}

void WriteAndRename(const fs::path& path, std::string_view text) {
  fs::path temporary = path;
  temporary += fmt::format(".tmp{}", static_cast<long>(getpid()));
  {
    std::ofstream out(temporary, std::ios::binary | std::ios::trunc);
    if (!out) {
      throw std::runtime_error(
          fmt::format("{}: cannot write beside it ({}): check that the folder exists and is writable", path.string(),
                      temporary.filename().string()));
    }
    out.write(text.data(), static_cast<std::streamsize>(text.size()));
    out.close();
    if (!out) {
      std::error_code ignored;
      fs::remove(temporary, ignored);
      throw std::runtime_error(fmt::format("{}: writing failed (disk full?); the file is unchanged", path.string()));
    }
  }
  std::error_code ec;
  fs::rename(temporary, path, ec);
  if (ec) {
    std::error_code ignored;
    fs::remove(temporary, ignored);
    throw std::runtime_error(fmt::format("{}: cannot replace it: {}", path.string(), ec.message()));
  }
}

}  // namespace

void WriteFileSafely(const fs::path& path, std::string_view text) {
  std::error_code ec;
  fs::path target = path;
  if (fs::is_symlink(fs::symlink_status(path, ec))) {
    target = fs::canonical(path, ec);
    if (ec) {
      throw std::runtime_error(fmt::format("{}: a symbolic link to nothing ({}); remove it or point it at a file",
                                           path.string(), ec.message()));
    }
  }
  const fs::file_status status = fs::status(target, ec);
  if (!fs::exists(status) || fs::is_regular_file(status)) return WriteAndRename(target, text);
  if (fs::is_fifo(status) || fs::is_character_file(status)) return WriteThrough(target, text);
  const char* what = fs::is_directory(status) ? "a folder" : fs::is_block_file(status) ? "a block device" : "a socket";
  throw std::runtime_error(fmt::format("{} is {}, not a file: give a file name", path.string(), what));
}

}  // namespace mb

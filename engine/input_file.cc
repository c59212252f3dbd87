#include "engine/input_file.h"

#include <fstream>
#include <stdexcept>
#include <system_error>

#include <fmt/format.h>

#include "engine/file_error.h"

namespace mb {

namespace fs = std::filesystem;

namespace {

std::uintmax_t g_max_input_file_bytes = kDefaultMaxInputFileBytes;

std::string TypeName(fs::file_type type) {
  switch (type) {
    case fs::file_type::directory: return "a folder";
    case fs::file_type::character: return "a character device";
    case fs::file_type::block: return "a block device";
    case fs::file_type::fifo: return "a FIFO (named pipe)";
    case fs::file_type::socket: return "a socket";
    default: return "not a file";
  }
}

std::string Megabytes(std::uintmax_t bytes) { return fmt::format("{:.4g} MB", static_cast<double>(bytes) / 1e6); }

[[noreturn]] void ThrowTooLarge(const fs::path& path, std::string_view kind, std::string_view size_text) {
  throw std::invalid_argument(fmt::format(
      "{}: the {} is {}, more than the input limit of {} ({} bytes); if it is meant to be this large, raise the "
      "limit with --max-input-mb (e.g. --max-input-mb {})",
      path.string(), kind, size_text, Megabytes(g_max_input_file_bytes), g_max_input_file_bytes,
      2 * (g_max_input_file_bytes / 1000000 + 1)));
}

}  // namespace

void SetMaxInputFileBytes(std::uintmax_t bytes) {
  if (bytes == 0) throw std::invalid_argument("--max-input-mb: the input size limit must be positive");
  g_max_input_file_bytes = bytes;
}

std::uintmax_t MaxInputFileBytes() { return g_max_input_file_bytes; }

void CheckInputFile(const fs::path& path, std::string_view kind) {
  std::error_code ec;
  const fs::file_status status = fs::status(path, ec);  // stat(2): never opens, so a FIFO cannot block
  if (!fs::exists(status)) return;                       // the caller's open says it is missing
  if (!fs::is_regular_file(status)) {
    throw std::invalid_argument(fmt::format(
        "{}: the {} is {}, not a regular file; give the path of a regular file (save a stream or a pipe's output "
        "to a file first)",
        path.string(), kind, TypeName(status.type())));
  }
  const std::uintmax_t size = fs::file_size(path, ec);
  if (!ec && size > g_max_input_file_bytes) {
    ThrowTooLarge(path, kind, fmt::format("{} bytes ({})", size, Megabytes(size)));
  }
}

std::string ReadInputFile(const fs::path& path, std::string_view kind) {
  CheckInputFile(path, kind);
  std::ifstream in(path, std::ios::binary);
  if (!in) {
    throw FileOpenError(
        fmt::format("{}: cannot open the {} (missing file or no permission); check the path", path.string(), kind));
  }
  std::string text;
  std::error_code ec;
  const std::uintmax_t size = fs::file_size(path, ec);
  if (!ec) text.reserve(static_cast<std::size_t>(size));
  char buffer[1 << 16];
  while (in.read(buffer, sizeof(buffer)) || in.gcount() > 0) {
    text.append(buffer, static_cast<std::size_t>(in.gcount()));
    if (text.size() > g_max_input_file_bytes) ThrowTooLarge(path, kind, "larger than that (it grew while read)");
  }
  return text;
}

}  // namespace mb

#include "engine/file_access.h"

#include <algorithm>
#include <mutex>
#include <stdexcept>
#include <system_error>

#include <fmt/format.h>

namespace mb {

namespace fs = std::filesystem;

namespace {

std::mutex& AllowedMutex() {
  static std::mutex m;
  return m;
}

std::vector<fs::path>& Allowed() {
  static std::vector<fs::path> folders;
  return folders;
}

// The canonical form of `p` (made absolute against the current directory), existing or not.
fs::path Canonical(const fs::path& p) {
  std::error_code ec;
  fs::path absolute = fs::absolute(p.empty() ? fs::path(".") : p, ec);
  if (ec) return p.lexically_normal();
  fs::path canonical = fs::weakly_canonical(absolute, ec);
  return ec ? absolute.lexically_normal() : canonical;
}

// True if `path` is `folder` or lies below it (both canonical).
bool IsUnder(const fs::path& path, const fs::path& folder) {
  const fs::path relative = path.lexically_relative(folder);
  return !relative.empty() && *relative.begin() != "..";
}

}  // namespace

void AllowDiagramFilesUnder(const fs::path& directory) {
  std::error_code ec;
  if (!fs::is_directory(directory, ec)) {
    throw std::invalid_argument(
        fmt::format("--allow-path {}: not an existing folder; give the folder that holds the files", directory.string()));
  }
  const fs::path folder = Canonical(directory);
  std::lock_guard lock(AllowedMutex());
  if (std::find(Allowed().begin(), Allowed().end(), folder) == Allowed().end()) Allowed().push_back(folder);
}

std::vector<fs::path> AllowedDiagramFileFolders() {
  std::lock_guard lock(AllowedMutex());
  return Allowed();
}

void ClearAllowedDiagramFileFolders() {
  std::lock_guard lock(AllowedMutex());
  Allowed().clear();
}

fs::path ResolveDiagramFile(const std::string& written, const fs::path& base_directory, const std::string& owner) {
  if (written.empty()) {
    throw std::invalid_argument(fmt::format("the file name is empty: give a file in the {}'s folder", owner));
  }
  const fs::path folder = Canonical(base_directory);
  const fs::path resolved = Canonical(fs::path(written).is_absolute() ? fs::path(written) : folder / written);
  const auto allowed = AllowedDiagramFileFolders();
  const bool inside = IsUnder(resolved, folder) ||
                      std::any_of(allowed.begin(), allowed.end(), [&](const fs::path& f) { return IsUnder(resolved, f); });
  if (!inside) {
    throw std::invalid_argument(fmt::format(
        "\"{}\" resolves to {}, outside the {}'s folder {}: a {} reads only files beside it; copy the file into that "
        "folder, or allow its folder with --allow-path {}",
        written, resolved.string(), owner, folder.string(), owner, resolved.parent_path().string()));
  }
  std::error_code ec;
  const fs::file_status status = fs::status(resolved, ec);
  if (!fs::exists(status)) {
    throw std::invalid_argument(fmt::format("\"{}\" ({}): no such file; check the name (relative names start at the "
                                            "{}'s folder {})",
                                            written, resolved.string(), owner, folder.string()));
  }
  if (!fs::is_regular_file(status)) {
    throw std::invalid_argument(fmt::format("\"{}\" ({}) is not a regular file (a folder, device, FIFO or socket); "
                                            "name a file",
                                            written, resolved.string()));
  }
  return resolved;
}

}  // namespace mb

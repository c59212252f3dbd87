#pragma once
// TemporaryFolder: a private scratch folder for outputs nobody keeps (dot's input and output for a drawing, a
// sweep run from Python without an output folder).

#include <filesystem>
#include <string>

namespace mb {

/// A fresh folder `<system temp>/<prefix>-XXXXXX` (mkdtemp: unique, mode 0700), removed with everything in it when
/// the object goes. @throws std::runtime_error naming the folder if it cannot be created (check TMPDIR).
class TemporaryFolder {
 public:
  explicit TemporaryFolder(const std::string& prefix);
  ~TemporaryFolder();
  TemporaryFolder(const TemporaryFolder&) = delete;
  TemporaryFolder& operator=(const TemporaryFolder&) = delete;
  const std::filesystem::path& path() const { return path_; }

 private:
  std::filesystem::path path_;
};

}  // namespace mb

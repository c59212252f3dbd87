#pragma once
// FileOpenError: an input file that cannot be opened (missing, a folder, no permission), as opposed to a file
// whose content is wrong (std::invalid_argument, DiagramError). The Python module raises it as OSError.

#include <stdexcept>

namespace mb {

/// Thrown by the readers of diagrams, CSV tables, GP models and sweep files when the file cannot be opened; the
/// message names the path and says what to check.
class FileOpenError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace mb

#pragma once
// Reading input files (diagrams, measurement logs, tables, GP models, sweep files) with a bound: only a regular
// file is opened (a device such as /dev/zero or /dev/urandom, a FIFO, a socket or a folder is refused from its
// status, before any open, so a FIFO without writer never blocks), and only up to a size limit that the user can
// raise (`motionblocks --max-input-mb N`). Issue 30, "Reads and requests without bound". Source: this project.

#include <cstdint>
#include <filesystem>
#include <string>
#include <string_view>

namespace mb {

/// The default size limit of one input file, in bytes: 1 GiB (a 25k-sample log is about 1 MB; ten million rows of
/// five columns about 600 MB).
inline constexpr std::uintmax_t kDefaultMaxInputFileBytes = std::uintmax_t{1} << 30;

/// Sets the size limit of every input file read afterwards, in bytes (> 0). Process-wide, like the allowed folders
/// of engine/file_access.h: set it while setting up (the command line), not while files are being read.
/// @throws std::invalid_argument if `bytes` is 0.
void SetMaxInputFileBytes(std::uintmax_t bytes);

/// The size limit in force, in bytes (kDefaultMaxInputFileBytes unless SetMaxInputFileBytes changed it).
std::uintmax_t MaxInputFileBytes();

/// Checks the input file at `path` without opening it: it must be a regular file (symbolic links followed) no
/// larger than MaxInputFileBytes(). A path that does not exist passes (the caller's open reports it in its own
/// words). `kind` names the file in messages ("diagram file", "measurement log", "GP model file").
/// @throws std::invalid_argument "<path>: the <kind> is not a regular file (a character device) …; give the path
/// of a regular file …" or "<path>: the <kind> is N bytes (… MB), more than the input limit of M MB; …raise the limit
/// with --max-input-mb …".
void CheckInputFile(const std::filesystem::path& path, std::string_view kind);

/// CheckInputFile, then the whole file as bytes; at most MaxInputFileBytes() are read even if the file grows
/// meanwhile (the same error then).
/// @throws std::invalid_argument as CheckInputFile; FileOpenError (engine/file_error.h) "<path>: cannot open the
/// <kind> (missing file or no permission); check the path" when it cannot be opened.
std::string ReadInputFile(const std::filesystem::path& path, std::string_view kind);

}  // namespace mb

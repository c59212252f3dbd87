#pragma once
// Writing what the tools produce (model files, logs, tables, JSON summaries) without harming what is there.

#include <filesystem>
#include <string_view>

namespace mb {

/// Writes `text` to `path` so that a reader never sees half a file and nothing but a file is ever replaced:
///  - no file or a regular file at `path`: the text goes to a temporary file beside it, which is then renamed
///    over `path` (atomic on POSIX);
///  - a symbolic link: the same, applied to the file it points to (the link stays a link);
///  - a FIFO or character device (a pipe, /dev/stdout, /dev/null): written through, never replaced;
///  - a folder, block device, socket or a dangling link: refused.
/// @throws std::runtime_error naming the path, what is there and how to fix it, when the target is refused or
/// cannot be written (the temporary file is removed; the original is untouched).
void WriteFileSafely(const std::filesystem::path& path, std::string_view text);

}  // namespace mb

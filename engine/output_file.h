#pragma once
// Writing what the tools produce (model files, logs, tables, JSON summaries) without harming what is there.

#include <filesystem>
#include <fstream>
#include <string>
#include <string_view>
#include <vector>

#include "engine/log_sink.h"

namespace mb {

/// Writes `text` to `path` so that a reader never sees half a file and nothing but a file is ever replaced:
///  - no file or a regular file at `path`: the text goes to a temporary file beside it, which is then renamed
///    over `path` (atomic on POSIX);
///  - a symbolic link: the same, applied to the file it points to (the link stays a link);
///  - a FIFO or character device (a pipe, /dev/stdout, /dev/null): written through, never replaced; a FIFO that no
///    process has open for reading is refused at once (opening it would wait forever);
///  - a folder, block device, socket or a dangling link: refused.
/// @throws std::runtime_error naming the path, what is there and how to fix it, when the target is refused or
/// cannot be written (the temporary file is removed; the original is untouched).
void WriteFileSafely(const std::filesystem::path& path, std::string_view text);

/// A file written piece by piece with WriteFileSafely's rules: into a temporary file beside `path`, renamed over it
/// by Commit (a FIFO or character device is written through; a folder, block device, socket or dangling link is
/// refused at once). Without Commit (an exception, a failed run) the temporary file is removed and `path` is
/// unchanged. @throws std::runtime_error as WriteFileSafely, from the constructor, Write and Commit.
class StreamedFile {
 public:
  explicit StreamedFile(const std::filesystem::path& path);
  ~StreamedFile();
  StreamedFile(const StreamedFile&) = delete;
  StreamedFile& operator=(const StreamedFile&) = delete;
  void Write(std::string_view text);
  void Commit();

 private:
  std::filesystem::path path_;       ///< the target as given
  std::filesystem::path target_;     ///< the file a link points to, or path_
  std::filesystem::path temporary_;  ///< empty when written through
  std::ofstream out_;
  bool committed_ = false;
};

/// From now on SIGINT, SIGTERM and SIGHUP first remove every temporary file a StreamedFile (or WriteFileSafely) is
/// writing and write the InterruptMarker's file, if one lives, then end the process as the signal's default action
/// would (so a shell sees the interrupt). The handler does only what a signal handler may (unlink, open, write,
/// rename). Call once, from main (issue 41: Ctrl-C left signals.csv.tmpNNNN beside an earlier run's files).
void RemoveTemporaryFilesOnInterrupt();

/// While it lives, an interrupt (RemoveTemporaryFilesOnInterrupt) writes `text` to `path` (through a temporary file
/// renamed over it): a folder left by an interrupted command says it is incomplete. One at a time.
class InterruptMarker {
 public:
  InterruptMarker(const std::filesystem::path& path, std::string text);
  ~InterruptMarker();
  InterruptMarker(const InterruptMarker&) = delete;
  InterruptMarker& operator=(const InterruptMarker&) = delete;

 private:
  std::string path_;
  std::string temporary_;
  std::string text_;
};

/// A simulation log streamed to CSV as it is taken (Simulator::StreamLogTo): the header "time_s,<names>", then
/// one row per sample, numbers in their shortest round-trip form — the file WriteSignalLog writes from a log in
/// memory, byte for byte. Buffered (64 KB); Commit when the run succeeded.
class CsvLogFile final : public LogSink {
 public:
  explicit CsvLogFile(const std::filesystem::path& path) : file_(path) {}
  void Begin(const std::vector<std::string>& names) override;
  void Append(double t, const std::vector<double>& values) override;
  /// Writes what is buffered and renames the file into place. @throws std::runtime_error.
  void Commit();

 private:
  StreamedFile file_;
  std::string buffer_;
};

}  // namespace mb

#include "engine/output_file.h"

#include <array>
#include <atomic>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <csignal>
#include <fstream>
#include <stdexcept>
#include <system_error>

#include <fmt/format.h>
#include <fcntl.h>
#include <signal.h>
#include <unistd.h>

namespace mb {

namespace fs = std::filesystem;

namespace {

constexpr std::size_t kCsvBufferBytes = 64 * 1024;

// The temporary files being written (their paths' C strings, owned by the StreamedFile), for the interrupt handler:
// a fixed table of lock-free atomic slots, which a signal handler may read.
constexpr std::size_t kTemporarySlots = 64;
std::array<std::atomic<const char*>, kTemporarySlots> g_temporaries{};

struct MarkerText {
  const char* path;
  const char* temporary;
  const char* text;
  std::size_t size;
};
std::atomic<const MarkerText*> g_marker{nullptr};

void RegisterTemporary(const char* path) {
  for (auto& slot : g_temporaries) {
    const char* expected = nullptr;
    if (slot.compare_exchange_strong(expected, path)) return;
  }  // more than 64 files at once: the rest are not removed on an interrupt (still removed on an exception)
}

void UnregisterTemporary(const char* path) {
  for (auto& slot : g_temporaries) {
    const char* expected = path;
    if (slot.compare_exchange_strong(expected, nullptr)) return;
  }
}

extern "C" void RemoveTemporariesAndReraise(int signal_number) {
  for (auto& slot : g_temporaries) {
    if (const char* path = slot.load()) ::unlink(path);
  }
  if (const MarkerText* marker = g_marker.load()) {
    const int fd = ::open(marker->temporary, O_WRONLY | O_CREAT | O_TRUNC | O_NOFOLLOW | O_CLOEXEC, 0644);
    if (fd >= 0) {
      const bool whole = ::write(fd, marker->text, marker->size) == static_cast<ssize_t>(marker->size);
      ::close(fd);
      if (!whole || ::rename(marker->temporary, marker->path) != 0) ::unlink(marker->temporary);
    }
  }
  ::signal(signal_number, SIG_DFL);
  ::raise(signal_number);
}

void AppendNumber(double value, std::string* text) {
  char buf[32];
  const auto res = std::to_chars(buf, buf + sizeof(buf), value);  // shortest round trip, as WriteMeasurementLog
  text->append(buf, res.ptr);
}

}  // namespace

StreamedFile::StreamedFile(const fs::path& path) : path_(path), target_(path) {
  std::error_code ec;
  if (fs::is_symlink(fs::symlink_status(path, ec))) {
    target_ = fs::canonical(path, ec);
    if (ec) {
      throw std::runtime_error(fmt::format("{}: a symbolic link to nothing ({}); remove it or point it at a file",
                                           path.string(), ec.message()));
    }
  }
  const fs::file_status status = fs::status(target_, ec);
  int probe = -1;
  if (fs::is_fifo(status)) {
    // Opening a FIFO for writing waits until a process opens it for reading: forever when none does (issue 41:
    // draw -o FIFO hung). Non-blocking, the open fails at once (ENXIO) when no reader has it open. The probe stays
    // open until the stream is: closed before, it would hand the reader an end of file, and the stream's open would
    // then wait for a reader that is gone.
    probe = ::open(target_.c_str(), O_WRONLY | O_NONBLOCK | O_CLOEXEC);
    if (probe < 0) {
      throw std::runtime_error(fmt::format("{} is a FIFO (named pipe) that no process reads{}: writing to it would "
                                           "wait forever; start its reader first, or give a file name",
                                           path.string(), errno == ENXIO ? "" : fmt::format(" ({})", std::strerror(errno))));
    }
  }
  if (fs::is_fifo(status) || fs::is_character_file(status)) {
    out_.open(target_, std::ios::binary | std::ios::app);  // no truncation of a device; opens an existing path
    if (probe >= 0) ::close(probe);
    if (!out_) {
      throw std::runtime_error(fmt::format("{}: cannot write (a pipe or device that refused it)", path.string()));
    }
    return;
  }
  if (fs::exists(status) && !fs::is_regular_file(status)) {
    const char* what = fs::is_directory(status)    ? "a folder"
                       : fs::is_block_file(status) ? "a block device"
                                                   : "a socket";
    throw std::runtime_error(fmt::format("{} is {}, not a file: give a file name", path.string(), what));
  }
  temporary_ = target_;
  temporary_ += fmt::format(".tmp{}", static_cast<long>(getpid()));
  RegisterTemporary(temporary_.c_str());
  out_.open(temporary_, std::ios::binary | std::ios::trunc);
  if (!out_) {
    UnregisterTemporary(temporary_.c_str());
    temporary_.clear();
    throw std::runtime_error(fmt::format("{}: cannot write beside it ({}): check that the folder exists and is "
                                         "writable",
                                         path.string(), temporary_.filename().string()));
  }
}

StreamedFile::~StreamedFile() {
  if (temporary_.empty()) return;
  if (!committed_) {
    out_.close();
    std::error_code ignored;
    fs::remove(temporary_, ignored);
  }
  UnregisterTemporary(temporary_.c_str());
}

void StreamedFile::Write(std::string_view text) {
  if (!out_.write(text.data(), static_cast<std::streamsize>(text.size()))) {
    throw std::runtime_error(fmt::format("{}: writing failed (disk full, or a pipe that closed); the file is unchanged",
                                         path_.string()));
  }
}

void StreamedFile::Commit() {
  out_.close();
  if (!out_) {
    throw std::runtime_error(fmt::format("{}: writing failed (disk full?); the file is unchanged", path_.string()));
  }
  committed_ = true;
  if (temporary_.empty()) return;
  std::error_code ec;
  fs::rename(temporary_, target_, ec);
  UnregisterTemporary(temporary_.c_str());
  if (ec) {
    std::error_code ignored;
    fs::remove(temporary_, ignored);
    throw std::runtime_error(fmt::format("{}: cannot replace it: {}", path_.string(), ec.message()));
  }
}

void RemoveTemporaryFilesOnInterrupt() {
  static_assert(std::atomic<const char*>::is_always_lock_free && std::atomic<const MarkerText*>::is_always_lock_free);
  for (const int signal_number : {SIGINT, SIGTERM, SIGHUP}) {
    struct sigaction action {};
    action.sa_handler = RemoveTemporariesAndReraise;
    sigemptyset(&action.sa_mask);
    action.sa_flags = static_cast<int>(SA_RESETHAND);  // a second Ctrl-C while it cleans up ends the process at once
    ::sigaction(signal_number, &action, nullptr);
  }
}

InterruptMarker::InterruptMarker(const fs::path& path, std::string text)
    : path_(path.string()), temporary_(path.string() + fmt::format(".tmp{}i", static_cast<long>(getpid()))),
      text_(std::move(text)) {
  static MarkerText marker;  // read by the handler while g_marker points at it (one marker at a time)
  marker = MarkerText{path_.c_str(), temporary_.c_str(), text_.data(), text_.size()};
  g_marker.store(&marker);
}

InterruptMarker::~InterruptMarker() { g_marker.store(nullptr); }

void WriteFileSafely(const fs::path& path, std::string_view text) {
  StreamedFile file(path);
  file.Write(text);
  file.Commit();
}

void CsvLogFile::Begin(const std::vector<std::string>& names) {
  buffer_ = "time_s";
  for (const auto& name : names) buffer_ += "," + name;
  buffer_ += '\n';
}

void CsvLogFile::Append(double t, const std::vector<double>& values) {
  AppendNumber(t, &buffer_);
  for (const double v : values) {
    buffer_ += ',';
    AppendNumber(v, &buffer_);
  }
  buffer_ += '\n';
  if (buffer_.size() >= kCsvBufferBytes) {
    file_.Write(buffer_);
    buffer_.clear();
  }
}

void CsvLogFile::Commit() {
  file_.Write(buffer_);
  buffer_.clear();
  file_.Commit();
}

}  // namespace mb

#include "engine/output_file.h"

#include <charconv>
#include <fstream>
#include <stdexcept>
#include <system_error>

#include <fmt/format.h>
#include <unistd.h>

namespace mb {

namespace fs = std::filesystem;

namespace {

constexpr std::size_t kCsvBufferBytes = 64 * 1024;

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
  if (fs::is_fifo(status) || fs::is_character_file(status)) {
    out_.open(target_, std::ios::binary | std::ios::app);  // no truncation of a device; opens an existing path
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
  out_.open(temporary_, std::ios::binary | std::ios::trunc);
  if (!out_) {
    throw std::runtime_error(fmt::format("{}: cannot write beside it ({}): check that the folder exists and is "
                                         "writable",
                                         path.string(), temporary_.filename().string()));
  }
}

StreamedFile::~StreamedFile() {
  if (committed_ || temporary_.empty()) return;
  out_.close();
  std::error_code ignored;
  fs::remove(temporary_, ignored);
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
  if (ec) {
    std::error_code ignored;
    fs::remove(temporary_, ignored);
    throw std::runtime_error(fmt::format("{}: cannot replace it: {}", path_.string(), ec.message()));
  }
}

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

#pragma once
// Writing what commands produce: logged signals as CSV, JSON summaries, a progress line on stderr.

#include <filesystem>
#include <string>

#include <nlohmann/json.hpp>

#include "engine/simulator.h"

namespace mb {

/// Writes the log as CSV: time_s, then one column per logged signal. @throws std::runtime_error.
void WriteSignalLog(const SignalLog& log, const std::filesystem::path& path);

/// Writes pretty JSON (2-space indent). @throws std::runtime_error if the file cannot be written.
void WriteJsonFile(const nlohmann::json& j, const std::filesystem::path& path);

/// A progress line "label  37 %" on stderr, rewritten in place; silent when stderr is not a terminal and
/// `always` is false (CI logs stay short: then only 0 %, 50 % and 100 % are printed).
class ProgressLine {
 public:
  explicit ProgressLine(std::string label);
  void Update(double fraction);
  void Done();

 private:
  std::string label_;
  bool tty_;
  int last_percent_ = -1;
};

}  // namespace mb

#pragma once
// Progress of long commands on stderr (run, compare, fit, improve, sweep, reproduce), one small facility: a
// process-wide mode set by the command line (--progress, --quiet), a rate-limited percentage line, and stage
// notes. Progress never goes to stdout, so JSON a command prints there stays clean.

#include <chrono>
#include <string>

namespace mb {

/// When progress is shown: kAuto — the percentage line only when stderr is a terminal (stage notes always);
/// kAlways (--progress) — the percentage line also into a file or pipe, one line per update at most every 2 s;
/// kNever (--quiet) — nothing, stage notes included.
enum class ProgressMode { kAuto, kAlways, kNever };

/// Sets the process-wide mode (the command line does, before the command runs). Not thread-safe: call at setup.
void SetProgressMode(ProgressMode mode);
ProgressMode GetProgressMode();

/// Prints `line` on stderr (a stage of a long command: "improve: step 0: …") unless the mode is kNever.
void ProgressNote(const std::string& line);

/// A progress line "label  37 %" on stderr: on a terminal rewritten in place at most every 0.2 s; with
/// kAlways and stderr not a terminal, one line at most every 2 s; else silent. Update is cheap when nothing
/// is printed (call it per run or per step). Not thread-safe: guard it with the caller's mutex.
class ProgressLine {
 public:
  explicit ProgressLine(std::string label);
  /// `fraction` in [0, 1] (clamped).
  void Update(double fraction);
  /// The final "label  100 % (12.3 s)" line, when anything was shown.
  void Done();

 private:
  std::string label_;
  bool terminal_;
  std::string terminal_label_;  // label_ with its control bytes escaped (EscapeControlBytes): written past the escaping
  bool shown_;
  std::chrono::steady_clock::time_point start_;
  std::chrono::steady_clock::time_point last_print_;
  int last_percent_ = -1;
};

}  // namespace mb

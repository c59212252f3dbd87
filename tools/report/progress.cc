#include "tools/report/progress.h"

#include <algorithm>
#include <cstdio>
#include <iostream>

#include <fmt/format.h>
#include <unistd.h>

#include "engine/terminal_text.h"

namespace mb {

namespace {

ProgressMode g_mode = ProgressMode::kAuto;

constexpr std::chrono::milliseconds kTerminalInterval{200};
constexpr std::chrono::milliseconds kFileInterval{2000};

// A progress line on a terminal: its own "\r" returns to the line's start, so it is written to stderr directly,
// past the command line's escaping of standard error (engine/terminal_text.h); the label is escaped here.
void RewriteTerminalLine(const std::string& text) {
  std::cerr.flush();
  std::fputs(text.c_str(), stderr);
  std::fflush(stderr);
}

}  // namespace

void SetProgressMode(ProgressMode mode) { g_mode = mode; }
ProgressMode GetProgressMode() { return g_mode; }

void ProgressNote(const std::string& line) {
  if (g_mode != ProgressMode::kNever) std::cerr << line << "\n";
}

ProgressLine::ProgressLine(std::string label)
    : label_(std::move(label)),
      terminal_(isatty(fileno(stderr)) != 0),
      terminal_label_(EscapeControlBytes(label_)),
      shown_(g_mode == ProgressMode::kAlways || (g_mode == ProgressMode::kAuto && terminal_)),
      start_(std::chrono::steady_clock::now()),
      last_print_(start_ - kFileInterval) {}

void ProgressLine::Update(double fraction) {
  if (!shown_) return;
  const int percent = static_cast<int>(100.0 * std::clamp(fraction, 0.0, 1.0));
  const auto now = std::chrono::steady_clock::now();
  if (percent == last_percent_ || now - last_print_ < (terminal_ ? kTerminalInterval : kFileInterval)) return;
  last_print_ = now;
  last_percent_ = percent;
  if (terminal_) {
    RewriteTerminalLine(fmt::format("\r{}  {:3d} %", terminal_label_, percent));
  } else {
    std::cerr << fmt::format("{}  {:3d} %\n", label_, percent);
  }
}

void ProgressLine::Done() {
  if (!shown_) return;
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  if (terminal_) {
    RewriteTerminalLine(fmt::format("\r{}  100 % ({:.1f} s)\n", terminal_label_, seconds));
  } else {
    std::cerr << fmt::format("{}  100 % ({:.1f} s)\n", label_, seconds);
  }
}

}  // namespace mb

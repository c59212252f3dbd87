#include "tools/report/progress.h"

#include <algorithm>
#include <cstdio>
#include <iostream>

#include <fmt/format.h>
#include <unistd.h>

namespace mb {

namespace {

ProgressMode g_mode = ProgressMode::kAuto;

constexpr std::chrono::milliseconds kTerminalInterval{200};
constexpr std::chrono::milliseconds kFileInterval{2000};

}  // namespace

void SetProgressMode(ProgressMode mode) { g_mode = mode; }
ProgressMode GetProgressMode() { return g_mode; }

void ProgressNote(const std::string& line) {
  if (g_mode != ProgressMode::kNever) std::cerr << line << "\n";
}

ProgressLine::ProgressLine(std::string label)
    : label_(std::move(label)),
      terminal_(isatty(fileno(stderr)) != 0),
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
    std::cerr << fmt::format("\r{}  {:3d} %", label_, percent) << std::flush;
  } else {
    std::cerr << fmt::format("{}  {:3d} %\n", label_, percent);
  }
}

void ProgressLine::Done() {
  if (!shown_) return;
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start_).count();
  std::cerr << fmt::format("{}{}  100 % ({:.1f} s)\n", terminal_ ? "\r" : "", label_, seconds);
}

}  // namespace mb

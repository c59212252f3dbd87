#include "hw/realtime.h"

#include <sched.h>
#include <sys/mman.h>
#include <time.h>

#include <algorithm>
#include <csignal>
#include <cerrno>
#include <cmath>
#include <cstring>

#include <fmt/format.h>

namespace mb {

namespace {
constexpr std::int64_t kNanosecondsPerSecond = 1'000'000'000;

double Seconds(std::int64_t ns) { return static_cast<double>(ns) * 1e-9; }

/// The q-quantile of sorted values (nearest rank).
double Quantile(const std::vector<double>& sorted, double q) {
  if (sorted.empty()) return 0.0;
  const auto n = static_cast<double>(sorted.size());
  const auto i = static_cast<std::size_t>(std::min(n - 1.0, std::max(0.0, std::ceil(q * n) - 1.0)));
  return sorted[i];
}

/// Touches `bytes` of stack so that its pages are mapped (and locked with mlockall) before the loop.
void PrefaultStack() {
  constexpr std::size_t kBytes = 256 * 1024;
  unsigned char buffer[kBytes];
  std::memset(buffer, 0, kBytes);
  asm volatile("" : : "r"(buffer) : "memory");  // keep the writes: the point is touching the pages
}
}  // namespace

std::int64_t MonotonicNanoseconds() noexcept {
  timespec ts{};
  clock_gettime(CLOCK_MONOTONIC, &ts);
  return static_cast<std::int64_t>(ts.tv_sec) * kNanosecondsPerSecond + ts.tv_nsec;
}

void SleepUntil(std::int64_t deadline_ns) noexcept {
  timespec ts{};
  ts.tv_sec = static_cast<time_t>(deadline_ns / kNanosecondsPerSecond);
  ts.tv_nsec = static_cast<long>(deadline_ns % kNanosecondsPerSecond);
  while (clock_nanosleep(CLOCK_MONOTONIC, TIMER_ABSTIME, &ts, nullptr) == EINTR) {
  }
}

std::vector<std::string> ApplyRealTimeOptions(const RealTimeOptions& options) {
  std::vector<std::string> notes;
  if (options.lock_memory) {
    if (mlockall(MCL_CURRENT | MCL_FUTURE) == 0) {
      PrefaultStack();
      notes.push_back("memory locked (mlockall), 256 KiB of stack prefaulted");
    } else {
      notes.push_back(fmt::format("mlockall: {} (raise `ulimit -l` or grant CAP_IPC_LOCK); memory not locked",
                                  std::strerror(errno)));
    }
  }
  if (options.fifo_priority > 0) {
    sched_param param{};
    param.sched_priority = std::clamp(options.fifo_priority, sched_get_priority_min(SCHED_FIFO),
                                      sched_get_priority_max(SCHED_FIFO));
    if (sched_setscheduler(0, SCHED_FIFO, &param) == 0) {
      notes.push_back(fmt::format("SCHED_FIFO priority {}", param.sched_priority));
    } else {
      notes.push_back(fmt::format("SCHED_FIFO {}: {} (run as root, or grant CAP_SYS_NICE or an rtprio limit in "
                                  "/etc/security/limits.conf); running with the default scheduler",
                                  param.sched_priority, std::strerror(errno)));
    }
  }
  return notes;
}

void LoopRecorder::Reserve(std::size_t ticks) {
  scheduled_.assign(ticks, 0);
  wake_.assign(ticks, 0);
  done_.assign(ticks, 0);
  flags_.assign(ticks, 0);
  size_ = 0;
}

void LoopRecorder::Record(std::int64_t scheduled_ns, std::int64_t wake_ns, std::int64_t done_ns,
                          std::uint8_t flags) noexcept {
  if (size_ >= scheduled_.size()) return;
  scheduled_[size_] = scheduled_ns;
  wake_[size_] = wake_ns;
  done_[size_] = done_ns;
  flags_[size_] = flags;
  ++size_;
}

LoopStatistics LoopRecorder::Summarize(double period) const {
  LoopStatistics s;
  s.period = period;
  s.ticks = static_cast<long long>(size_);
  if (size_ == 0) return s;
  std::vector<double> latency(size_), compute(size_);
  double jitter_sq = 0.0;
  long long overrun_streak = 0, missed_streak = 0;
  for (std::size_t i = 0; i < size_; ++i) {
    latency[i] = Seconds(wake_[i] - scheduled_[i]);
    compute[i] = Seconds(done_[i] - wake_[i]);
    if (i > 0) {
      const double jitter = Seconds(wake_[i] - wake_[i - 1]) - period;
      jitter_sq += jitter * jitter;
      s.jitter_max_abs = std::max(s.jitter_max_abs, std::abs(jitter));
    }
    const bool overrun = (flags_[i] & kTickOverrun) != 0;
    const bool missed = (flags_[i] & kTickMissedSample) != 0;
    s.overruns += overrun ? 1 : 0;
    s.missed_samples += missed ? 1 : 0;
    overrun_streak = overrun ? overrun_streak + 1 : 0;
    missed_streak = missed ? missed_streak + 1 : 0;
    s.max_overrun_streak = std::max(s.max_overrun_streak, overrun_streak);
    s.max_missed_streak = std::max(s.max_missed_streak, missed_streak);
  }
  if (size_ > 1) s.jitter_rms = std::sqrt(jitter_sq / static_cast<double>(size_ - 1));
  double latency_sum = 0.0, compute_sum = 0.0;
  for (std::size_t i = 0; i < size_; ++i) {
    latency_sum += latency[i];
    compute_sum += compute[i];
  }
  s.latency_mean = latency_sum / static_cast<double>(size_);
  s.compute_mean = compute_sum / static_cast<double>(size_);
  std::sort(latency.begin(), latency.end());
  std::sort(compute.begin(), compute.end());
  s.latency_p50 = Quantile(latency, 0.5);
  s.latency_p99 = Quantile(latency, 0.99);
  s.latency_p999 = Quantile(latency, 0.999);
  s.latency_max = latency.back();
  s.compute_p99 = Quantile(compute, 0.99);
  s.compute_max = compute.back();
  return s;
}

void LoopRecorder::Columns(std::vector<double>* scheduled, std::vector<double>* latency,
                           std::vector<double>* compute, std::vector<double>* flags) const {
  scheduled->resize(size_);
  latency->resize(size_);
  compute->resize(size_);
  flags->resize(size_);
  const std::int64_t t0 = size_ > 0 ? scheduled_[0] : 0;
  for (std::size_t i = 0; i < size_; ++i) {
    (*scheduled)[i] = Seconds(scheduled_[i] - t0);
    (*latency)[i] = Seconds(wake_[i] - scheduled_[i]);
    (*compute)[i] = Seconds(done_[i] - wake_[i]);
    (*flags)[i] = static_cast<double>(flags_[i]);
  }
}

namespace {

std::atomic<bool> g_stop_requested{false};

extern "C" void RequestStop(int) { g_stop_requested.store(true); }

}  // namespace

void StopOnSignals::Install() {
  std::signal(SIGINT, RequestStop);
  std::signal(SIGTERM, RequestStop);
  installed_ = true;
}

StopOnSignals::~StopOnSignals() {
  if (!installed_) return;
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);
}

const std::atomic<bool>& StopOnSignals::requested() noexcept { return g_stop_requested; }

}  // namespace mb

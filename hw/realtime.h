#pragma once
// Real-time helpers for the HIL loop: the monotonic clock, sleeping on an absolute schedule, SCHED_FIFO and
// memory locking, and per-tick timing records with their statistics (wake-up latency, period jitter, compute
// time, overruns). Linux (POSIX clock_nanosleep, sched_setscheduler, mlockall).

#include <atomic>
#include <cstdint>
#include <string>
#include <vector>

namespace mb {

/// CLOCK_MONOTONIC now [ns].
std::int64_t MonotonicNanoseconds() noexcept;
/// Sleeps until CLOCK_MONOTONIC reaches `deadline_ns` (clock_nanosleep with TIMER_ABSTIME, so the schedule
/// does not drift with the time spent computing); returns at once if it is already past. noexcept.
void SleepUntil(std::int64_t deadline_ns) noexcept;

/// Scheduling of the calling thread for a real-time loop.
struct RealTimeOptions {
  int fifo_priority = 0;     ///< SCHED_FIFO priority 1–99; 0 = keep the default scheduler
  bool lock_memory = false;  ///< mlockall(MCL_CURRENT | MCL_FUTURE) and prefault 256 KiB of stack
};

/// Applies `options` to the calling thread/process. Never throws for a missing privilege (a loop without
/// SCHED_FIFO still runs, with more jitter): returns one line per setting saying what was done or why it
/// failed (e.g. "SCHED_FIFO 80: not permitted (run as root or grant CAP_SYS_NICE / an rtprio limit)").
std::vector<std::string> ApplyRealTimeOptions(const RealTimeOptions& options);

/// The safe stop a signal requests (`hil`, `virtual-stage`): from Install() until this object ends, SIGINT and SIGTERM
/// set requested() (one process-wide flag, which the loop polls) instead of ending the process; then their default
/// actions come back. The flag is never reset: one loop per process.
class StopOnSignals final {
 public:
  StopOnSignals() = default;
  StopOnSignals(const StopOnSignals&) = delete;
  StopOnSignals& operator=(const StopOnSignals&) = delete;
  ~StopOnSignals();

  /// From now on, SIGINT and SIGTERM set requested().
  void Install();
  /// True once SIGINT or SIGTERM arrived while installed.
  static const std::atomic<bool>& requested() noexcept;

 private:
  bool installed_ = false;
};

/// How one tick of the loop went: a bit set of these flags (0 = on time with fresh inputs).
inline constexpr std::uint8_t kTickMissedSample = 1;  ///< no fresh inputs this tick
inline constexpr std::uint8_t kTickOverrun = 2;       ///< outputs written after the next tick was due

/// Summary statistics of a loop run. Times in seconds.
struct LoopStatistics {
  long long ticks = 0;
  double period = 0.0;
  /// Wake-up latency: wake − scheduled, ≥ 0 for a sleeping clock.
  double latency_mean = 0.0, latency_p50 = 0.0, latency_p99 = 0.0, latency_p999 = 0.0, latency_max = 0.0;
  /// Period jitter: (wake_k − wake_{k−1}) − period.
  double jitter_rms = 0.0, jitter_max_abs = 0.0;
  /// Compute time: outputs written − wake (I/O exchange + controller step).
  double compute_mean = 0.0, compute_p99 = 0.0, compute_max = 0.0;
  long long overruns = 0;         ///< ticks whose outputs were written after the next tick was due
  long long missed_samples = 0;   ///< ticks without fresh inputs
  long long max_overrun_streak = 0;
  long long max_missed_streak = 0;
};

/// Per-tick timing records in storage allocated once (Reserve), so Record is allocation-free in the loop.
class LoopRecorder {
 public:
  /// Allocates room for `ticks` records. Not real time.
  void Reserve(std::size_t ticks);
  /// Records one tick. Beyond the reserved size records are dropped (counted). Real time: noexcept.
  void Record(std::int64_t scheduled_ns, std::int64_t wake_ns, std::int64_t done_ns, std::uint8_t flags) noexcept;
  std::size_t size() const { return size_; }
  /// Statistics over the recorded ticks, `period` [s]. Not real time (sorts copies).
  LoopStatistics Summarize(double period) const;
  /// Per-tick columns: scheduled time [s] relative to the first, latency [s], compute [s], flags.
  void Columns(std::vector<double>* scheduled, std::vector<double>* latency, std::vector<double>* compute,
               std::vector<double>* flags) const;

 private:
  std::vector<std::int64_t> scheduled_, wake_, done_;
  std::vector<std::uint8_t> flags_;
  std::size_t size_ = 0;
};

}  // namespace mb

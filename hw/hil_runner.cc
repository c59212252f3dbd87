#include "hw/hil_runner.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

namespace mb {

namespace {
bool IsMultiple(double value, double period) {
  const double ratio = value / period;
  return std::abs(ratio - std::round(ratio)) <= 1e-9 * std::max(1.0, std::abs(ratio));
}
}  // namespace

double HilLoopPeriod(const Diagram& diagram) {
  double period = 0.0;
  for (const auto& block : diagram.blocks()) {
    if (block->num_continuous_states() > 0) {
      throw std::invalid_argument(fmt::format(
          "diagram '{}': block '{}' has {} continuous state(s); in HIL only the controller runs, at the board's "
          "sample rate: move continuous dynamics into the replaced plant subsystem or use a discrete block "
          "(e.g. discrete_transfer_function, pd_controller with a sampleTime)",
          diagram.name(), block->name(), block->num_continuous_states()));
    }
    if (block->sample_time().is_discrete()) {
      period = period == 0.0 ? block->sample_time().period : std::min(period, block->sample_time().period);
    }
  }
  if (period == 0.0) {
    throw std::invalid_argument(fmt::format("diagram '{}' has no discrete block: give the controller and the HIL "
                                            "blocks a \"sampleTime\" (the loop runs at the fastest one)",
                                            diagram.name()));
  }
  for (const auto& block : diagram.blocks()) {
    const SampleTime& st = block->sample_time();
    if (!st.is_discrete()) continue;
    if (!IsMultiple(st.period, period) || !IsMultiple(st.offset, period)) {
      throw std::invalid_argument(fmt::format("diagram '{}': block '{}' has sample time {}, not a multiple of the "
                                              "loop period {} s (the fastest discrete block)",
                                              diagram.name(), block->name(), st.ToString(), period));
    }
  }
  return period;
}

HilResult RunHilLoop(const Diagram& diagram, IoBoard& board, const HilOptions& options) {
  HilResult result;
  const double period = HilLoopPeriod(diagram);
  result.period = period;
  const double t0 = diagram.experiment().start_time;
  const auto ticks = static_cast<long long>(std::llround((diagram.experiment().stop_time - t0) / period));

  // Everything that allocates happens here, before the board starts.
  Simulator simulator(diagram);
  simulator.Initialize();  // outputs at t0 from the zero-referenced counts; reserves the whole log
  result.timing.Reserve(static_cast<std::size_t>(std::max(0LL, ticks)));
  result.realtime_notes = ApplyRealTimeOptions(options.realtime);
  board.Start(period);

  const std::int64_t period_ns = std::llround(period * 1e9);
  long long missed_streak = 0;
  long long overrun_streak = 0;
  long long k = 0;
  const char* stop_reason = nullptr;  // static strings only: no allocation in the loop
  try {
    if (!board.WriteOutputs()) stop_reason = "the board refused the first output write";
    while (stop_reason == nullptr && k < ticks) {
      if (options.stop_request != nullptr && options.stop_request->load(std::memory_order_relaxed)) {
        stop_reason = "stop requested (SIGINT/SIGTERM)";
        break;
      }
      SampleTiming timing;
      const SampleStatus status = board.WaitForSample(&timing);
      if (status == SampleStatus::kFault) {
        stop_reason = "board fault while reading the inputs";
        break;
      }
      ++k;
      simulator.AdvanceTo(t0 + static_cast<double>(k) * period);
      const bool written = board.WriteOutputs();
      const std::int64_t done = MonotonicNanoseconds();
      std::uint8_t flags = 0;
      if (status == SampleStatus::kMissed) flags |= kTickMissedSample;
      if (done > timing.scheduled_ns + period_ns) flags |= kTickOverrun;
      result.timing.Record(timing.scheduled_ns, timing.wake_ns, done, flags);
      missed_streak = (flags & kTickMissedSample) != 0 ? missed_streak + 1 : 0;
      overrun_streak = (flags & kTickOverrun) != 0 ? overrun_streak + 1 : 0;
      if (!written) {
        stop_reason = "board fault while writing the outputs";
      } else if (missed_streak >= options.max_missed_streak) {
        stop_reason = "watchdog: too many consecutive samples without fresh inputs (the stage or board stopped "
                      "answering)";
      } else if (overrun_streak >= options.max_overrun_streak) {
        stop_reason = "overrun streak: the loop missed its deadline too many times in a row";
      }
    }
  } catch (...) {
    board.SafeStop();
    throw;
  }
  board.SafeStop();

  result.completed = stop_reason == nullptr;
  if (stop_reason != nullptr) {
    result.stop_reason = fmt::format("{} (safe stop at t = {:.4f} s, tick {}: all outputs zeroed)", stop_reason,
                                     t0 + static_cast<double>(k) * period, k);
  }
  result.stop_time = t0 + static_cast<double>(k) * period;
  result.log = simulator.log();
  result.statistics = result.timing.Summarize(period);
  try {
    result.metrics = Simulator::ComputeMetrics(diagram, result.log);
  } catch (const std::invalid_argument& e) {
    result.metrics_error = e.what();
  }
  return result;
}

}  // namespace mb

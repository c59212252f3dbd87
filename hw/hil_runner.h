#pragma once
// The hardware-in-the-loop runner: runs the discrete (controller) part of a diagram in real time against an
// I/O board. Each tick k of the board's clock: WaitForSample (the encoder counts of t_k are latched) →
// Simulator::AdvanceTo(t_k) (the encoder_input blocks read the counts, the controller computes, the
// analog_output blocks buffer their clamped voltages) → WriteOutputs. Safe stop (all outputs zero) on any
// fault: a streak of missed samples (watchdog on the link), a streak of overruns, a board error, an external
// stop request (SIGINT/SIGTERM), or an exception. The signals are logged exactly as `run` logs them.
// Real-time discipline inside the loop: no allocation (the Simulator reserves its log in Initialize, the
// timing records are reserved before the loop), no lock, no exception on the normal path.

#include <atomic>
#include <map>
#include <string>
#include <vector>

#include "engine/simulator.h"
#include "hw/board.h"
#include "hw/realtime.h"

namespace mb {

/// The longest run `hil --duration` accepts [s]: a day (a longer run is refused when the options are parsed; its
/// log is also bounded by the simulator's --max-steps check).
inline constexpr double kHilMaxDuration = 86400.0;

struct HilOptions {
  int max_missed_streak = 20;   ///< consecutive ticks without fresh inputs that trigger the safe stop
  int max_overrun_streak = 10;  ///< consecutive overruns (outputs written after the next tick was due)
  RealTimeOptions realtime;
  /// Polled once per tick; true requests a safe stop (set from a signal handler). May be null.
  const std::atomic<bool>* stop_request = nullptr;
};

struct HilResult {
  SignalLog log;                          ///< the diagram's logged signals, as `run` writes them
  std::map<std::string, double> metrics;  ///< the diagram's metrics over the logged run
  std::string metrics_error;              ///< why metrics are missing (e.g. stopped before their window)
  LoopStatistics statistics;              ///< latency, jitter, compute time, overruns, missed samples
  LoopRecorder timing;                    ///< per-tick timing records
  bool completed = false;                 ///< ran to the stop time without a fault
  std::string stop_reason;                ///< the fault that caused the safe stop ("" when completed)
  double stop_time = 0.0;                 ///< diagram time of the last tick run [s]
  double period = 0.0;                    ///< the loop's sample period [s]
  std::vector<std::string> realtime_notes;  ///< what ApplyRealTimeOptions did
};

/// The loop period of a diagram for HIL: the fastest discrete sample period. The diagram must have no
/// continuous states (the plant is the hardware; discretise controller filters) and every discrete period and
/// offset must be a multiple of it.
/// @throws std::invalid_argument naming the offending block and the fix.
double HilLoopPeriod(const Diagram& diagram);

/// Runs `diagram` (already built with the board attached, hw/board_registry.h) in real time against `board`
/// from its start to its stop time. The board is started here and always safe-stopped before returning.
/// @throws std::invalid_argument (HilLoopPeriod) or std::runtime_error from Board::Start, before the loop;
/// an exception from a block inside the loop is rethrown after the safe stop.
HilResult RunHilLoop(const Diagram& diagram, IoBoard& board, const HilOptions& options);

}  // namespace mb

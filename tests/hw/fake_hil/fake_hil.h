#pragma once
// The behaviour behind the test double of the Quanser HIL C API (hil.h here): one simulated board with an encoder
// on a rigid-body plant driven by an analog output through an amplifier, a watchdog, and a recorder of every call.
// Tests reset it, run hw/quanser_board.cc (compiled against hil.h) and read back what was called and where the
// plant went. Faults can be injected: a failing hil_open or hil_task_start, a read that times out, a watchdog
// that has expired.
//
// The plant (own physics, a few lines): M ẍ = K_a·V − B ẋ with the analog output V of channel 0 held over each
// sample period (zero-order hold, integrated exactly); encoder channel 0 reads round(x · counts_per_metre) minus the
// count set by hil_set_encoder_counts. The clock is simulated: hil_task_read_encoder advances the plant by one
// period 1/frequency per sample and returns at once, so results do not depend on the test machine's timing (a real
// board's read blocks until the hardware clock ticks). When the watchdog has expired, the analog outputs hold
// their expiration state, whatever is written.
//
// Real-time discipline of the double itself: the calls allocate nothing (the call record has a fixed capacity,
// reserved by Reset), so an allocation counted inside the loop is the backend's.

#include <cstddef>
#include <cstdint>
#include <vector>

namespace mb::fake_hil {

/// The HIL functions the backend calls, in the order DESIGN.md expects them for one run.
enum class Call : std::uint8_t {
  kOpen,
  kSetEncoderCounts,
  kWriteAnalog,
  kWatchdogSetAnalogExpirationState,
  kWatchdogStart,
  kTaskCreateEncoderReader,
  kTaskStart,
  kTaskReadEncoder,
  kWatchdogReload,
  kReadDigital,
  kWriteDigital,
  kTaskStop,
  kTaskDelete,
  kWatchdogStop,
  kWatchdogClear,
  kClose,
};
/// The C function's name, e.g. "hil_task_read_encoder".
const char* ToString(Call call);

/// One recorded call: the function, its result, and for hil_write_analog the volts of channel 0.
struct CallRecord {
  Call call = Call::kOpen;
  int result = 0;
  double volts = 0.0;
};

/// The rigid body behind the board (defaults: the paper's nominal plant and diagrams/hil/subsystems/hil_io.json).
struct Plant {
  double mass = 0.2621;           ///< M [kg]
  double damping = 3.0;           ///< B [N·s/m]
  double newtons_per_volt = 1.0;  ///< amplifier gain K_a [N/V]
  double counts_per_metre = 1e7;  ///< encoder resolution [counts/m]
};

enum class Fault {
  kNone,
  kOpenFails,        ///< hil_open returns an error (no board)
  kTaskStartFails,   ///< hil_task_start returns an error
  kReadTimeout,      ///< hil_task_read_encoder returns a timeout error at sample `at_sample`
  kWatchdogExpired,  ///< the watchdog expires before sample `at_sample`: outputs go to the expiration state and
                     ///< hil_watchdog_reload returns 0 from then on
};

/// The error code the double returns for an injected fault (the SDK's codes are negative).
inline constexpr int kInjectedError = -1073;

/// Puts the board in its initial state (closed, plant at rest at x = 0), clears the record and arms `fault`.
/// Allocates the record's capacity (`record_capacity` calls; more are counted, not stored).
void Reset(const Plant& plant = {}, Fault fault = Fault::kNone, long at_sample = 0,
           std::size_t record_capacity = 1u << 16);

/// Every recorded call in order.
std::vector<CallRecord> Record();
/// The functions only, in order.
std::vector<Call> Calls();
/// Calls made beyond the record's capacity (not stored).
long Unrecorded();

/// The plant's state and the board's, for checks.
double Position();         ///< x [m]
double Velocity();         ///< ẋ [m/s]
double AppliedVolts();     ///< the voltage the amplifier applies now (channel 0, or the expiration state) [V]
long SamplesRead();        ///< samples returned by hil_task_read_encoder
double TaskFrequency();    ///< the frequency given to hil_task_start [Hz]
double WatchdogTimeout();  ///< the timeout given to hil_watchdog_start [s]
bool WatchdogExpired();
bool IsOpen();

/// Called (if set) at the first hil_task_read_encoder and at hil_task_stop: an allocation count taken there brackets
/// the real-time loop. Plain function pointers: setting them allocates nothing.
void SetLoopHooks(void (*on_first_read)(), void (*on_task_stop)());

}  // namespace mb::fake_hil

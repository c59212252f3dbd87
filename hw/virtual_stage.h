#pragma once
// The virtual stage: the plant of a HIL diagram simulated in real time in its own process, answering the UDP
// board protocol (hw/udp_protocol.h) on 127.0.0.1, so that `motionblocks hil --board udp` exercises the whole
// HIL path — sockets, clocks, watchdogs, safe stop — without hardware (docs/hil.md).
//
// The plant diagram's time follows CLOCK_MONOTONIC since the stage started. The stage advances it at every
// 1 kHz tick and at every packet: a sample request is answered with the encoder counts of the plant at that
// instant, analog outputs drive the plant's force inputs from the instant they arrive (zero-order hold).
// Watchdog: when no outputs packet arrived for `watchdog_timeout`, the forces are zeroed (an amplifier's
// enable dropping out), until the next outputs packet.
// Fault: an outputs packet whose volts on a wired channel are not finite or exceed that channel's limit (the
// analog_output's `limit` in the I/O file) is not applied: the forces are zeroed, the stage stops, and
// VirtualStageReport::fault names the packet, the channel and the value (`virtual-stage` exits 1 with it).

#include <atomic>
#include <cstdint>
#include <filesystem>
#include <iosfwd>
#include <limits>
#include <memory>
#include <string>
#include <vector>

#include "engine/diagram.h"
#include "engine/diagram_loader.h"
#include "engine/simulator.h"
#include "hw/udp_socket.h"

namespace mb {

/// One channel of the stage's wiring: a plant connector, a board channel and the scale between them.
struct StageChannel {
  std::string connector;  ///< the plant diagram's output (encoders) or input (analog outputs) connector
  int channel = 0;        ///< board channel
  double scale = 1.0;     ///< counts per metre (encoders) or newtons per volt (analog outputs)
  /// Analog outputs: the most volts a packet may carry, |v| ≤ limit [V] (the block's clamp); more is a fault.
  double limit = std::numeric_limits<double>::infinity();
};

/// How the plant is wired to the board: which plant outputs the encoders measure and which plant inputs the
/// analog outputs drive, with the same scales the HIL blocks use.
struct StageWiring {
  std::vector<StageChannel> encoders;
  std::vector<StageChannel> analog_outputs;

  /// Reads the wiring from the HIL I/O subsystem file that replaces the plant (e.g.
  /// diagrams/hil/subsystems/hil_io.json): every encoder_input element wired to an output connector C gives
  /// an encoder channel measuring plant output C; every analog_output element fed from input connector C gives
  /// an analog channel driving plant input C, with the element's limit. Parameters are validated as the blocks do
  /// (defaults filled in).
  /// @throws std::runtime_error / std::invalid_argument naming the file, the element and the fix.
  static StageWiring FromIoFile(const std::filesystem::path& io_file);
};

/// The ranges VirtualStage checks its options against (and `virtual-stage` its flags, at parse time).
inline constexpr double kStageMinPeriod = 1e-5;           ///< shortest tick [s] (10 µs)
inline constexpr double kStageMaxPeriod = 1.0;            ///< longest tick [s]
inline constexpr double kStageMinWatchdog = 1e-4;         ///< shortest watchdog timeout [s]
inline constexpr double kStageMaxWatchdog = 60.0;         ///< longest watchdog timeout [s]
inline constexpr double kStageMaxDuration = 86400.0;      ///< longest finite run [s]: a day (the plant's horizon)

struct VirtualStageOptions {
  std::uint16_t port = 0;       ///< UDP port on 127.0.0.1; 0 = an ephemeral port (see VirtualStage::port)
  double period = 1e-3;         ///< the stage's real-time tick [s], in [kStageMinPeriod, kStageMaxPeriod]
  double watchdog_timeout = 0.05;  ///< zero the forces after this long without outputs [s], in [1e-4, 60]
  /// Stop after this long [s]: in (0, kStageMaxDuration], or +infinity (until stopped).
  double duration = std::numeric_limits<double>::infinity();
  /// Fault injection for tests: from this stage time on [s], every packet is dropped unanswered.
  double drop_from = std::numeric_limits<double>::infinity();
};

/// What happened during a stage run.
struct VirtualStageReport {
  double time = 0.0;              ///< stage time at the end [s]
  long long requests = 0;         ///< sample requests answered
  long long outputs = 0;          ///< outputs packets applied
  long long lost_outputs = 0;     ///< outputs packets missing according to their sequence numbers
  long long dropped = 0;          ///< packets dropped by fault injection
  long long watchdog_trips = 0;   ///< times the watchdog zeroed the forces
  /// Empty, or why the stage stopped on a fault: "outputs packet <sequence> (t = … s): analog output channel <c>
  /// carries <v> V, …" (forces zeroed before Run returned).
  std::string fault;
};

/// What `motionblocks virtual-stage` says of a run, one line: "stopped at t = … s: … sample requests answered, …
/// outputs applied, … outputs lost (sequence gaps), … packets dropped (fault injection), … watchdog trips".
std::string DescribeVirtualStageRun(const VirtualStageReport& report);

class VirtualStage {
 public:
  /// Loads the plant diagram (overrides applied), checks the wiring against its connectors and binds the
  /// socket. @throws DiagramError, std::invalid_argument (an option outside its range — period, watchdog timeout,
  /// duration, as VirtualStageOptions documents, NaN included —, a wired connector the plant lacks, listing its
  /// connectors) or std::runtime_error (socket).
  VirtualStage(const std::filesystem::path& plant_file, StageWiring wiring, VirtualStageOptions options,
               const std::vector<ParameterOverride>& overrides = {});
  ~VirtualStage();

  /// The bound UDP port on 127.0.0.1.
  std::uint16_t port() const { return socket_->port(); }
  const Diagram& plant() const { return *plant_; }
  /// The force each wired analog output applies to the plant now [N] (volts · newtons_per_volt; 0 until the first
  /// outputs packet, after the watchdog and after a fault), in StageWiring::analog_outputs order.
  const std::vector<double>& forces() const { return forces_; }

  /// Runs in real time until `stop` is set, the duration has passed or an outputs packet is a fault (see the top of
  /// this file; the report's `fault` says which); one line per event (watchdog, fault injection, fault) goes to
  /// `events`. Inside the loop nothing is allocated for a fault and nothing thrown: the packet's sequence, channel
  /// and value are kept, the text is written after the loop.
  VirtualStageReport Run(const std::atomic<bool>& stop, std::ostream& events);

 private:
  void SetForce(std::size_t analog, double volts) noexcept;  // real time: no allocation
  void AdvanceTo(double t);

  StageWiring wiring_;
  VirtualStageOptions options_;
  std::unique_ptr<Diagram> plant_;
  std::unique_ptr<Simulator> simulator_;
  std::unique_ptr<LoopbackUdpSocket> socket_;
  std::vector<SignalRef> encoder_sources_;   // per wiring_.encoders
  std::vector<double> forces_;               // per wiring_.analog_outputs [N]
  std::vector<std::size_t> force_inputs_;    // per wiring_.analog_outputs: its plant input (Simulator::HoldInput)
};

}  // namespace mb

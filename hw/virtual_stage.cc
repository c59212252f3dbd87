#include "hw/virtual_stage.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <ostream>
#include <stdexcept>

#include <fmt/format.h>

#include "engine/block_roles.h"
#include "engine/diagram_document.h"
#include "hw/realtime.h"

namespace mb {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::string ConnectorNames(const std::vector<std::string>& names) {
  std::string list;
  for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
  return list.empty() ? "(none)" : list;
}

}  // namespace

StageWiring StageWiring::FromIoFile(const fs::path& io_file) {
  const DiagramDocument io = DiagramDocument::Load(io_file);
  StageWiring wiring;
  const auto names = io.ElementNames();
  for (std::size_t i = 0; i < names.size(); ++i) {
    const std::string& name = names[i];
    const std::string type = io.TypeOf(name);
    // The I/O blocks declare their board channel in their own file (MB_REGISTER_IO_CHANNEL, engine/block_roles.h).
    const IoChannelTrait* io_channel = BlockRoleRegistry::Global().IoChannelOf(type);
    if (!io_channel) continue;
    const std::string pointer = fmt::format("/elements/{}", i);
    const Parameters p = io.ElementParameters(name);
    StageChannel channel;
    channel.channel = p.Integer("channel");
    for (const Connection& c : io.Connections()) {
      if (io_channel->measures && c.start.element == name && c.end.is_connector()) channel.connector = c.end.port;
      if (!io_channel->measures && c.end.element == name && c.start.is_connector()) channel.connector = c.start.port;
    }
    if (channel.connector.empty()) {
      throw std::invalid_argument(fmt::format(
          "{}: {}: {} '{}' is not wired to a connector of the I/O subsystem; the virtual stage needs it to know "
          "which plant signal the channel carries ({})",
          io_file.string(), pointer, type, name,
          io_channel->measures ? "connect its x to an output connector" : "feed its f from an input connector"));
    }
    channel.scale = p.Number(io_channel->scale_parameter);
    if (!io_channel->limit_parameter.empty()) channel.limit = p.Number(io_channel->limit_parameter);
    (io_channel->measures ? wiring.encoders : wiring.analog_outputs).push_back(channel);
  }
  if (wiring.encoders.empty()) {
    throw std::invalid_argument(fmt::format("{}: no encoder_input element wired to an output connector: the virtual "
                                            "stage would have nothing to measure",
                                            io_file.string()));
  }
  return wiring;
}

VirtualStage::VirtualStage(const fs::path& plant_file, StageWiring wiring, VirtualStageOptions options,
                           const std::vector<ParameterOverride>& overrides)
    : wiring_(std::move(wiring)), options_(options) {
  // Written so that NaN fails every check.
  if (!(options_.period >= kStageMinPeriod && options_.period <= kStageMaxPeriod)) {
    throw std::invalid_argument(fmt::format("virtual stage: the tick period {} s is outside [{}, {}] s: give "
                                            "--period-ms from {} to {}",
                                            options_.period, kStageMinPeriod, kStageMaxPeriod, kStageMinPeriod * 1e3,
                                            kStageMaxPeriod * 1e3));
  }
  if (!(options_.watchdog_timeout >= kStageMinWatchdog && options_.watchdog_timeout <= kStageMaxWatchdog)) {
    throw std::invalid_argument(fmt::format("virtual stage: the watchdog timeout {} s is outside [{}, {}] s: give "
                                            "--watchdog-ms from {} to {}",
                                            options_.watchdog_timeout, kStageMinWatchdog, kStageMaxWatchdog,
                                            kStageMinWatchdog * 1e3, kStageMaxWatchdog * 1e3));
  }
  if (!(options_.duration > 0.0 && (options_.duration <= kStageMaxDuration || std::isinf(options_.duration)))) {
    throw std::invalid_argument(fmt::format("virtual stage: the duration {} s is outside (0, {}] s: give --duration "
                                            "in that range, or none to run until stopped",
                                            options_.duration, kStageMaxDuration));
  }
  json j = ReadDiagramJson(plant_file);
  ApplyOverrides(&j, overrides, plant_file.string());
  // The stage runs open-ended: log only the connectors, every 10 s, into storage reserved for a day.
  DiagramDocument plant(std::move(j), plant_file.parent_path(), plant_file.string());
  plant.SetLoggedSignals({});
  plant.ClearMetrics();
  plant.SetExperiment(0.0, 86400.0, 10.0);
  plant_ = std::make_unique<Diagram>(BuildDiagram(plant.json(), plant_file.parent_path(), plant_file.string()));

  std::vector<std::string> outputs, inputs;
  for (const auto& o : plant_->outputs()) outputs.push_back(o.name);
  for (const auto& in : plant_->inputs()) inputs.push_back(in.name);
  for (const auto& e : wiring_.encoders) {
    const auto it = std::find(outputs.begin(), outputs.end(), e.connector);
    if (it == outputs.end()) {
      throw std::invalid_argument(fmt::format("{}: encoder channel {} measures '{}', but the plant has no output "
                                              "connector of that name; its outputs: {}",
                                              plant_file.string(), e.channel, e.connector, ConnectorNames(outputs)));
    }
    encoder_sources_.push_back(plant_->outputs()[static_cast<std::size_t>(it - outputs.begin())].source);
  }
  for (const auto& a : wiring_.analog_outputs) {
    const auto input = std::find(inputs.begin(), inputs.end(), a.connector);
    force_inputs_.push_back(static_cast<std::size_t>(input - inputs.begin()));
    if (input == inputs.end()) {
      throw std::invalid_argument(fmt::format("{}: analog output {} drives '{}', but the plant has no input "
                                              "connector of that name; its inputs: {}",
                                              plant_file.string(), a.channel, a.connector, ConnectorNames(inputs)));
    }
  }
  // The stage runs until it is stopped (the plant's stopTime is nominal): no run-length limit.
  SimulationLimits unlimited;
  unlimited.max_steps = std::numeric_limits<double>::infinity();
  simulator_ = std::make_unique<Simulator>(*plant_, unlimited);
  for (const auto& name : inputs) simulator_->SetInput(name, InputSeries{{0.0}, {0.0}});
  forces_.assign(wiring_.analog_outputs.size(), 0.0);
  simulator_->Initialize(0.0);
  socket_ = std::make_unique<LoopbackUdpSocket>(options_.port);
}

VirtualStage::~VirtualStage() = default;

void VirtualStage::SetForce(std::size_t analog, double volts) noexcept {
  const StageChannel& a = wiring_.analog_outputs[analog];
  forces_[analog] = volts * a.scale;
  // Held from now on, in place: no allocation in the real-time loop (the input was fed a one-point series at
  // construction; Simulator holds a series' ends).
  simulator_->HoldInput(force_inputs_[analog], forces_[analog]);
}

void VirtualStage::AdvanceTo(double t) {
  if (t > simulator_->time()) simulator_->AdvanceTo(t);
}

namespace {

// A fault seen inside the real-time loop: plain numbers, no text (formatted after the loop).
struct OutputsFault {
  bool found = false;
  std::uint32_t sequence = 0;
  double time = 0.0;
  int channel = 0;
  double volts = 0.0;
  double limit = 0.0;
};

}  // namespace

VirtualStageReport VirtualStage::Run(const std::atomic<bool>& stop, std::ostream& events) {
  VirtualStageReport report;
  OutputsFault fault;
  const auto period_ns = static_cast<std::int64_t>(std::llround(options_.period * 1e9));
  const auto watchdog_ns = static_cast<std::int64_t>(std::llround(options_.watchdog_timeout * 1e9));
  const std::int64_t start_ns = MonotonicNanoseconds();
  const auto stage_time = [&](std::int64_t now_ns) { return static_cast<double>(now_ns - start_ns) * 1e-9; };
  std::int64_t last_outputs_ns = 0;
  bool watchdog_armed = false;
  bool have_sequence = false;
  std::uint32_t last_sequence = 0;
  std::uint32_t digital_loopback = 0;
  bool drop_announced = false;
  for (long long tick = 1; !stop.load(std::memory_order_relaxed); ++tick) {
    const std::int64_t tick_ns = start_ns + tick * period_ns;
    BoardPacket packet;
    sockaddr_in peer{};
    while (socket_->ReceiveUntil(tick_ns, &packet, &peer)) {
      const std::int64_t now = MonotonicNanoseconds();
      const double t = stage_time(now);
      if (t >= options_.drop_from) {
        if (!drop_announced) {
          events << fmt::format("t = {:.3f} s: fault injection: dropping every packet from now on\n", t) << std::flush;
          drop_announced = true;
        }
        ++report.dropped;
        continue;
      }
      AdvanceTo(t);
      if (packet.type == PacketType::kSampleRequest) {
        BoardPacket reply;
        reply.type = PacketType::kSample;
        reply.sequence = packet.sequence;
        reply.timestamp_ns = now;
        reply.digital = digital_loopback;
        for (std::size_t i = 0; i < wiring_.encoders.size(); ++i) {
          const double counts = std::round(simulator_->SignalValue(encoder_sources_[i]) * wiring_.encoders[i].scale);
          const double limited = std::clamp(counts, static_cast<double>(std::numeric_limits<std::int32_t>::min()),
                                            static_cast<double>(std::numeric_limits<std::int32_t>::max()));
          reply.encoder_counts[static_cast<std::size_t>(wiring_.encoders[i].channel)] =
              static_cast<std::int32_t>(limited);
        }
        socket_->SendTo(peer, reply);
        ++report.requests;
      } else if (packet.type == PacketType::kOutputs) {
        // Volts that are not finite or beyond a channel's limit are a fault: not applied (the plant would integrate
        // them, or the solver fail on them), the stage stops below.
        for (std::size_t i = 0; i < wiring_.analog_outputs.size() && !fault.found; ++i) {
          const StageChannel& a = wiring_.analog_outputs[i];
          const double v = packet.analog_volts[static_cast<std::size_t>(a.channel)];
          if (!(std::isfinite(v) && std::abs(v) <= a.limit && std::isfinite(v * a.scale))) {
            fault = {true, packet.sequence, t, a.channel, v, a.limit};
          }
        }
        if (fault.found) break;
        // A gap in the sequence numbers is lost packets; a smaller number is a new client run (it restarts at 0).
        if (have_sequence && packet.sequence > last_sequence + 1) {
          report.lost_outputs += packet.sequence - last_sequence - 1;
        }
        last_sequence = packet.sequence;
        have_sequence = true;
        for (std::size_t i = 0; i < wiring_.analog_outputs.size(); ++i) {
          SetForce(i, packet.analog_volts[static_cast<std::size_t>(wiring_.analog_outputs[i].channel)]);
        }
        digital_loopback = packet.digital;
        last_outputs_ns = now;
        watchdog_armed = true;
        ++report.outputs;
      }
    }
    if (fault.found) break;
    const std::int64_t now = MonotonicNanoseconds();
    AdvanceTo(stage_time(now));
    if (watchdog_armed && now - last_outputs_ns > watchdog_ns) {
      for (std::size_t i = 0; i < wiring_.analog_outputs.size(); ++i) SetForce(i, 0.0);
      watchdog_armed = false;
      have_sequence = false;
      ++report.watchdog_trips;
      events << fmt::format("t = {:.3f} s: watchdog: no outputs for {:.0f} ms, forces zeroed\n", stage_time(now),
                            options_.watchdog_timeout * 1e3)
             << std::flush;
    }
    if (stage_time(now) >= options_.duration) break;
  }
  if (fault.found) {
    for (std::size_t i = 0; i < wiring_.analog_outputs.size(); ++i) SetForce(i, 0.0);
    report.fault = fmt::format(
        "outputs packet {} (t = {:.3f} s): analog output channel {} carries {} V, {}; the packet was not applied, "
        "every force is zeroed and the stage stopped: check the controller and its analog_output (a finite command "
        "within ±limit), then start the stage again",
        fault.sequence, fault.time, fault.channel, fault.volts,
        !std::isfinite(fault.volts)      ? std::string("not a finite voltage")
        : std::abs(fault.volts) > fault.limit ? fmt::format("beyond the channel's limit of ±{} V", fault.limit)
                                              : std::string("a force beyond the range of a double"));
    events << fmt::format("t = {:.3f} s: fault: {}\n", fault.time, report.fault) << std::flush;
  }
  report.time = simulator_->time();
  return report;
}

std::string DescribeVirtualStageRun(const VirtualStageReport& r) {
  return fmt::format("stopped at t = {:.3f} s: {} sample requests answered, {} outputs applied, {} outputs lost "
                     "(sequence gaps), {} packets dropped (fault injection), {} watchdog trips",
                     r.time, r.requests, r.outputs, r.lost_outputs, r.dropped, r.watchdog_trips);
}

}  // namespace mb

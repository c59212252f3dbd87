// motionblocks virtual-stage PLANT.json --io HIL_IO.json [--port P] [--watchdog-ms MS] [--duration S]
//                            [--drop-from S] [--set block.param=value …]
// Runs the plant diagram in real time as a separate process that speaks the UDP board protocol on 127.0.0.1
// (hw/virtual_stage.h, docs/hil.md): the no-hardware path of `motionblocks hil --board udp`.

#include <iostream>

#include <fmt/format.h>

#include "hw/realtime.h"
#include "hw/virtual_stage.h"
#include "tools/commands/cli_options.h"
#include "tools/commands/command_registry.h"

namespace mb {

namespace {

struct VirtualStageCommandOptions {
  std::string plant;
  std::string io;
  std::vector<std::string> overrides;
  int port = 0;
  double period_ms = 1.0;
  double watchdog_ms = 50.0;
  double duration = 0.0;
  double drop_from = -1.0;
  int fifo_priority = 0;
};

void RunVirtualStage(const VirtualStageCommandOptions& o) {
  const std::vector<ParameterOverride> overrides = ParseOverrides(o.overrides);
  VirtualStageOptions options;
  options.port = static_cast<std::uint16_t>(o.port);
  options.period = o.period_ms * 1e-3;
  options.watchdog_timeout = o.watchdog_ms * 1e-3;
  if (o.duration > 0.0) options.duration = o.duration;  // 0: not given (the check refuses anything else ≤ 0)
  if (o.drop_from >= 0.0) options.drop_from = o.drop_from;
  VirtualStage stage(o.plant, StageWiring::FromIoFile(o.io), options, overrides);
  for (const auto& note : ApplyRealTimeOptions({o.fifo_priority, false})) std::cout << note << "\n";
  StopOnSignals signals;  // from here until the stage stopped and said so
  signals.Install();
  // The first line names the port (tests and scripts read it when --port 0 picked a free one).
  std::cout << fmt::format("virtual-stage listening on 127.0.0.1:{}\n", stage.port());
  std::cout << fmt::format("plant '{}' from {}, tick {} ms, watchdog {} ms; stop with Ctrl-C\n",
                           stage.plant().name(), o.plant, o.period_ms, o.watchdog_ms)
            << std::flush;
  const VirtualStageReport r = stage.Run(StopOnSignals::requested(), std::cout);
  std::cout << DescribeVirtualStageRun(r) << "\n";
  if (!r.fault.empty()) throw std::runtime_error("virtual-stage: " + r.fault);
}

void SetupVirtualStageCommand(CLI::App& app) {
  auto options = std::make_shared<VirtualStageCommandOptions>();
  auto* cmd = app.add_subcommand("virtual-stage",
                                 "Run a plant diagram in real time behind the UDP board protocol on 127.0.0.1 (the "
                                 "no-hardware end of `hil --board udp`)");
  cmd->add_option("diagram", options->plant, "plant diagram JSON (the subsystem file `hil --replace` swaps out)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--io", options->io,
                  "the HIL I/O subsystem file: its encoder_input/analog_output elements give the channels, scales "
                  "and plant connectors")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--port", options->port, "UDP port on 127.0.0.1 (0 = a free one, printed)")
      ->check(CLI::Range(0, 65535))
      ->capture_default_str();
  cmd->add_option("--period-ms", options->period_ms,
                  fmt::format("real-time tick [ms], from {} to {}", kStageMinPeriod * 1e3, kStageMaxPeriod * 1e3))
      ->check(FiniteRange(kStageMinPeriod * 1e3, kStageMaxPeriod * 1e3))
      ->capture_default_str();
  cmd->add_option("--watchdog-ms", options->watchdog_ms,
                  fmt::format("zero the forces after this long without outputs [ms], from {} to {}",
                              kStageMinWatchdog * 1e3, kStageMaxWatchdog * 1e3))
      ->check(FiniteRange(kStageMinWatchdog * 1e3, kStageMaxWatchdog * 1e3))
      ->capture_default_str();
  cmd->add_option("--duration", options->duration,
                  fmt::format("stop after this many seconds, more than 0 and at most {} (default: run until stopped)",
                              kStageMaxDuration))
      ->check(FiniteRange(0.0, kStageMaxDuration, /*low_open=*/true));
  cmd->add_option("--drop-from", options->drop_from,
                  "fault injection: drop every packet from this many seconds on (tests the safe stop)")
      ->check(FiniteRange(0.0, kStageMaxDuration));
  AddSetOption(cmd, &options->overrides, "plant parameter override block.param=value (repeatable)");
  AddFifoOption(cmd, &options->fifo_priority);
  cmd->callback([options] { RunVirtualStage(*options); });
}

}  // namespace

MB_REGISTER_COMMAND(virtual_stage, {"virtual-stage", CommandGroup::kHardware, &SetupVirtualStageCommand, false})

}  // namespace mb

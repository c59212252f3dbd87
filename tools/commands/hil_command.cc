// motionblocks hil DIAGRAM --board quanser|udp --replace plant=HIL_IO.json [--port P] [--duration S]
//                  [--fifo PRIO] [--lock-memory] [--set block.param=value …] [--out DIR]
// Swaps the plant subsystem for the I/O subsystem (HIL blocks), opens the board and runs the rest of the
// diagram unchanged at its sample time in real time, writing signals.csv, timing.csv and summary.json into --out:
// one library call, RunHilSession (tools/hil/hil_session.h, docs/hil.md). This file fills its settings, stops the
// loop safely on SIGINT/SIGTERM and prints; a safe stop is an error exit after the files are written.

#include <cstdint>
#include <iostream>
#include <memory>
#include <stdexcept>
#include <string>

#include <fmt/format.h>

#include "hw/realtime.h"
#include "tools/commands/cli_options.h"
#include "tools/commands/command_registry.h"
#include "tools/hil/hil_session.h"

namespace mb {

namespace {

// The session's settings (their defaults are the library's), and the options given in other units or types.
struct HilCommandOptions {
  HilSessionSettings settings;
  std::string board;
  std::string out = settings.out.string();
  int port = settings.udp.stage_port;
  double reply_timeout_ms = settings.udp.reply_timeout * 1e3;
  double hardware_watchdog_ms = settings.quanser.watchdog_timeout * 1e3;
};

void RunHil(const HilCommandOptions& o) {
  HilSessionSettings settings = o.settings;
  settings.board = ParseHilBoardKind(o.board);
  settings.out = o.out;
  settings.udp.stage_port = static_cast<std::uint16_t>(o.port);
  settings.udp.reply_timeout = o.reply_timeout_ms * 1e-3;
  settings.quanser.watchdog_timeout = o.hardware_watchdog_ms * 1e-3;
  StopOnSignals signals;
  const HilSessionResult result = RunHilSession(
      settings, &StopOnSignals::requested(),
      [](const std::string& dropped) { std::cerr << DescribeHilDroppedItem(dropped) << "\n"; },
      [&signals](const HilSessionStart& start) {
        signals.Install();
        std::cout << DescribeHilSessionStart(start) << "\n" << std::flush;
      });
  PrintHilSessionSummary(result, o.out, std::cout);
  if (!result.run.completed) throw std::runtime_error("hil: " + result.run.stop_reason);
}

void SetupHilCommand(CLI::App& app) {
  auto options = std::make_shared<HilCommandOptions>();
  HilSessionSettings& s = options->settings;
  auto* cmd = app.add_subcommand("hil",
                                 "Hardware in the loop: swap the plant subsystem for board I/O and run the controller "
                                 "in real time (Quanser board, or the UDP virtual stage)");
  cmd->add_option("diagram", s.diagram, "diagram JSON file (its plant is a subsystem element)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--board", options->board, "I/O board: quanser or udp (the virtual stage)")
      ->required()
      ->check(CLI::IsMember({"quanser", "udp"}));
  cmd->add_option("--replace", s.replacements,
                  "ELEMENT=FILE: swap subsystem ELEMENT for FILE, e.g. plant=diagrams/hil/subsystems/hil_io.json")
      ->required();
  AddSetOption(cmd, &s.overrides);
  cmd->add_option("--duration", s.duration,
                  fmt::format("run this many seconds, more than 0 and at most {} (default: the diagram's stop time)",
                              kHilMaxDuration))
      ->check(FiniteRange(0.0, kHilMaxDuration, /*low_open=*/true));
  cmd->add_option("--out", options->out, "output folder")->capture_default_str();
  cmd->add_option("--port", options->port, "udp: the virtual stage's port on 127.0.0.1")->check(CLI::Range(1, 65535));
  cmd->add_option("--reply-timeout-ms", options->reply_timeout_ms,
                  "udp: wait this long for the stage's sample, then count a missed sample [ms], from 0.001 to 1000")
      ->check(FiniteRange(1e-3, 1e3))
      ->capture_default_str();
  cmd->add_option("--quanser-board", s.quanser.board_type, "quanser: board type for hil_open")
      ->capture_default_str();
  cmd->add_option("--quanser-id", s.quanser.board_identifier, "quanser: board identifier")->capture_default_str();
  cmd->add_option("--encoders", s.quanser.encoder_channels, "quanser: encoder channels read (0 … n−1)")
      ->check(CLI::Range(1, kMaxEncoderChannels))
      ->capture_default_str();
  cmd->add_option("--analog-outputs", s.quanser.analog_outputs, "quanser: analog outputs written (0 … n−1)")
      ->check(CLI::Range(0, kMaxAnalogOutputs))
      ->capture_default_str();
  cmd->add_option("--hardware-watchdog-ms", options->hardware_watchdog_ms,
                  "quanser: the board's watchdog zeroes the outputs after this long without a write [ms], from 0.1 "
                  "to 60000")
      ->check(FiniteRange(0.1, 6e4))
      ->capture_default_str();
  cmd->add_option("--max-missed", s.loop.max_missed_streak, "safe stop after this many consecutive missed samples")
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
  cmd->add_option("--max-overruns", s.loop.max_overrun_streak, "safe stop after this many consecutive overruns")
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
  AddFifoOption(cmd, &s.loop.realtime.fifo_priority);
  cmd->add_flag("--lock-memory", s.loop.realtime.lock_memory, "mlockall the process and prefault the stack");
  cmd->callback([options] { RunHil(*options); });
}

}  // namespace

MB_REGISTER_COMMAND(hil, {"hil", CommandGroup::kHardware, &SetupHilCommand, false})

}  // namespace mb

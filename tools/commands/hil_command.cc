// motionblocks hil DIAGRAM --board quanser|udp --replace plant=HIL_IO.json [--port P] [--duration S]
//                  [--fifo PRIO] [--lock-memory] [--set block.param=value …] [--out DIR]
// Swaps the plant subsystem for the I/O subsystem (HIL blocks), opens the board and runs the rest of the
// diagram unchanged at its sample time in real time (hw/hil_runner.h, docs/hil.md). Writes signals.csv (as
// `run` does, so `compare` reads it), timing.csv (per tick) and summary.json (metrics, loop statistics, the
// stop reason). A safe stop is an error exit after the files are written. The files an earlier run left in --out are
// removed before the loop starts (a run killed in the loop leaves none of them).

#include <csignal>
#include <iostream>
#include <memory>

#include <fmt/format.h>

#include "engine/diagram_document.h"
#include "engine/diagram_loader.h"
#include "engine/file_access.h"
#include "hw/board_registry.h"
#include "hw/hil_diagram.h"
#include "hw/hil_runner.h"
#include "hw/quanser_board.h"
#include "hw/udp_board.h"
#include "tools/commands/cli_options.h"
#include "tools/commands/command_registry.h"
#include "tools/report/output_files.h"

namespace mb {

namespace fs = std::filesystem;

namespace {

std::atomic<bool> g_hil_stop{false};

extern "C" void StopHil(int) { g_hil_stop.store(true); }

struct HilCommandOptions {
  std::string diagram;
  std::string board;
  std::vector<std::string> replacements;
  std::vector<std::string> overrides;
  double duration = 0.0;
  std::string out = "out/hil";
  // UDP virtual board
  int port = 0;
  double reply_timeout_ms = 0.5;
  // Quanser
  std::string quanser_board = "q8_usb";
  std::string quanser_id = "0";
  int encoders = 1;
  int analog_outputs = 1;
  double hardware_watchdog_ms = 10.0;
  // Loop
  int max_missed = 20;
  int max_overruns = 10;
  int fifo_priority = 0;
  bool lock_memory = false;
};

std::unique_ptr<IoBoard> OpenBoard(const HilCommandOptions& o) {
  if (o.board == "udp") {
    UdpBoardOptions options;
    options.stage_port = static_cast<std::uint16_t>(o.port);
    options.reply_timeout = o.reply_timeout_ms * 1e-3;
    return std::make_unique<UdpBoard>(options);
  }
  QuanserBoardOptions options;
  options.board_type = o.quanser_board;
  options.board_identifier = o.quanser_id;
  options.encoder_channels = o.encoders;
  options.analog_outputs = o.analog_outputs;
  options.watchdog_timeout = o.hardware_watchdog_ms * 1e-3;
  return OpenQuanserBoard(options);
}

nlohmann::json StatisticsJson(const LoopStatistics& s) {
  return {{"ticks", s.ticks},
          {"period_s", s.period},
          {"latency_s", {{"mean", s.latency_mean}, {"p50", s.latency_p50}, {"p99", s.latency_p99},
                         {"p99.9", s.latency_p999}, {"max", s.latency_max}}},
          {"period_jitter_s", {{"rms", s.jitter_rms}, {"max_abs", s.jitter_max_abs}}},
          {"compute_s", {{"mean", s.compute_mean}, {"p99", s.compute_p99}, {"max", s.compute_max}}},
          {"overruns", s.overruns},
          {"max_overrun_streak", s.max_overrun_streak},
          {"missed_samples", s.missed_samples},
          {"max_missed_streak", s.max_missed_streak}};
}

void WriteTiming(const LoopRecorder& timing, const fs::path& path) {
  SignalLog log;
  std::vector<double> scheduled;
  log.names = {"latency_s", "compute_s", "flags"};
  log.columns.resize(3);
  timing.Columns(&scheduled, &log.columns[0], &log.columns[1], &log.columns[2]);
  log.time = std::move(scheduled);
  WriteSignalLog(log, path);
}

// The files `hil` writes into --out, after the loop.
const std::vector<std::string> kHilOutputNames = {"signals.csv", "timing.csv", "summary.json"};

// Removes what an earlier run wrote into `out` (kHilOutputNames and killed runs' "<name>.tmp<pid>"), unless it is one
// of the inputs: a run killed in the loop (SIGKILL, a lost machine) then leaves no earlier summary.json looking like
// its own.
void RemoveEarlierHilFiles(const fs::path& out, const std::vector<fs::path>& inputs) {
  std::error_code error;
  if (!fs::is_directory(out, error)) return;
  std::vector<fs::path> stale;
  for (const auto& entry : fs::directory_iterator(out, error)) {
    const std::string name = entry.path().filename().string();
    for (const auto& output : kHilOutputNames) {
      if (name != output && !FileNameMatches(name, output + ".tmp*")) continue;
      bool input = false;
      for (const auto& in : inputs) input = input || fs::equivalent(entry.path(), in, error);
      if (!input && entry.is_regular_file(error)) stale.push_back(entry.path());
    }
  }
  for (const auto& path : stale) {
    if (!fs::remove(path, error) && error) {
      throw std::runtime_error(fmt::format("{}: cannot remove this file of an earlier run ({}): remove it, or give "
                                           "another --out",
                                           path.string(), error.message()));
    }
  }
}

void RunHil(const HilCommandOptions& o) {
  if (o.replacements.empty()) {
    throw std::invalid_argument("hil: give --replace plant=HIL_IO.json: the plant subsystem must be swapped for the "
                                "I/O subsystem (e.g. diagrams/hil/subsystems/hil_io.json)");
  }
  std::vector<CommandFile> input_files{{"DIAGRAM", o.diagram}};
  for (const auto& text : o.replacements) input_files.push_back({"--replace", SubsystemReplacement::Parse(text).file});
  RefuseOutputsOverInputs(input_files, {}, {{"--out", o.out, kHilOutputNames}});  // before the board is opened
  nlohmann::json j = ReadDiagramJson(o.diagram);
  std::vector<std::string> dropped;
  for (const auto& text : o.replacements) {
    const SubsystemReplacement replacement = SubsystemReplacement::Parse(text);
    // The user named this file on the command line: the diagram may read it wherever it lies.
    if (std::filesystem::is_directory(replacement.file.parent_path())) AllowDiagramFilesUnder(replacement.file.parent_path());
    j = ReplaceSubsystem(j, replacement, o.diagram, &dropped);
  }
  const std::vector<ParameterOverride> overrides = ParseOverrides(o.overrides);
  ApplyOverrides(&j, overrides, o.diagram);
  if (o.duration > 0.0) {
    DiagramDocument document(std::move(j), fs::path(o.diagram).parent_path(), o.diagram);
    document.SetExperimentDuration(o.duration);
    j = document.json();
  }
  for (const auto& d : dropped) std::cerr << fmt::format("hil: dropped {} (it names the replaced plant)\n", d);

  std::unique_ptr<IoBoard> board = OpenBoard(o);
  ScopedBoardAttachment attachment(*board);
  const Diagram diagram = BuildDiagram(j, fs::path(o.diagram).parent_path(), o.diagram);

  HilOptions options;
  options.max_missed_streak = o.max_missed;
  options.max_overrun_streak = o.max_overruns;
  options.realtime.fifo_priority = o.fifo_priority;
  options.realtime.lock_memory = o.lock_memory;
  options.stop_request = &g_hil_stop;
  std::signal(SIGINT, StopHil);
  std::signal(SIGTERM, StopHil);
  std::cout << fmt::format("hil {} on {}: {} s at {} Hz\n", diagram.name(), board->description(),
                           diagram.experiment().stop_time - diagram.experiment().start_time,
                           1.0 / HilLoopPeriod(diagram))
            << std::flush;
  std::vector<fs::path> inputs{o.diagram};
  for (const auto& text : o.replacements) inputs.push_back(SubsystemReplacement::Parse(text).file);
  RemoveEarlierHilFiles(o.out, inputs);
  const HilResult result = RunHilLoop(diagram, *board, options);
  std::signal(SIGINT, SIG_DFL);
  std::signal(SIGTERM, SIG_DFL);

  const fs::path out(o.out);
  fs::create_directories(out);
  WriteSignalLog(result.log, out / "signals.csv");
  WriteTiming(result.timing, out / "timing.csv");
  nlohmann::json summary = {
      {"diagram", fs::absolute(o.diagram).string()},
      {"name", diagram.name()},
      {"overrides", o.overrides},
      {"replacements", o.replacements},
      {"metrics", result.metrics},
      {"metric_units", nlohmann::json::object()},
      {"samples", result.log.time.size()},
      {"hil", {{"board", board->description()},
               {"completed", result.completed},
               {"stop_reason", result.stop_reason},
               {"stop_time_s", result.stop_time},
               {"realtime", result.realtime_notes},
               {"loop", StatisticsJson(result.statistics)}}}};
  if (!result.metrics_error.empty()) summary["metrics_error"] = result.metrics_error;
  for (const auto& m : diagram.metrics()) summary["metric_units"][m.name] = m.unit;
  WriteJsonFile(summary, out / "summary.json");

  for (const auto& note : result.realtime_notes) std::cout << note << "\n";
  const LoopStatistics& s = result.statistics;
  std::cout << fmt::format("{} ticks at {:.0f} Hz: latency mean {:.1f} µs, p99 {:.1f} µs, max {:.1f} µs; period "
                           "jitter rms {:.1f} µs, max {:.1f} µs; compute mean {:.1f} µs, max {:.1f} µs; {} overruns, "
                           "{} missed samples\n",
                           s.ticks, 1.0 / s.period, s.latency_mean * 1e6, s.latency_p99 * 1e6, s.latency_max * 1e6,
                           s.jitter_rms * 1e6, s.jitter_max_abs * 1e6, s.compute_mean * 1e6, s.compute_max * 1e6,
                           s.overruns, s.missed_samples);
  for (const auto& [name, value] : result.metrics) std::cout << fmt::format("{} = {:.6g}\n", name, value);
  std::cout << fmt::format("wrote {}/signals.csv, timing.csv, summary.json\n", out.string());
  if (!result.completed) throw std::runtime_error("hil: " + result.stop_reason);
}

void SetupHilCommand(CLI::App& app) {
  auto options = std::make_shared<HilCommandOptions>();
  auto* cmd = app.add_subcommand("hil",
                                 "Hardware in the loop: swap the plant subsystem for board I/O and run the controller "
                                 "in real time (Quanser board, or the UDP virtual stage)");
  cmd->add_option("diagram", options->diagram, "diagram JSON file (its plant is a subsystem element)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--board", options->board, "I/O board: quanser or udp (the virtual stage)")
      ->required()
      ->check(CLI::IsMember({"quanser", "udp"}));
  cmd->add_option("--replace", options->replacements,
                  "ELEMENT=FILE: swap subsystem ELEMENT for FILE, e.g. plant=diagrams/hil/subsystems/hil_io.json")
      ->required();
  AddSetOption(cmd, &options->overrides);
  cmd->add_option("--duration", options->duration,
                  fmt::format("run this many seconds, more than 0 and at most {} (default: the diagram's stop time)",
                              kHilMaxDuration))
      ->check(FiniteRange(0.0, kHilMaxDuration, /*low_open=*/true));
  cmd->add_option("--out", options->out, "output folder")->capture_default_str();
  cmd->add_option("--port", options->port, "udp: the virtual stage's port on 127.0.0.1")->check(CLI::Range(1, 65535));
  cmd->add_option("--reply-timeout-ms", options->reply_timeout_ms,
                  "udp: wait this long for the stage's sample, then count a missed sample [ms], from 0.001 to 1000")
      ->check(FiniteRange(1e-3, 1e3))
      ->capture_default_str();
  cmd->add_option("--quanser-board", options->quanser_board, "quanser: board type for hil_open")
      ->capture_default_str();
  cmd->add_option("--quanser-id", options->quanser_id, "quanser: board identifier")->capture_default_str();
  cmd->add_option("--encoders", options->encoders, "quanser: encoder channels read (0 … n−1)")
      ->check(CLI::Range(1, kMaxEncoderChannels))
      ->capture_default_str();
  cmd->add_option("--analog-outputs", options->analog_outputs, "quanser: analog outputs written (0 … n−1)")
      ->check(CLI::Range(0, kMaxAnalogOutputs))
      ->capture_default_str();
  cmd->add_option("--hardware-watchdog-ms", options->hardware_watchdog_ms,
                  "quanser: the board's watchdog zeroes the outputs after this long without a write [ms], from 0.1 "
                  "to 60000")
      ->check(FiniteRange(0.1, 6e4))
      ->capture_default_str();
  cmd->add_option("--max-missed", options->max_missed, "safe stop after this many consecutive missed samples")
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
  cmd->add_option("--max-overruns", options->max_overruns, "safe stop after this many consecutive overruns")
      ->check(CLI::Range(1, 1000000))
      ->capture_default_str();
  cmd->add_option("--fifo", options->fifo_priority, "SCHED_FIFO priority 1–99 (0 = default scheduler)")
      ->check(CLI::Range(0, 99));
  cmd->add_flag("--lock-memory", options->lock_memory, "mlockall the process and prefault the stack");
  cmd->callback([options] { RunHil(*options); });
}

}  // namespace

MB_REGISTER_COMMAND(hil, {"hil", CommandGroup::kHardware, &SetupHilCommand, false})

}  // namespace mb

#include "tools/hil/hil_session.h"

#include <stdexcept>
#include <system_error>

#include <fmt/format.h>

#include "engine/diagram_document.h"
#include "engine/diagram_loader.h"
#include "engine/file_access.h"
#include "hw/board_registry.h"
#include "hw/hil_diagram.h"
#include "tools/report/output_files.h"

namespace mb {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr const char* kSignalsFile = "signals.csv";
constexpr const char* kTimingFile = "timing.csv";
constexpr const char* kSummaryFile = "summary.json";

json StatisticsJson(const LoopStatistics& s) {
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

// timing.csv: the scheduled time of each tick [s] (relative to the first), its wake-up latency and compute time [s]
// and its flags (kTickMissedSample | kTickOverrun).
void WriteTiming(const LoopRecorder& timing, const fs::path& path) {
  SignalLog log;
  std::vector<double> scheduled;
  log.names = {"latency_s", "compute_s", "flags"};
  log.columns.resize(3);
  timing.Columns(&scheduled, &log.columns[0], &log.columns[1], &log.columns[2]);
  log.time = std::move(scheduled);
  WriteSignalLog(log, path);
}

// The files the session reads: the diagram and the replacements' files.
std::vector<fs::path> InputFiles(const HilSessionSettings& settings) {
  std::vector<fs::path> inputs{settings.diagram};
  for (const auto& text : settings.replacements) inputs.push_back(SubsystemReplacement::Parse(text).file);
  return inputs;
}

// Removes what an earlier run wrote into `out` (HilSessionOutputNames and killed runs' "<name>.tmp<pid>"), unless it
// is one of the inputs: a run killed in the loop (SIGKILL, a lost machine) then leaves no earlier summary.json looking
// like its own.
void RemoveEarlierHilFiles(const fs::path& out, const std::vector<fs::path>& inputs) {
  std::error_code error;
  if (!fs::is_directory(out, error)) return;
  std::vector<fs::path> stale;
  for (const auto& entry : fs::directory_iterator(out, error)) {
    const std::string name = entry.path().filename().string();
    for (const auto& output : HilSessionOutputNames()) {
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

void WriteHilSessionFiles(const HilSessionResult& result, const fs::path& out) {
  fs::create_directories(out);
  WriteSignalLog(result.run.log, out / kSignalsFile);
  WriteTiming(result.run.timing, out / kTimingFile);
  WriteJsonFile(result.ToJson(), out / kSummaryFile);
}

}  // namespace

std::string HilBoardName(HilBoardKind kind) { return kind == HilBoardKind::kUdp ? "udp" : "quanser"; }

HilBoardKind ParseHilBoardKind(const std::string& name) {
  for (const HilBoardKind kind : {HilBoardKind::kUdp, HilBoardKind::kQuanser}) {
    if (name == HilBoardName(kind)) return kind;
  }
  throw std::invalid_argument(fmt::format("hil: unknown board '{}': give udp (the virtual stage) or quanser", name));
}

const std::vector<std::string>& HilSessionOutputNames() {
  static const std::vector<std::string> names{kSignalsFile, kTimingFile, kSummaryFile};
  return names;
}

PreparedHilDiagram PrepareHilDiagram(const HilSessionSettings& settings) {
  if (settings.replacements.empty()) {
    throw std::invalid_argument("hil: give --replace plant=HIL_IO.json: the plant subsystem must be swapped for the "
                                "I/O subsystem (e.g. diagrams/hil/subsystems/hil_io.json)");
  }
  std::vector<CommandFile> input_files{{"DIAGRAM", settings.diagram}};
  for (const auto& text : settings.replacements) {
    input_files.push_back({"--replace", SubsystemReplacement::Parse(text).file});
  }
  RefuseOutputsOverInputs(input_files, {}, {{"--out", settings.out, HilSessionOutputNames()}});

  PreparedHilDiagram prepared;
  json j = ReadDiagramJson(settings.diagram);
  for (const auto& text : settings.replacements) {
    const SubsystemReplacement replacement = SubsystemReplacement::Parse(text);
    // The user named this file: the diagram may read it wherever it lies.
    if (fs::is_directory(replacement.file.parent_path())) AllowDiagramFilesUnder(replacement.file.parent_path());
    j = ReplaceSubsystem(j, replacement, settings.diagram, &prepared.dropped);
  }
  std::vector<ParameterOverride> overrides;
  for (const auto& text : settings.overrides) overrides.push_back(ParameterOverride::Parse(text));
  ApplyOverrides(&j, overrides, settings.diagram);
  if (settings.duration > 0.0) {
    DiagramDocument document(std::move(j), fs::path(settings.diagram).parent_path(), settings.diagram);
    document.SetExperimentDuration(settings.duration);
    j = document.json();
  }
  prepared.json = std::move(j);
  return prepared;
}

std::unique_ptr<IoBoard> OpenHilBoard(const HilSessionSettings& settings) {
  switch (settings.board) {
    case HilBoardKind::kUdp:
      return std::make_unique<UdpBoard>(settings.udp);
    case HilBoardKind::kQuanser:
      return OpenQuanserBoard(settings.quanser);
  }
  throw std::invalid_argument("hil: unknown board kind");
}

json HilSessionResult::ToJson() const {
  json summary = {{"diagram", diagram},
                  {"name", name},
                  {"overrides", overrides},
                  {"replacements", replacements},
                  {"metrics", run.metrics},
                  {"metric_units", json::object()},
                  {"samples", run.log.time.size()},
                  {"hil", {{"board", board},
                           {"completed", run.completed},
                           {"stop_reason", run.stop_reason},
                           {"stop_time_s", run.stop_time},
                           {"realtime", run.realtime_notes},
                           {"loop", StatisticsJson(run.statistics)}}}};
  if (!run.metrics_error.empty()) summary["metrics_error"] = run.metrics_error;
  for (const auto& [metric, unit] : metric_units) summary["metric_units"][metric] = unit;
  return summary;
}

HilSessionResult RunHilSessionOnBoard(const HilSessionSettings& settings, const json& prepared_diagram,
                                      IoBoard& board, const std::atomic<bool>* stop,
                                      const std::function<void(const HilSessionStart&)>& on_start) {
  ScopedBoardAttachment attachment(board);
  const Diagram diagram = BuildDiagram(prepared_diagram, fs::path(settings.diagram).parent_path(), settings.diagram);
  const HilSessionStart start{diagram.name(), board.description(),
                              diagram.experiment().stop_time - diagram.experiment().start_time,
                              HilLoopPeriod(diagram)};
  if (on_start) on_start(start);

  HilOptions options = settings.loop;
  options.stop_request = stop;
  RemoveEarlierHilFiles(settings.out, InputFiles(settings));
  HilSessionResult result;
  result.run = RunHilLoop(diagram, board, options);
  result.diagram = fs::absolute(settings.diagram).string();
  result.name = diagram.name();
  result.overrides = settings.overrides;
  result.replacements = settings.replacements;
  for (const auto& m : diagram.metrics()) result.metric_units[m.name] = m.unit;
  result.board = start.board;
  WriteHilSessionFiles(result, settings.out);
  return result;
}

HilSessionResult RunHilSession(const HilSessionSettings& settings, const std::atomic<bool>* stop,
                               const std::function<void(const std::string&)>& on_dropped,
                               const std::function<void(const HilSessionStart&)>& on_start) {
  const PreparedHilDiagram prepared = PrepareHilDiagram(settings);
  if (on_dropped) {
    for (const auto& item : prepared.dropped) on_dropped(item);
  }
  const std::unique_ptr<IoBoard> board = OpenHilBoard(settings);
  return RunHilSessionOnBoard(settings, prepared.json, *board, stop, on_start);
}

std::string DescribeHilSessionStart(const HilSessionStart& start) {
  return fmt::format("hil {} on {}: {} s at {} Hz", start.name, start.board, start.duration, 1.0 / start.period);
}

std::string DescribeHilDroppedItem(const std::string& dropped) {
  return fmt::format("hil: dropped {} (it names the replaced plant)", dropped);
}

void PrintHilSessionSummary(const HilSessionResult& result, const std::string& out, std::ostream& os) {
  for (const auto& note : result.run.realtime_notes) os << note << "\n";
  const LoopStatistics& s = result.run.statistics;
  os << fmt::format("{} ticks at {:.0f} Hz: latency mean {:.1f} µs, p99 {:.1f} µs, max {:.1f} µs; period jitter rms "
                    "{:.1f} µs, max {:.1f} µs; compute mean {:.1f} µs, max {:.1f} µs; {} overruns, {} missed samples\n",
                    s.ticks, 1.0 / s.period, s.latency_mean * 1e6, s.latency_p99 * 1e6, s.latency_max * 1e6,
                    s.jitter_rms * 1e6, s.jitter_max_abs * 1e6, s.compute_mean * 1e6, s.compute_max * 1e6,
                    s.overruns, s.missed_samples);
  for (const auto& [name, value] : result.run.metrics) os << fmt::format("{} = {:.6g}\n", name, value);
  os << fmt::format("wrote {}/signals.csv, timing.csv, summary.json\n", out);
}

}  // namespace mb

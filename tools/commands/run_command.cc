// motionblocks run DIAGRAM [--set id.param=value …] [--input connector=FILE[:COLUMN] …] [--out DIR]
// Simulates a diagram; writes signals.csv (streamed as the run goes), summary.json (metrics in SI units) and
// report.html with plots. Complete or absent: the files an earlier run left in --out are removed before this one
// starts, and each file is written whole by rename, so an interrupted run leaves no summary.json (issue 30).

#include <chrono>
#include <iostream>

#include <fmt/format.h>

#include "engine/diagram_loader.h"
#include "engine/output_file.h"
#include "engine/simulator.h"
#include "tools/commands/cli_options.h"
#include "tools/commands/command_registry.h"
#include "tools/workflow/comparison.h"
#include "tools/report/diagram_drawing.h"
#include "tools/report/output_files.h"
#include "tools/report/report.h"

namespace mb {

namespace fs = std::filesystem;

namespace {

constexpr std::size_t kFigureSamples = 20000;  // per signal, in the report's figures

// The files a run writes into --out.
constexpr const char* kSignalsFile = "signals.csv";
constexpr const char* kSummaryFile = "summary.json";
constexpr const char* kReportFile = "report.html";
constexpr const char* kSignalFigures = "signal_{}.png";  // one per logged signal, numbered

std::vector<std::string> RunOutputNames() {
  std::vector<std::string> names{kSignalsFile, kSummaryFile, kReportFile};
  for (const auto& name : FigureFileNames(fmt::format(kSignalFigures, "*"))) names.push_back(name);
  for (const auto& name : DiagramDrawingFileNames()) names.push_back(name);
  return names;
}

// The input files a run reads: the diagram and each --input connector=FILE[:COLUMN]'s FILE (split as
// FeedInputsFromFiles does: at the last ':').
std::vector<CommandFile> RunInputFiles(const std::string& diagram, const std::vector<std::string>& inputs) {
  std::vector<CommandFile> files{{"DIAGRAM", diagram}};
  for (const auto& spec : inputs) {
    const auto eq = spec.find('=');
    if (eq == std::string::npos) continue;  // FeedInputsFromFiles refuses it
    const std::string file = spec.substr(eq + 1);
    files.push_back({"--input", file.substr(0, file.rfind(':'))});
  }
  return files;
}

// Removes from `out` and its plot/ subfolder what an earlier run wrote there (RunOutputNames, and the temporary files
// of a run that was killed: "<name>.tmp<pid>"), so that only this run's files are ever found beside each other. The
// inputs are not among them (RefuseOutputsOverInputs checked that first). Returns how many files were removed.
int RemoveEarlierRunFiles(const fs::path& out) {
  std::error_code error;
  int removed = 0;
  for (const auto& path : OutputFilesIn(out, RunOutputNames())) {
    if (!fs::remove(path, error) && error) {
      throw std::runtime_error(fmt::format("{}: cannot remove this file of an earlier run ({}): remove it, or give "
                                           "another --out",
                                           path.string(), error.message()));
    }
    ++removed;
  }
  return removed;
}

struct RunOptions {
  std::string diagram;
  std::vector<std::string> overrides;
  std::vector<std::string> inputs;
  std::string out = "out/run";
};

void RunRun(const RunOptions& o) {
  RefuseOutputsOverInputs(RunInputFiles(o.diagram, o.inputs), {}, {{"--out", o.out, RunOutputNames()}});
  const std::vector<ParameterOverride> overrides = ParseOverrides(o.overrides);
  const Diagram diagram = LoadDiagram(o.diagram, overrides);
  Simulator sim(diagram);
  FeedInputsFromFiles(diagram, o.inputs, &sim);
  ProgressLine progress(fmt::format("run {}", diagram.name()));
  sim.SetProgressCallback([&](double t, double t_stop) {
    const double t0 = diagram.experiment().start_time;
    progress.Update((t - t0) / (t_stop - t0));
  });
  // The log streams to signals.csv as it is taken (memory stays bounded however long the run); the report's
  // figures get an evenly thinned copy of at most kFigureSamples samples.
  const fs::path out(o.out);
  RemoveEarlierRunFiles(out);
  fs::create_directories(out);
  CsvLogFile signals(out / kSignalsFile);
  sim.StreamLogTo(&signals, kFigureSamples);
  const auto start = std::chrono::steady_clock::now();
  sim.Initialize();
  sim.AdvanceTo(diagram.experiment().stop_time);
  signals.Commit();
  SimulationResult result;
  result.log = sim.log();
  result.metrics = sim.StreamedMetrics();
  result.solver_stats = sim.solver_stats();
  result.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  progress.Done();

  nlohmann::json summary = {
      {"diagram", fs::absolute(o.diagram).string()},
      {"name", diagram.name()},
      {"overrides", o.overrides},
      {"metrics", result.metrics},
      {"metric_units", nlohmann::json::object()},
      {"solver", {{"type", diagram.solver().type},
                  {"steps", result.solver_stats.steps},
                  {"rhs_evaluations", result.solver_stats.rhs_evaluations},
                  {"roots_found", result.solver_stats.roots_found},
                  {"reinitialisations", result.solver_stats.reinitialisations}}},
      {"wall_time_s", result.wall_time_s},
      {"samples", sim.logged_samples()}};
  for (const auto& m : diagram.metrics()) summary["metric_units"][m.name] = m.unit;
  WriteJsonFile(summary, out / kSummaryFile);

  HtmlReport report(fmt::format("motionblocks run: {}", diagram.name()));
  report.Paragraph(fmt::format("Diagram {} simulated from {} s to {} s with {} ({} steps) in {:.3f} s wall time.",
                               o.diagram, diagram.experiment().start_time, diagram.experiment().stop_time,
                               diagram.solver().type, result.solver_stats.steps, result.wall_time_s));
  AddDiagramDrawing(&report, diagram, {}, out);
  if (!result.metrics.empty()) {
    std::vector<std::vector<std::string>> rows;
    for (const auto& m : diagram.metrics()) {
      rows.push_back({m.name, fmt::format("{:.6g}", result.metrics.at(m.name)), m.unit, std::string(Name(m.type)), m.signal});
    }
    report.Heading("Metrics");
    report.Table({"metric", "value", "unit", "type", "signal"}, rows);
  }
  report.Heading("Logged signals");
  for (std::size_t i = 0; i < result.log.names.size(); ++i) {
    Figure f;
    f.file = fmt::format(kSignalFigures, i);
    f.title = result.log.names[i];
    f.xlabel = "time [s]";
    f.ylabel = result.log.names[i];
    f.series.push_back({result.log.time, result.log.columns[i], result.log.names[i], "lines"});
    report.AddFigure(f, out);
  }
  report.Write(out / kReportFile);
  for (const auto& [name, value] : result.metrics) std::cout << fmt::format("{} = {:.6g}\n", name, value);
  std::cout << fmt::format("wrote {}/signals.csv, summary.json, report.html\n", out.string());
}

void SetupRunCommand(CLI::App& app) {
  auto options = std::make_shared<RunOptions>();
  auto* cmd = app.add_subcommand("run", "Simulate a diagram: logged signals (CSV), summary.json with metrics, report");
  cmd->add_option("diagram", options->diagram, "diagram JSON file")->required()->check(CLI::ExistingFile);
  AddSetOption(cmd, &options->overrides);
  cmd->add_option("--input", options->inputs,
                  "feed an input connector from a CSV log: connector=FILE[:COLUMN] (default column: the "
                  "connector's measurement name)");
  cmd->add_option("--out", options->out, "output folder")->capture_default_str();
  cmd->callback([options] { RunRun(*options); });
}

}  // namespace

MB_REGISTER_COMMAND(run, {"run", CommandGroup::kSimulate, &SetupRunCommand, true})

}  // namespace mb

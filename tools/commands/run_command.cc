// motionblocks run DIAGRAM [--set id.param=value …] [--input connector=FILE[:COLUMN] …] [--out DIR]
// Simulates a diagram (RunDiagram, tools/workflow/run.h); writes signals.csv (streamed as the run goes), summary.json
// (metrics in SI units) and report.html with plots (tools/report/run_report.h). Complete or absent: the files an
// earlier run left in --out are removed before this one starts, and each file is written whole by rename, so a killed
// run leaves no summary.json (issue 30); an interrupted one (Ctrl-C, SIGTERM, SIGHUP) removes its temporary files and
// leaves summary.json saying "complete": false (issue 41).

#include <iostream>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "engine/diagram_loader.h"
#include "engine/output_file.h"
#include "tools/commands/cli_options.h"
#include "tools/commands/command_registry.h"
#include "tools/report/output_files.h"
#include "tools/report/progress.h"
#include "tools/report/run_report.h"
#include "tools/workflow/run.h"

namespace mb {

namespace fs = std::filesystem;

namespace {

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

struct RunOptions {
  std::string diagram;
  std::vector<std::string> overrides;
  std::vector<std::string> inputs;
  std::string out = "out/run";
};

// What summary.json says when the run is interrupted (SIGINT, SIGTERM, SIGHUP) before it has finished: written by the
// signal handler (engine/output_file.h, InterruptMarker) after it removed the run's temporary files (issue 41).
std::string InterruptedSummary(const RunOptions& o) {
  return nlohmann::json{{"complete", false},
                        {"interrupted", "the run was interrupted (SIGINT, SIGTERM or SIGHUP) before it finished: no "
                                        "file in this folder is its result; run it again"},
                        {"diagram", fs::absolute(o.diagram).string()},
                        {"overrides", o.overrides}}
             .dump(2) +
         "\n";
}

void RunRun(const RunOptions& o) {
  RefuseOutputsOverInputs(RunInputFiles(o.diagram, o.inputs), {}, {{"--out", o.out, RunOutputNames()}});
  const InterruptMarker interrupted(fs::path(o.out) / "summary.json", InterruptedSummary(o));
  const Diagram diagram = LoadDiagram(o.diagram, ParseOverrides(o.overrides));
  DiagramRun run(diagram, {o.inputs});  // refuses a bad diagram or input before any file is touched
  const RunFiles files{o.diagram, o.overrides, o.out};
  RemoveEarlierRunFiles(files.out);
  fs::create_directories(files.out);
  CsvLogFile signals(RunSignalsFile(files.out));
  ProgressLine progress(fmt::format("run {}", diagram.name()));
  const RunOutcome outcome = run.Execute(&signals, [&](double share) { progress.Update(share); });
  signals.Commit();
  progress.Done();
  WriteRunResults(diagram, files, outcome);
  for (const auto& [name, value] : outcome.result.metrics) std::cout << fmt::format("{} = {:.6g}\n", name, value);
  std::cout << fmt::format("wrote {}/signals.csv, summary.json, report.html\n", files.out.string());
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

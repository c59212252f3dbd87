// motionblocks linearize DIAGRAM [--input connector=value …] [--time T] [--set id.param=value …] [-o FILE]
//                                [--from-hz F0 --to-hz F1 --points K] [--report FOLDER]
// The diagram linearised about an operating point, as Simulink's linmod: A, B, C, D printed and written to JSON with
// the Bode data of every output–input pair (engine/linearization.h); with --report, a page of Bode plots.

#include <iostream>

#include <Eigen/Core>
#include <fmt/format.h>

#include "engine/diagram_loader.h"
#include "engine/linearization.h"
#include "tools/commands/cli_options.h"
#include "tools/commands/command_registry.h"
#include "tools/report/bode_report.h"
#include "tools/report/output_files.h"

namespace mb {

namespace fs = std::filesystem;

namespace {

struct LinearizeOptions {
  std::string diagram;
  std::vector<std::string> overrides;
  std::vector<std::string> inputs;  ///< connector=value
  std::optional<double> time;
  std::string output;  ///< "" = <diagram stem>.linearization.json in the current folder
  double from_hz = 0.1, to_hz = 1000.0;
  int points = 200;
  std::string report;  ///< "" = none
};

void PrintMatrix(const char* name, const Eigen::MatrixXd& m) {
  const Eigen::IOFormat format(6, 0, "  ", "\n", "  [", "]");
  std::cout << fmt::format("{} ({} × {}):\n", name, m.rows(), m.cols());
  if (m.size() > 0) std::cout << m.format(format) << "\n";
}

void RunLinearize(const LinearizeOptions& o) {
  const fs::path output = o.output.empty() ? fs::path(fs::path(o.diagram).stem().string() + ".linearization.json")
                                           : fs::path(o.output);
  std::vector<OutputFolder> folders;
  if (!o.report.empty()) folders.push_back({"--report", o.report, BodeReportFileNames()});
  RefuseOutputsOverInputs({{"DIAGRAM", o.diagram}}, {{"-o", output}}, folders);
  const Eigen::VectorXd frequencies = LogSpacedFrequencies(o.from_hz, o.to_hz, o.points);
  const Diagram diagram = BuildDiagram(ReadDiagramWithOverrides(o.diagram, o.overrides),
                                       fs::path(o.diagram).parent_path(), o.diagram);
  const LinearModel model = Linearize(diagram, OperatingPoint{ParseInputValues(o.inputs), o.time});
  std::cout << fmt::format("{} linearised at t = {} s: {} states, {} inputs, {} outputs\n", o.diagram, model.time,
                           model.a.rows(), model.b.cols(), model.c.rows());
  for (const auto& name : model.state_names) std::cout << "  state: " << name << "\n";
  PrintMatrix("A", model.a);
  PrintMatrix("B", model.b);
  PrintMatrix("C", model.c);
  PrintMatrix("D", model.d);
  WriteJsonFile(LinearizationJson(model, frequencies), output);
  std::cout << fmt::format("wrote {}\n", output.string());
  if (!o.report.empty()) {
    WriteBodeReport(model, frequencies, fmt::format("motionblocks linearize: {}", fs::path(o.diagram).filename().string()),
                    o.report);
    std::cout << fmt::format("wrote {}\n", (fs::path(o.report) / "report.html").string());
  }
}

void SetupLinearizeCommand(CLI::App& app) {
  auto o = std::make_shared<LinearizeOptions>();
  auto* cmd = app.add_subcommand("linearize", "Linearise a diagram about an operating point (A, B, C, D and Bode, as "
                                              "Simulink's linmod)");
  cmd->add_option("diagram", o->diagram, "diagram JSON file")->required()->check(CLI::ExistingFile);
  cmd->add_option("--input", o->inputs, "an input connector held at a value, connector=value in its unit (repeatable; "
                                        "default: the connector's default, 0 for a required input)");
  cmd->add_option("--time", o->time, "the time the diagram is initialised at [s] (default: its start time)");
  cmd->add_option("-o,--output", o->output, "the JSON file (default: DIAGRAM's name with .linearization.json)");
  cmd->add_option("--from-hz", o->from_hz, "lowest Bode frequency [Hz]")->capture_default_str();
  cmd->add_option("--to-hz", o->to_hz, "highest Bode frequency [Hz]")->capture_default_str();
  cmd->add_option("--points", o->points, "Bode frequencies, log-spaced")->capture_default_str();
  cmd->add_option("--report", o->report, "also write FOLDER/report.html with the Bode plots");
  AddSetOption(cmd, &o->overrides);
  cmd->callback([o] { RunLinearize(*o); });
}

}  // namespace

MB_REGISTER_COMMAND(linearize, {"linearize", CommandGroup::kInspect, &SetupLinearizeCommand, false})

}  // namespace mb

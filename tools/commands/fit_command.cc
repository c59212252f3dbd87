// motionblocks fit DIAGRAM --measurement LOG.csv [--fit block.param,…] [--map connector=column …]
//                  [--set block.param=value …] [--out DIR]
// Refits chosen parameters of any diagram against a measurement (simulation or equation-error, as the diagram's
// experiment.mode says) by Levenberg–Marquardt; writes DIR/fit.json (estimates, standard errors, 95 % confidence
// intervals, RMSE before/after) and DIR/fitted.json (the diagram with the estimates). Parameters the log cannot
// determine (no effect, or indistinguishable) or a result that is not finite: exit 3, fit.json says which. The step after
// `compare --suggest` (docs/diagnosis.md).

#include <iostream>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "engine/diagram_document.h"
#include "engine/diagram_loader.h"
#include "engine/numerical_error.h"
#include "tools/commands/cli_options.h"
#include "tools/commands/commands.h"
#include "tools/workflow/comparison.h"
#include "tools/report/output_files.h"
#include "tools/report/progress.h"

namespace mb {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// The files a fit writes into --out.
constexpr const char* kFitSummary = "fit.json";
constexpr const char* kFittedDiagram = "fitted.json";

struct FitOptions {
  std::string diagram;
  MeasurementOptions measurement;
  std::vector<std::string> params;
  std::string out = "out/fit";
};

void RunFit(const FitOptions& o) {
  RefuseOutputsOverInputs({{"DIAGRAM", o.diagram}, {"--measurement", o.measurement.measurement}}, {},
                          {{"--out", o.out, {kFitSummary, kFittedDiagram}}});
  const json diagram = ReadDiagramWithOverrides(o.diagram, o.measurement.overrides);
  const MeasurementSettings settings = o.measurement.Settings();
  std::vector<std::string> names = SplitCommaLists(o.params);
  if (names.empty()) names = DiagramDocument(diagram).FreeParameters();
  if (names.empty()) {
    throw std::invalid_argument(fmt::format(
        "nothing to fit: name parameters with --params block.param,… ({} has no \"free\" list)", o.diagram));
  }
  const ExperimentMode mode = DiagramDocument(diagram).Mode();
  const bool equation_error = mode == ExperimentMode::kEquationError;
  // Equation error: the measured outputs and the model's get the same zero-phase low-pass (as compare does).
  const MeasurementLog log = ReadMeasurementFor(diagram, o.measurement.measurement, settings);
  ProgressNote(fmt::format("fit {} to {} ({} samples, {} mode): {} …", o.diagram, o.measurement.measurement,
                           log.rows(), Name(mode), fmt::join(names, ", ")));
  const DiagramFit result = FitDiagram(diagram, fs::path(o.diagram).parent_path(), o.diagram, log,
                                       settings.column_map, names,
                                       equation_error ? settings.derivative_cutoff_hz : 0.0);

  const fs::path out(o.out);
  fs::create_directories(out);
  json summary = result.ToJson();
  summary["diagram"] = o.diagram;
  summary["measurement"] = o.measurement.measurement;
  summary["mode"] = mode;
  summary["samples"] = log.rows();
  if (!result.fit.identifiable) {  // fit.json says what could not be estimated; no fitted diagram (exit 3)
    fs::remove(out / kFittedDiagram);  // an earlier run's would look like this one's result
    WriteJsonFile(summary, out / kFitSummary);
    throw NumericalError(fmt::format("{}: the parameters cannot be estimated from this log: {} (details in {})",
                                     o.measurement.measurement, result.fit.identifiability_problem,
                                     (out / kFitSummary).string()));
  }
  summary["fitted_diagram"] = (out / kFittedDiagram).string();
  WriteJsonFile(summary, out / kFitSummary);
  WriteJsonFile(result.fitted_diagram, out / kFittedDiagram);

  const auto& before = result.before.front();
  const auto& after = result.after.front();
  for (std::size_t i = 0; i < result.fit.parameters.size(); ++i) {
    const auto k = static_cast<Eigen::Index>(i);
    std::cout << fmt::format("  {:<32} {:>12.6g} → {:>12.6g}  ± {:.3g} (95 %)\n", result.fit.parameters[i].name,
                             result.fit.initial(k), result.fit.estimate(k), 1.96 * result.fit.standard_error(k));
  }
  std::cout << fmt::format("{}: RMSE {:.5g} → {:.5g} {} (fit {:.1f} % → {:.1f} %); {}\n", after.connector, before.rmse,
                           after.rmse, after.unit, before.fit_percent, after.fit_percent, result.fit.status);
  std::cout << fmt::format("wrote {} and {}\n", (out / kFitSummary).string(), (out / kFittedDiagram).string());
}

}  // namespace

void SetupFitCommand(CLI::App& app) {
  auto o = std::make_shared<FitOptions>();
  auto* cmd = app.add_subcommand("fit", "Refit chosen parameters of a diagram against a measurement, with 95 % "
                                        "confidence intervals");
  cmd->add_option("diagram", o->diagram, "diagram JSON file")->required()->check(CLI::ExistingFile);
  AddMeasurementOptions(cmd, &o->measurement, "measurement log CSV (time_s first)",
                        "parameter override block.param=value before fitting (repeatable)");
  cmd->add_option("--fit", o->params, "parameters to refit: block.param,… (default: the diagram's \"free\" list)");
  AddDeprecatedAlias(cmd, "--params", "--fit", &o->params);
  cmd->add_option("--out", o->out, "output folder (fit.json, fitted.json)")->capture_default_str();
  cmd->callback([o] { RunFit(*o); });
}

}  // namespace mb

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
#include "tools/commands/command_registry.h"
#include "tools/workflow/fit.h"
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
  const DiagramDocument document(ReadDiagramWithOverrides(o.diagram, o.measurement.overrides),
                                 fs::path(o.diagram).parent_path(), o.diagram);
  FitSettings settings;
  settings.measurement = o.measurement.Settings();
  settings.parameters = SplitCommaLists(o.params);
  const MeasurementLog log = ReadMeasurementFor(document.json(), o.measurement.measurement, settings.measurement);
  ProgressNote(fmt::format("fit {} to {} ({} samples, {} mode) …", o.diagram, o.measurement.measurement, log.rows(),
                           Name(document.Mode())));
  const FitOutcome outcome = FitToMeasurement(document, log, o.measurement.measurement, settings);
  const DiagramFit& result = outcome.result;

  const fs::path out(o.out);
  fs::create_directories(out);
  json summary = outcome.ToJson();
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
    const std::string& unit = result.fit.parameters[i].unit;  // on the diagram's axis: N·m·s/rad on a rotary one
    std::cout << fmt::format("  {:<32} {:>12.6g} → {:>12.6g}  ± {:.3g}{}{} (95 %)\n", result.fit.parameters[i].name,
                             result.fit.initial(k), result.fit.estimate(k), 1.96 * result.fit.standard_error(k),
                             unit.empty() ? "" : " ", unit);
  }
  std::cout << fmt::format("{}: RMSE {:.5g} → {:.5g} {} (fit {:.1f} % → {:.1f} %); {}\n", after.connector, before.rmse,
                           after.rmse, after.unit, before.fit_percent, after.fit_percent, result.fit.status);
  std::cout << fmt::format("wrote {} and {}\n", (out / kFitSummary).string(), (out / kFittedDiagram).string());
}

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

}  // namespace

MB_REGISTER_COMMAND(fit, {"fit", CommandGroup::kMeasurements, &SetupFitCommand, true})

}  // namespace mb

// motionblocks fit DIAGRAM --measurement LOG.csv [--params block.param,…] [--map connector=column …]
//                  [--set block.param=value …] [--out DIR]
// Refits chosen parameters of any diagram against a measurement (simulation or equation-error, as the diagram's
// experiment.mode says) by Levenberg–Marquardt; writes DIR/fit.json (estimates, standard errors, 95 % confidence
// intervals, RMSE before/after) and DIR/fitted.json (the diagram with the estimates). The step after
// `compare --suggest` (docs/diagnosis.md).

#include <iostream>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "engine/diagram_document.h"
#include "engine/diagram_loader.h"
#include "tools/commands.h"
#include "tools/comparison.h"
#include "tools/output_files.h"

namespace mb {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

struct FitOptions {
  std::string diagram;
  std::string measurement;
  std::vector<std::string> params;
  std::vector<std::string> maps;
  std::vector<std::string> overrides;
  std::string out = "out/fit";
  std::string position_column = "position_m";
  double derivative_cutoff_hz = 100.0;
};

std::vector<std::string> SplitCommas(const std::vector<std::string>& items) {
  std::vector<std::string> out;
  for (const auto& item : items) {
    std::size_t start = 0;
    while (start <= item.size()) {
      const auto comma = item.find(',', start);
      const std::string name = item.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
      if (!name.empty()) out.push_back(name);
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
  }
  return out;
}

void RunFit(const FitOptions& o) {
  std::vector<ParameterOverride> overrides;
  for (const auto& s : o.overrides) overrides.push_back(ParameterOverride::Parse(s));
  json diagram = ReadDiagramJson(o.diagram);
  ApplyOverrides(&diagram, overrides, o.diagram);
  std::map<std::string, std::string> column_map;
  for (const auto& m : o.maps) {
    const auto eq = m.find('=');
    if (eq == std::string::npos) throw std::invalid_argument(fmt::format("--map '{}': write connector=column", m));
    column_map[m.substr(0, eq)] = m.substr(eq + 1);
  }
  std::vector<std::string> names = SplitCommas(o.params);
  if (names.empty()) names = DiagramDocument(diagram).FreeParameters();
  if (names.empty()) {
    throw std::invalid_argument(fmt::format(
        "nothing to fit: name parameters with --params block.param,… ({} has no \"free\" list)", o.diagram));
  }
  const std::string mode = DiagramDocument(diagram).ExperimentMode();
  const bool equation_error = mode == "equation_error";
  // Equation error: the measured outputs and the model's get the same zero-phase low-pass (as compare does).
  const MeasurementLog log = ReadMeasurementWithDerivatives(
      o.measurement, o.position_column, o.derivative_cutoff_hz,
      equation_error ? OutputColumns(diagram, column_map) : std::vector<std::string>{});
  std::cerr << fmt::format("fit {} to {} ({} samples, {} mode): {} …\n", o.diagram, o.measurement, log.rows(), mode,
                           fmt::join(names, ", "));
  const DiagramFit result = FitDiagram(diagram, fs::path(o.diagram).parent_path(), o.diagram, log, column_map, names,
                                       equation_error ? o.derivative_cutoff_hz : 0.0);

  const fs::path out(o.out);
  fs::create_directories(out);
  json summary = result.ToJson();
  summary["diagram"] = o.diagram;
  summary["measurement"] = o.measurement;
  summary["mode"] = mode;
  summary["samples"] = log.rows();
  summary["fitted_diagram"] = (out / "fitted.json").string();
  WriteJsonFile(summary, out / "fit.json");
  WriteJsonFile(result.fitted_diagram, out / "fitted.json");

  const auto& before = result.before.front();
  const auto& after = result.after.front();
  for (std::size_t i = 0; i < result.fit.parameters.size(); ++i) {
    const auto k = static_cast<Eigen::Index>(i);
    std::cout << fmt::format("  {:<32} {:>12.6g} → {:>12.6g}  ± {:.3g} (95 %)\n", result.fit.parameters[i].name,
                             result.fit.initial(k), result.fit.estimate(k), 1.96 * result.fit.standard_error(k));
  }
  std::cout << fmt::format("{}: RMSE {:.5g} → {:.5g} {} (fit {:.1f} % → {:.1f} %); {}\n", after.connector, before.rmse,
                           after.rmse, after.unit, before.fit_percent, after.fit_percent, result.fit.status);
  std::cout << fmt::format("wrote {} and {}\n", (out / "fit.json").string(), (out / "fitted.json").string());
}

}  // namespace

void SetupFitCommand(CLI::App& app) {
  auto o = std::make_shared<FitOptions>();
  auto* cmd = app.add_subcommand("fit", "Refit chosen parameters of a diagram against a measurement, with 95 % "
                                        "confidence intervals");
  cmd->add_option("diagram", o->diagram, "diagram JSON file")->required()->check(CLI::ExistingFile);
  cmd->add_option("--measurement", o->measurement, "measurement log CSV (time_s first)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--params", o->params, "parameters to refit: block.param,… (default: the diagram's \"free\" list)");
  cmd->add_option("--map", o->maps, "connector=column: read a connector from another column (repeatable)");
  cmd->add_option("--set", o->overrides, "parameter override block.param=value before fitting (repeatable)");
  cmd->add_option("--position-column", o->position_column, "measured position column [m, rad, rev or deg: the unit is the name's suffix]")->capture_default_str();
  cmd->add_option("--derivative-cutoff-hz", o->derivative_cutoff_hz,
                  "zero-phase low-pass cut-off before differentiating the position [Hz]")
      ->capture_default_str();
  cmd->add_option("--out", o->out, "output folder (fit.json, fitted.json)")->capture_default_str();
  cmd->callback([o] { RunFit(*o); });
}

}  // namespace mb

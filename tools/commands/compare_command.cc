// motionblocks compare DIAGRAM --measurement LOG.csv [--map connector=column …] [--fit block.param,…]
//                      [--suggest AMENDED.json [--suggest-effect NAME]] [--write-fitted FITTED.json]
//                      [--no-gpr-fallback] --out DIR
// Drives the diagram with the measured inputs, compares its outputs with the measured columns, refits the free
// parameters, shows where the model fails and ranks the candidate missing effects (docs/diagnosis.md); then fits
// a TISO-GPR to what the ranked effects leave and says how much of it depends on position and velocity.

#include <iostream>

#include <fmt/format.h>

#include "engine/diagram_loader.h"
#include "tools/commands/cli_options.h"
#include "tools/commands/command_registry.h"
#include "tools/report/compare_report.h"
#include "tools/report/output_files.h"
#include "tools/report/progress.h"
#include "tools/workflow/compare.h"

namespace mb {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

struct CompareOptions {
  std::string diagram;
  MeasurementOptions measurement;
  std::vector<std::string> fit;
  bool no_fit = false;
  std::string out = "out/compare";
  std::string suggest;
  std::string suggest_effect;
  std::string write_fitted;
  bool no_gpr_fallback = false;
};

void RunCompare(const CompareOptions& o) {
  RefuseOutputsOverInputs({{"DIAGRAM", o.diagram}, {"--measurement", o.measurement.measurement}},
                          {{"--suggest", o.suggest}, {"--write-fitted", o.write_fitted}},
                          {{"--out", o.out, CompareOutputNames()}});
  const json diagram = ReadDiagramWithOverrides(o.diagram, o.measurement.overrides);
  CompareSettings settings;
  settings.measurement = o.measurement.Settings();
  const MeasurementLog log = ReadMeasurementFor(diagram, o.measurement.measurement, settings.measurement);
  ProgressNote(fmt::format("compare {} with {} ({} samples, {} mode)", o.diagram, o.measurement.measurement,
                           log.rows(), Name(ModeOf(diagram))));
  settings.fit = SplitCommaLists(o.fit);
  settings.no_fit = o.no_fit;
  settings.gpr_fallback = !o.no_gpr_fallback;
  settings.suggest = !o.suggest.empty();
  settings.suggest_effect = o.suggest_effect;
  settings.fallback_model_path = fs::absolute(fs::path(o.out) / "residual_gpr.json").string();
  const CompareOutcome outcome =
      Compare(DiagramDocument(diagram, fs::path(o.diagram).parent_path(), o.diagram), log, settings, ProgressNote);
  const CompareFiles files{o.diagram, o.measurement.measurement, o.out, o.write_fitted, o.suggest,
                           o.measurement.position_column};
  const json written = WriteCompareResults(outcome, log, files);
  PrintCompareSummary(outcome, written, files, std::cout, std::cerr);
}

void SetupCompareCommand(CLI::App& app) {
  auto o = std::make_shared<CompareOptions>();
  auto* cmd = app.add_subcommand("compare", "Compare a model with a measurement, refit, find the missing effect");
  cmd->add_option("diagram", o->diagram, "diagram JSON file")->required()->check(CLI::ExistingFile);
  AddMeasurementOptions(cmd, &o->measurement, "measurement log CSV (time_s first)");
  cmd->add_option("--fit", o->fit, "parameters to refit: block.param,… (default: the diagram's \"free\" list)");
  cmd->add_flag("--no-fit", o->no_fit, "compare as is, refit nothing");
  cmd->add_flag("--no-gpr-fallback", o->no_gpr_fallback,
                "skip the TISO-GPR fitted to what the diagnosis leaves (it writes residual_gpr.json when it helps)");
  cmd->add_option("--suggest", o->suggest,
                  "write the diagram amended, in the ranking's order, with the friction-law replacements and the top "
                  "missing effect's block here (it says what it added)");
  cmd->add_option("--suggest-effect", o->suggest_effect,
                  "with --suggest: the highest-ranked effect of this catalogue name instead of the top one "
                  "(e.g. velocity_dependent_ripple); when no effect is named but the TISO-GPR fallback helps, "
                  "--suggest adds its gpr block (nonparametric_fallback)");
  cmd->add_option("--write-fitted", o->write_fitted, "write the diagram with the fitted parameters here");
  cmd->add_option("--out", o->out, "output folder")->capture_default_str();
  cmd->callback([o] { RunCompare(*o); });
}

}  // namespace

MB_REGISTER_COMMAND(compare, {"compare", CommandGroup::kMeasurements, &SetupCompareCommand, true})

}  // namespace mb

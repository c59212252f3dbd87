// motionblocks improve DIAGRAM --measurement LOG.csv [--validation LOG.csv] [--max-effects N] [--out DIR]
// The loop compare → suggest → fit → compare in one command: add the diagnosed missing effects one at a time,
// refit jointly, keep an effect only if the held-out error falls (tools/workflow/improve.h). Writes DIR/step_<k>/diagram.json
// as each step completes, DIR/improved.json, DIR/improve.json and DIR/report.html (before/after figures); when the
// residual stays non-white, the TISO-GPR fallback (DIR/residual_gpr.json, DIR/improved_with_gp.json).
// improve.json says whether it is the whole result: "complete": false while the loop runs (rewritten by rename after
// each step, so a killed improve leaves the steps it finished, marked incomplete), true once everything is written;
// an improve.json of an earlier run in DIR is removed before the first step (issue 30).

#include <iostream>
#include <optional>

#include "engine/diagram_document.h"
#include "engine/diagram_loader.h"
#include "tools/commands/cli_options.h"
#include "tools/commands/command_registry.h"
#include "tools/report/improve_report.h"
#include "tools/report/output_files.h"
#include "tools/report/progress.h"
#include "tools/workflow/improve.h"

namespace mb {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

struct ImproveOptions {
  std::string diagram;
  MeasurementOptions measurement;
  std::string validation;
  std::vector<std::string> validation_fit;
  ImproveSettings settings;  // --max-effects, --max-trials, --min-gain: their defaults are the library's
  bool no_refine_periods = false;
  std::string out = "out/improve";
};

void RunImprove(const ImproveOptions& o) {
  std::vector<CommandFile> inputs{{"DIAGRAM", o.diagram}, {"--measurement", o.measurement.measurement}};
  if (!o.validation.empty()) inputs.push_back({"--validation", o.validation});
  RefuseOutputsOverInputs(inputs, {}, {{"--out", o.out, ImproveOutputNames()}});
  const DiagramDocument document(ReadDiagramWithOverrides(o.diagram, o.measurement.overrides),
                                 fs::path(o.diagram).parent_path(), o.diagram);
  ImproveSettings settings = o.settings;
  settings.measurement = o.measurement.Settings();
  settings.refine_periods = !o.no_refine_periods;
  settings.validation_free = SplitCommaLists(o.validation_fit);

  const MeasurementLog training = ReadMeasurementFor(document.json(), o.measurement.measurement, settings.measurement);
  std::optional<MeasurementLog> validation;
  if (!o.validation.empty()) validation = ReadMeasurementFor(document.json(), o.validation, settings.measurement);
  const MeasurementLog* held_out = validation ? &*validation : nullptr;
  const fs::path out(o.out);
  RemoveEarlierImproveResult(out, {o.diagram, o.measurement.measurement, o.validation});
  const auto progress = [](const std::string& line) { ProgressNote("improve: " + line); };
  // improve.json with "complete": false after each step, so that a killed run keeps the steps it finished.
  const ImproveOutcome outcome = ImproveToMeasurement(
      document, training, o.measurement.measurement, held_out, o.validation, settings,
      progress, [&](const ImproveResult& so_far, const json& head) { WriteImproveProgress(so_far, out, head); });
  const ImproveFiles files{o.diagram, o.measurement.measurement, document.base_directory(), out,
                           o.measurement.position_column};
  const std::optional<json> fallback = WriteImproveResults(outcome, training, held_out, files);
  PrintImproveSummary(outcome.result, fallback, out, std::cout);
}

void SetupImproveCommand(CLI::App& app) {
  auto o = std::make_shared<ImproveOptions>();
  auto* cmd = app.add_subcommand(
      "improve", "Add the missing effects one at a time (compare → suggest → fit), keep those that lower the "
                 "held-out error; before/after report");
  cmd->add_option("diagram", o->diagram, "diagram JSON file")->required()->check(CLI::ExistingFile);
  AddMeasurementOptions(cmd, &o->measurement, "measurement log CSV to fit on (time_s first)");
  cmd->add_option("--validation", o->validation,
                  "held-out log CSV: scores each step; only the record's parameters (ripple position offsets) are "
                  "refit on it (default: cross-validation on the measurement)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--max-effects", o->settings.max_effects, "effects to add at most")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--max-trials", o->settings.max_trials_per_round,
                  "ranked effects tried per round before stopping")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--min-gain", o->settings.min_relative_gain,
                  "keep an effect if the held-out RMSE falls by at least this share")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 0.999));
  cmd->add_option("--validation-fit", o->validation_fit,
                  "parameters refit on the validation record instead of the ripple position offsets: block.param,…");
  cmd->add_flag("--no-refine-periods", o->no_refine_periods,
                "keep an added ripple's period from the periodogram instead of refitting it");
  cmd->add_option("--out", o->out, "output folder")->capture_default_str();
  cmd->callback([o] { RunImprove(*o); });
}

}  // namespace

MB_REGISTER_COMMAND(improve, {"improve", CommandGroup::kMeasurements, &SetupImproveCommand, true})

}  // namespace mb

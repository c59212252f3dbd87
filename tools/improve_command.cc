// motionblocks improve DIAGRAM --measurement LOG.csv [--validation LOG.csv] [--max-effects N] [--out DIR]
// The loop compare → suggest → fit → compare in one command: add the diagnosed missing effects one at a time,
// refit jointly, keep an effect only if the held-out error falls (tools/improve.h). Writes DIR/step_<k>/diagram.json
// as each step completes, DIR/improved.json, DIR/improve.json and DIR/report.html (before/after figures); when the
// residual stays non-white, the TISO-GPR fallback (DIR/residual_gpr.json, DIR/improved_with_gp.json).

#include <fstream>
#include <iostream>
#include <optional>

#include <fmt/format.h>

#include "engine/diagram_loader.h"
#include "models/diagnosis/effect_registry.h"
#include "models/gpr/gpr_io.h"
#include "models/gpr/residual_gpr.h"
#include "tools/output_files.h"
#include "tools/suggest.h"
#include "tools/commands.h"
#include "tools/comparison.h"
#include "tools/improve.h"

namespace mb {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

struct ImproveOptions {
  std::string diagram;
  std::string measurement;
  std::string validation;
  std::vector<std::string> maps;
  std::vector<std::string> overrides;
  std::vector<std::string> validation_fit;
  int max_effects = 3;
  int max_trials = 3;
  double min_gain = 0.002;
  bool no_refine_periods = false;
  std::string out = "out/improve";
  std::string position_column = "position_m";
  double derivative_cutoff_hz = 100.0;
};

// When the loop stops with a residual that is still not white: the TISO-GPR fallback (models/gpr/residual_gpr.h)
// fitted to the last accepted diagram's residual — "PS" at the period of the first accepted periodic effect, else
// "DS" —
// scored on held-out blocks. When it helps, writes residual_gpr.json and improved_with_gp.json (the last accepted
// diagram with the gpr block, SuggestGprFallbackBlock) and records both in improve.json under
// "nonparametric_fallback". Returns that record.
std::optional<json> FitFallback(const ImproveResult& result, const fs::path& out) {
  const ImproveStep& last = result.last_accepted();
  if (!result.residual_not_white || !last.training.diagnosis) return std::nullopt;
  std::cerr << "improve: fitting the non-parametric fallback (TISO-GPR on position and velocity) to what is left …\n";
  ResidualGprOptions options;
  for (const auto& step : result.steps) {
    if (step.accepted && step.diagnosed && step.diagnosed->parameters.count("period") &&
        LookupEffect(step.effect).traits.periodicity == Periodicity::kPosition) {
      options.period = step.diagnosed->parameters.at("period");
      break;  // the first accepted period: the strongest (later ones are often its harmonics)
    }
  }
  json record;
  ResidualGprResult g;
  try {
    g = FitResidualGpr(last.training.signals, last.training.signals.residual, options);
    record = g.ToJson();
  } catch (const std::exception& e) {  // the loop's result stands without it (e.g. a log too short for the folds)
    std::cerr << "improve: no non-parametric fallback: " << e.what() << "\n";
    record = {{"useful", false}, {"skipped", e.what()}, {"description", std::string("no fallback: ") + e.what()}};
  }
  if (g.model) {
    const std::string model = fs::absolute(out / "residual_gpr.json").string();
    SaveGprModel(*g.model, model);
    const json amended =
        SuggestGprFallbackBlock(last.training.fitted_diagram, model, last.training.after.front().connector);
    WriteJsonFile(amended, out / "improved_with_gp.json");
    record["model"] = model;
    record["diagram"] = (out / "improved_with_gp.json").string();
  }
  std::ifstream in(out / "improve.json");
  json written = json::parse(in);
  written["nonparametric_fallback"] = record;
  WriteJsonFile(written, out / "improve.json");
  return record;
}

void RunImprove(const ImproveOptions& o) {
  std::vector<ParameterOverride> overrides;
  for (const auto& s : o.overrides) overrides.push_back(ParameterOverride::Parse(s));
  json diagram = ReadDiagramJson(o.diagram);
  ApplyOverrides(&diagram, overrides, o.diagram);
  ImproveSettings settings;
  for (const auto& m : o.maps) {
    const auto eq = m.find('=');
    if (eq == std::string::npos) throw std::invalid_argument(fmt::format("--map '{}': write connector=column", m));
    settings.measurement.column_map[m.substr(0, eq)] = m.substr(eq + 1);
  }
  settings.measurement.position_column = o.position_column;
  settings.measurement.derivative_cutoff_hz = o.derivative_cutoff_hz;
  settings.max_effects = o.max_effects;
  settings.max_trials_per_round = o.max_trials;
  settings.min_relative_gain = o.min_gain;
  settings.refine_periods = !o.no_refine_periods;
  for (const auto& f : o.validation_fit) {
    for (std::size_t start = 0; start <= f.size();) {
      const auto comma = f.find(',', start);
      const std::string name = f.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
      if (!name.empty()) settings.validation_free.push_back(name);
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
  }

  const MeasurementLog training = ReadMeasurementFor(diagram, o.measurement, settings.measurement);
  std::optional<MeasurementLog> validation;
  if (!o.validation.empty()) validation = ReadMeasurementFor(diagram, o.validation, settings.measurement);
  const fs::path out(o.out);
  const json context = {{"diagram", o.diagram},
                        {"measurement", o.measurement},
                        {"validation", o.validation.empty() ? json(nullptr) : json(o.validation)},
                        {"mode", ExperimentMode(diagram)},
                        {"max_effects", o.max_effects},
                        {"min_relative_gain", o.min_gain}};
  const ImproveResult result = ImproveModel(
      diagram, fs::path(o.diagram).parent_path(), o.diagram, training, validation ? &*validation : nullptr, settings,
      [](const std::string& line) { std::cerr << "improve: " << line << "\n"; },
      [&](const ImproveStep&, const ImproveResult& so_far) { WriteImproveProgress(so_far, out, context); });
  const std::optional<json> fallback = FitFallback(result, out);
  std::cerr << "improve: writing the report …\n";
  WriteImproveReport(result,
                     training, validation ? &*validation : nullptr,
                     fmt::format("motionblocks improve: {} on {}", fs::path(o.diagram).filename().string(),
                                 fs::path(o.measurement).filename().string()),
                     o.position_column, out);

  int k = 0;
  for (const auto& s : result.steps) {
    std::cout << fmt::format("{:>4}  {:<28} fit RMSE {:.4g} → {:.4g}  held out {:.4g} → {:.4g} {}  {}\n",
                             s.accepted ? fmt::format("{}", k++) : "—", s.effect.empty() ? "(as given, refit)" : s.effect,
                             s.rmse_train_before, s.rmse_train, s.rmse_heldout_before, s.rmse_heldout,
                             s.training.after.front().unit, s.accepted ? "" : "(rejected)");
  }
  std::cout << "stop: " << result.stop_reason << "\n";
  if (fallback) std::cout << (*fallback)["description"].get<std::string>() << "\n";
  std::cout << fmt::format("wrote {}/improved.json, improve.json, step_*/diagram.json and report.html\n", out.string());
}

}  // namespace

void SetupImproveCommand(CLI::App& app) {
  auto o = std::make_shared<ImproveOptions>();
  auto* cmd = app.add_subcommand(
      "improve", "Add the missing effects one at a time (compare → suggest → fit), keep those that lower the "
                 "held-out error; before/after report");
  cmd->add_option("diagram", o->diagram, "diagram JSON file")->required()->check(CLI::ExistingFile);
  cmd->add_option("--measurement", o->measurement, "measurement log CSV to fit on (time_s first)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--validation", o->validation,
                  "held-out log CSV: scores each step; only the record's parameters (ripple position offsets) are "
                  "refit on it (default: cross-validation on the measurement)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--max-effects", o->max_effects, "effects to add at most")
      ->capture_default_str()
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--max-trials", o->max_trials, "ranked effects tried per round before stopping")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  cmd->add_option("--min-gain", o->min_gain, "keep an effect if the held-out RMSE falls by at least this share")
      ->capture_default_str()
      ->check(CLI::Range(0.0, 0.999));
  cmd->add_option("--validation-fit", o->validation_fit,
                  "parameters refit on the validation record instead of the ripple position offsets: block.param,…");
  cmd->add_flag("--no-refine-periods", o->no_refine_periods,
                "keep an added ripple's period from the periodogram instead of refitting it");
  cmd->add_option("--map", o->maps, "connector=column: read a connector from another column (repeatable)");
  cmd->add_option("--set", o->overrides, "parameter override block.param=value (repeatable)");
  cmd->add_option("--position-column", o->position_column, "measured position column [m, rad, rev or deg: the unit is the name's suffix]")->capture_default_str();
  cmd->add_option("--derivative-cutoff-hz", o->derivative_cutoff_hz,
                  "zero-phase low-pass cut-off before differentiating the position [Hz]")
      ->capture_default_str();
  cmd->add_option("--out", o->out, "output folder")->capture_default_str();
  cmd->callback([o] { RunImprove(*o); });
}

}  // namespace mb

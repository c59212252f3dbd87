// motionblocks compare DIAGRAM --measurement LOG.csv [--map connector=column …] [--fit block.param,…]
//                      [--suggest AMENDED.json [--suggest-effect NAME]] [--write-fitted FITTED.json]
//                      [--no-gpr-fallback] --out DIR
// Drives the diagram with the measured inputs, compares its outputs with the measured columns, refits the free
// parameters, shows where the model fails and ranks the candidate missing effects (docs/diagnosis.md); then fits
// a TISO-GPR to what the ranked effects leave and says how much of it depends on position and velocity.

#include <fstream>
#include <stdexcept>
#include <iostream>

#include <fmt/format.h>

#include "engine/diagram_document.h"
#include "engine/diagram_loader.h"
#include "models/diagnosis/diagnosis.h"
#include "models/gpr/gpr_io.h"
#include "models/gpr/residual_gpr.h"
#include "tools/commands.h"
#include "tools/comparison.h"
#include "tools/output_files.h"
#include "tools/report.h"
#include "tools/suggest.h"

namespace mb {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

struct CompareOptions {
  std::string diagram;
  std::string measurement;
  std::vector<std::string> maps;
  std::vector<std::string> fit;
  bool no_fit = false;
  std::vector<std::string> overrides;
  std::string out = "out/compare";
  std::string suggest;
  std::string suggest_effect;
  std::string write_fitted;
  std::string position_column = "position_m";
  double derivative_cutoff_hz = 100.0;
  bool no_gpr_fallback = false;
};

std::vector<double> ToStd(const Eigen::VectorXd& v) { return {v.data(), v.data() + v.size()}; }

void AddResidualFigures(HtmlReport* report, const fs::path& out, const MeasurementLog& log,
                        const ComparedOutput& before, const Eigen::VectorXd& residual_after,
                        const DiagnosisResult* diagnosis, const std::string& position_column) {
  const auto t = ToStd(log.time());
  Figure overlay{"model_vs_measurement.png", fmt::format("{}: measured vs model", before.connector), "time [s]",
                 fmt::format("{} [{}]", before.connector, before.unit), {}};
  overlay.series.push_back({t, ToStd(before.measured), "measured (" + before.column + ")", "lines"});
  overlay.series.push_back({t, ToStd(before.model), "model", "lines"});
  report->AddFigure(overlay, out);

  Figure rt{"residual_vs_time.png", "Residual against time (after the fit)", "time [s]",
            fmt::format("measured − model [{}]", before.unit), {}};
  rt.series.push_back({t, ToStd(residual_after), "residual", "lines"});
  report->AddFigure(rt, out);
  if (log.has_column(position_column)) {
    Figure rx{"residual_vs_position.png", "Residual against position", "position [m]",
              fmt::format("residual [{}]", before.unit), {}};
    rx.series.push_back({ToStd(log.column(position_column)), ToStd(residual_after), "residual", "dots"});
    report->AddFigure(rx, out);
  }
  const std::string velocity_column = DerivedVelocityColumn(position_column);
  const std::string acceleration_column = DerivedAccelerationColumn(position_column);
  if (log.has_column(velocity_column)) {
    const BinnedResidual b = BinResidual(log.column(velocity_column), residual_after, 40);
    std::vector<double> xs, ys;
    for (Eigen::Index i = 0; i < b.centers.size(); ++i) {
      if (b.count(i) > 0) {
        xs.push_back(b.centers(i));
        ys.push_back(b.mean(i));
      }
    }
    Figure rv{"residual_vs_velocity.png", "Residual against velocity (binned mean: the friction shape)",
              "velocity [m/s]", fmt::format("residual [{}]", before.unit), {}};
    rv.series.push_back({ToStd(log.column(velocity_column)), ToStd(residual_after), "samples", "dots"});
    rv.series.push_back({xs, ys, "bin mean", "lines"});
    report->AddFigure(rv, out);
  }
  if (log.has_column(acceleration_column)) {
    Figure ra{"residual_vs_acceleration.png", "Residual against acceleration (a slope: mass mismatch)",
              "acceleration [m/s²]", fmt::format("residual [{}]", before.unit), {}};
    ra.series.push_back({ToStd(log.column(acceleration_column)), ToStd(residual_after), "samples", "dots"});
    report->AddFigure(ra, out);
  }
  if (diagnosis && !diagnosis->position_peaks.empty()) {
    // Re-plot the periodogram from the peaks list is too sparse; compute the full one here for the figure.
    const Periodogram pg = PositionPeriodogram(log.column(position_column), residual_after);
    Figure fp{"position_periodogram.png", "Position-domain periodogram of the residual (share of variance explained)",
              "period [m]", "power", {}};
    fp.log_x = true;
    fp.series.push_back({ToStd(pg.periods), ToStd(pg.power), "floating-mean Lomb–Scargle", "lines"});
    report->AddFigure(fp, out);
  }
}

// Writes an amended diagram (suggested on the comparison's copy) with the input diagram's own defaultExperiment.
void WriteSuggestion(const json& amended, const json& input, const std::string& path) {
  DiagramDocument document(amended);
  document.CopyExperimentFrom(DiagramDocument(input));
  WriteJsonFile(document.json(), path);
}

void RunCompare(const CompareOptions& o) {
  std::vector<ParameterOverride> overrides;
  for (const auto& s : o.overrides) overrides.push_back(ParameterOverride::Parse(s));
  json diagram_json = ReadDiagramJson(o.diagram);
  ApplyOverrides(&diagram_json, overrides, o.diagram);
  std::map<std::string, std::string> column_map;
  for (const auto& m : o.maps) {
    const auto eq = m.find('=');
    if (eq == std::string::npos) throw std::invalid_argument(fmt::format("--map '{}': write connector=column", m));
    column_map[m.substr(0, eq)] = m.substr(eq + 1);
  }
  const MeasurementSettings settings{column_map, o.position_column, o.derivative_cutoff_hz};
  const std::string mode = ExperimentMode(diagram_json);
  const MeasurementLog log = ReadMeasurementFor(diagram_json, o.measurement, settings);
  std::cerr << fmt::format("compare {} with {} ({} samples, {} mode)\n", o.diagram, o.measurement, log.rows(), mode);

  // Refit the free parameters (--fit, else the diagram's "free" list).
  std::vector<std::string> fit_names;
  for (const auto& f : o.fit) {
    std::size_t start = 0;
    while (start <= f.size()) {
      const auto comma = f.find(',', start);
      const std::string name = f.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
      if (!name.empty()) fit_names.push_back(name);
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
  }
  if (fit_names.empty() && !o.no_fit) {
    fit_names = DiagramDocument(diagram_json).FreeParameters();
  }
  if (o.no_fit) fit_names.clear();
  std::cerr << fmt::format("fitting {} parameter(s) by Levenberg–Marquardt, diagnosing the residual …\n",
                           fit_names.size());
  const DiagnosedComparison compared =
      CompareAndDiagnose(diagram_json, fs::path(o.diagram).parent_path(), o.diagram, log, settings, fit_names);
  const std::optional<FitResult>& fit = compared.fit;
  const std::vector<FreeParameter>& params = compared.parameters;
  const std::optional<DiagnosisResult>& diagnosis = compared.diagnosis;
  const std::string& diagnosis_skipped = compared.diagnosis_skipped;
  const auto& before = compared.before;
  const auto& after = compared.after;
  const ComparedOutput& primary_before = before.front();
  const ComparedOutput& primary_after = after.front();
  const Eigen::VectorXd residual_after = primary_after.residual();
  std::optional<ResidualGprResult> fallback;
  std::string fallback_skipped;  // the comparison stands without it (e.g. a log too short for its folds)
  if (diagnosis && !o.no_gpr_fallback) {
    std::cerr << "fitting the non-parametric fallback (TISO-GPR on position and velocity) to what is left …\n";
    try {
      fallback = FitResidualGprAfterDiagnosis(compared.signals, compared.base, *diagnosis);
    } catch (const std::exception& e) {
      fallback_skipped = e.what();
      std::cerr << "no non-parametric fallback: " << fallback_skipped << "\n";
    }
  }

  // compare.json
  const fs::path out(o.out);
  fs::create_directories(out);
  json result = {{"diagram", o.diagram},
                 {"measurement", o.measurement},
                 {"mode", mode},
                 {"samples", log.rows()},
                 {"output", primary_after.connector},
                 {"unit", primary_after.unit},
                 {"rmse_before", primary_before.rmse},
                 {"rmse_after", primary_after.rmse},
                 {"fit_percent_before", primary_before.fit_percent},
                 {"fit_percent_after", primary_after.fit_percent},
                 {"outputs", ComparedOutputsJson(before, after)}};
  if (fit) result["fit"] = fit->ToJson();
  json ranked = json::array();
  if (diagnosis) {
    for (const auto& e : diagnosis->effects) {
      ranked.push_back({{"effect", e.effect}, {"score", e.score}, {"parameters", e.parameters},
                        {"description", e.description}});
    }
    result["missing_effect_found"] = diagnosis->missing_effect_found;
    result["position_time_indistinguishable"] = diagnosis->position_time_indistinguishable;
    result["summary"] = diagnosis->summary;
    result["details"] = diagnosis->ToJson();
  } else {
    result["missing_effect_found"] = false;
    result["summary"] = diagnosis_skipped;
  }
  result["diagnosis"] = ranked;
  result["notes"] = compared.notes;  // the intake's (merged rows, resampling, gaps), then the diagnosis's
  if (fallback) {
    json j = fallback->ToJson();
    if (fallback->model) {
      SaveGprModel(*fallback->model, out / "residual_gpr.json");
      j["model"] = (out / "residual_gpr.json").string();
    }
    result["nonparametric_fallback"] = j;
  } else if (!fallback_skipped.empty()) {
    result["nonparametric_fallback"] = {{"useful", false}, {"skipped", fallback_skipped}};
  }

  if (fit && !o.write_fitted.empty()) {
    WriteJsonFile(compared.fitted_diagram, o.write_fitted);
    result["fitted_diagram"] = o.write_fitted;
  }
  if (!o.suggest.empty() && diagnosis) {
    std::string why = "no missing effect found";
    json skipped = json::array();
    for (const auto& e : diagnosis->effects) {
      if (!o.suggest_effect.empty() && e.effect != o.suggest_effect) {
        why = fmt::format("no effect '{}' among the ranked ones", o.suggest_effect);
        continue;
      }
      if (!HasEffectBlock(e.effect)) {
        why = fmt::format("the top effects have no block yet (first: {})", e.effect);
        continue;
      }
      json amended;
      try {
        amended = SuggestAmendedDiagram(compared.compared_diagram, e, primary_after.connector);
      } catch (const std::invalid_argument& error) {  // e.g. a negative delay: say why, try the next effect
        std::cerr << fmt::format("not suggesting {}: {}\n", e.effect, error.what());
        skipped.push_back({{"effect", e.effect}, {"why_not", error.what()}});
        why = fmt::format("no ranked effect could be added (last: {}: {})", e.effect, error.what());
        continue;
      }
      WriteSuggestion(amended, diagram_json, o.suggest);
      result["suggested_diagram"] = {{"path", o.suggest}, {"effect", e.effect}};
      why.clear();
      break;
    }
    // Nothing in the catalogue named, but something left that depends on (x, v): the fallback's GP as a block. (Only
    // then: with effects named, the GP learned what their corrections leave, not the residual of this diagram.)
    const bool want_fallback = o.suggest_effect.empty() || o.suggest_effect == "nonparametric_fallback";
    if (!why.empty() && want_fallback && diagnosis->effects.empty() && fallback && fallback->model) {
      const std::string model = fs::absolute(out / "residual_gpr.json").string();
      WriteSuggestion(SuggestGprFallbackBlock(compared.compared_diagram, model, primary_after.connector), diagram_json,
                      o.suggest);
      result["suggested_diagram"] = {{"path", o.suggest}, {"effect", "nonparametric_fallback"}, {"model", model}};
      why.clear();
    }
    if (!why.empty()) result["suggested_diagram"] = {{"path", nullptr}, {"why_not", why}};
    if (!skipped.empty()) result["suggested_diagram"]["skipped"] = skipped;
  }
  WriteJsonFile(result, out / "compare.json");

  // report.html
  HtmlReport report(fmt::format("motionblocks compare: {} vs {}", fs::path(o.diagram).filename().string(),
                                fs::path(o.measurement).filename().string()));
  report.Paragraph(fmt::format("{} mode; {} samples. Output '{}' compared with column '{}'.", mode, log.rows(),
                               primary_after.connector, primary_after.column));
  std::vector<std::vector<std::string>> rows;
  for (std::size_t i = 0; i < after.size(); ++i) {
    rows.push_back({after[i].connector, fmt::format("{:.5g}", before[i].rmse), fmt::format("{:.5g}", after[i].rmse),
                    fmt::format("{:.2f}", before[i].fit_percent), fmt::format("{:.2f}", after[i].fit_percent),
                    after[i].unit});
  }
  report.Table({"output", "RMSE before fit", "RMSE after fit", "fit % before", "fit % after", "unit"}, rows);
  if (fit) {
    report.Heading("Fitted parameters (Levenberg–Marquardt)");
    std::vector<std::vector<std::string>> prow;
    for (std::size_t i = 0; i < params.size(); ++i) {
      const auto k = static_cast<Eigen::Index>(i);
      prow.push_back({params[i].name, fmt::format("{:.6g}", fit->initial(k)), fmt::format("{:.6g}", fit->estimate(k)),
                      fmt::format("± {:.3g}", 1.96 * fit->standard_error(k))});
    }
    report.Table({"parameter", "initial", "estimate", "95 % CI"}, prow);
    report.Paragraph(fmt::format("{}; {} iterations; condition number of the scaled Jacobian {:.3g}.", fit->status,
                                 fit->iterations, fit->condition_number));
  }
  for (const auto& note : log.notes()) report.Paragraph("Measurement: " + note);
  report.Heading("Where the model fails: what is missing");
  if (diagnosis) {
    report.Paragraph(diagnosis->summary);
    std::vector<std::vector<std::string>> drow;
    for (const auto& e : diagnosis->effects) {
      std::string ps;
      for (const auto& [k, v] : e.parameters) ps += fmt::format("{}{} = {:.5g}", ps.empty() ? "" : ", ", k, v);
      drow.push_back({e.effect, fmt::format("{:.1f} %", 100.0 * e.score),
                      fmt::format("{:.1f} %", 100.0 * e.cumulative_share), ps});
    }
    report.Table({"effect", "share of remaining held-out residual explained", "cumulative", "parameters"}, drow);
    for (const auto& e : diagnosis->effects) report.Paragraph(e.effect + ": " + e.description);
    for (const auto& n : diagnosis->notes) report.Paragraph(n);
    if (fallback) {
      report.Heading("What no catalogue effect explains (non-parametric fallback)");
      report.Paragraph(fallback->description);
    }
  } else {
    report.Paragraph(diagnosis_skipped);
  }
  report.Heading("Views");
  AddResidualFigures(&report, out, log, primary_after, residual_after, diagnosis ? &*diagnosis : nullptr,
                     o.position_column);
  report.Write(out / "report.html");

  std::cout << fmt::format("{}: RMSE {:.5g} → {:.5g} {} (fit {:.1f} % → {:.1f} %)\n", primary_after.connector,
                           primary_before.rmse, primary_after.rmse, primary_after.unit, primary_before.fit_percent,
                           primary_after.fit_percent);
  if (diagnosis) {
    std::cout << diagnosis->summary << "\n";
    for (const auto& e : diagnosis->effects) {
      std::cout << fmt::format("  {:<28} {:5.1f} %  {}\n", e.effect, 100.0 * e.score, e.description);
    }
  }
  if (fallback) std::cout << fallback->description << "\n";
  for (const auto& note : log.notes()) std::cout << "note: " << note << "\n";
  std::cout << fmt::format("wrote {}/compare.json and report.html\n", out.string());
}

}  // namespace

void SetupCompareCommand(CLI::App& app) {
  auto o = std::make_shared<CompareOptions>();
  auto* cmd = app.add_subcommand("compare", "Compare a model with a measurement, refit, find the missing effect");
  cmd->add_option("diagram", o->diagram, "diagram JSON file")->required()->check(CLI::ExistingFile);
  cmd->add_option("--measurement", o->measurement, "measurement log CSV (time_s first)")->required()->check(CLI::ExistingFile);
  cmd->add_option("--map", o->maps, "connector=column: read a connector from another column (repeatable)");
  cmd->add_option("--fit", o->fit, "parameters to refit: block.param,… (default: the diagram's \"free\" list)");
  cmd->add_flag("--no-fit", o->no_fit, "compare as is, refit nothing");
  cmd->add_flag("--no-gpr-fallback", o->no_gpr_fallback,
                "skip the TISO-GPR fitted to what the diagnosis leaves (it writes residual_gpr.json when it helps)");
  cmd->add_option("--set", o->overrides, "parameter override block.param=value (repeatable)");
  cmd->add_option("--suggest", o->suggest, "write the diagram amended with the top-ranked effect's block here");
  cmd->add_option("--suggest-effect", o->suggest_effect,
                  "with --suggest: the highest-ranked effect of this catalogue name instead of the top one "
                  "(e.g. velocity_dependent_ripple); when no effect is named but the TISO-GPR fallback helps, "
                  "--suggest adds its gpr block (nonparametric_fallback)");
  cmd->add_option("--write-fitted", o->write_fitted, "write the diagram with the fitted parameters here");
  cmd->add_option("--position-column", o->position_column, "measured position column [m, rad, rev or deg: the unit is the name's suffix]")->capture_default_str();
  cmd->add_option("--derivative-cutoff-hz", o->derivative_cutoff_hz,
                  "zero-phase low-pass cut-off before differentiating the position [Hz]")
      ->capture_default_str();
  cmd->add_option("--out", o->out, "output folder")->capture_default_str();
  cmd->callback([o] { RunCompare(*o); });
}

}  // namespace mb

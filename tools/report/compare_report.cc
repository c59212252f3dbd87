#include "tools/report/compare_report.h"

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "models/diagnosis/effect_registry.h"
#include "models/diagnosis/parameter_text.h"
#include "models/gpr/gpr_io.h"
#include "tools/report/output_files.h"
#include "tools/report/diagram_drawing.h"
#include "tools/report/report.h"
#include "tools/report/frequency_figures.h"
#include "tools/report/resid_figures.h"
#include "tools/report/residual_figures.h"
#include "tools/workflow/suggest.h"

namespace mb {

// The files of a compare in its folder (CompareOutputNames lists them with the figures and the drawing).
namespace {
constexpr const char* kCompareJson = "compare.json";
constexpr const char* kCompareReport = "report.html";
constexpr const char* kFallbackModel = "residual_gpr.json";
}  // namespace

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

// The fallback's model saved beside compare.json (its path in the record), the fitted and the amended diagrams.
void WriteFallbackAndDiagrams(const CompareOutcome& outcome, const CompareFiles& files, json* result) {
  const fs::path folder = fs::path(files.diagram).parent_path();  // what the diagram's file names are relative to
  if (outcome.fallback.gpr && outcome.fallback.gpr->model) {
    SaveGprModel(*outcome.fallback.gpr->model, files.out / kFallbackModel);
    (*result)["nonparametric_fallback"]["model"] = (files.out / kFallbackModel).string();
  }
  if (outcome.compared.fit && !files.write_fitted.empty()) {
    const auto outside = WriteDiagramFile(outcome.compared.fitted_diagram, folder, files.write_fitted);
    (*result)["fitted_diagram"] = files.write_fitted;
    if (!outside.empty()) (*result)["fitted_diagram_reads_outside_its_folder"] = outside;
  }
  if (files.suggest.empty() || !outcome.suggestion) return;
  const CompareSuggestion& s = *outcome.suggestion;
  if (s.diagram) {
    const auto outside = WriteDiagramFile(*s.diagram, folder, files.suggest);
    (*result)["suggested_diagram"] = {{"path", files.suggest}, {"effect", s.effect}, {"effects", s.effects}};
    if (!outside.empty()) (*result)["suggested_diagram"]["reads_outside_its_folder"] = outside;
    if (!s.model.empty()) (*result)["suggested_diagram"]["model"] = s.model;
  } else {
    (*result)["suggested_diagram"] = {{"path", nullptr}, {"why_not", s.why_not}};
  }
  if (!s.skipped.empty()) (*result)["suggested_diagram"]["skipped"] = s.skipped;
}

std::vector<std::vector<std::string>> FittedParameterRows(const DiagnosedComparison& compared) {
  const FitResult& fit = *compared.fit;
  std::vector<std::vector<std::string>> rows;
  for (std::size_t i = 0; i < compared.parameters.size(); ++i) {
    const auto k = static_cast<Eigen::Index>(i);
    rows.push_back({compared.parameters[i].name, fmt::format("{:.6g}", fit.initial(k)),
                    fmt::format("{:.6g}", fit.estimate(k)), fmt::format("± {:.3g}", 1.96 * fit.standard_error(k)),
                    compared.parameters[i].unit.empty() ? "1 (no unit)" : compared.parameters[i].unit});
  }
  return rows;
}

// A diagnosed effect's parameters with their units, integers as integers: "amplitude = 1.569 N, harmonics = 1,
// period = 16.29 mm" (FormatParameterValue, the diagnosis text's); the amplitude of Fourier columns in the output's
// unit.
std::string ParametersWithUnits(const DiagnosedEffect& e, const std::string& position_unit,
                                const std::string& output_unit) {
  const EffectType* type = EffectRegistry::Global().Find(e.effect);
  // The first harmonic's amplitude: of Fourier columns (the output's unit), or of Fourier columns scaled by |v|
  // (the output's unit per unit of speed); of other columns, no unit is claimed.
  std::string amplitude_unit;
  if (type && type->regressor_formula.starts_with("cos(")) amplitude_unit = output_unit;
  if (type && type->regressor_formula.starts_with("|v|·cos(")) {
    amplitude_unit = fmt::format("{}·s/{}", output_unit, position_unit);
  }
  std::string out;
  for (const auto& [name, value] : e.parameters) {
    std::string shown = FormatParameterValue(value, EffectParameterUnit(e.effect, name), position_unit);
    if (name == "amplitude" && !amplitude_unit.empty()) shown = fmt::format("{:.4g} {}", value, amplitude_unit);
    out += fmt::format("{}{} = {}", out.empty() ? "" : ", ", name, shown);
  }
  return out;
}

void AddDiagnosisSection(const CompareOutcome& outcome, const std::string& position_column,
                         const std::filesystem::path& out, HtmlReport* report) {
  const DiagnosisResult& diagnosis = *outcome.compared.diagnosis;
  report->Paragraph(diagnosis.summary);
  // In the order compare --suggest and improve apply them (the friction-law replacements first): cumulative rises.
  std::vector<std::vector<std::string>> rows;
  const std::string position_unit = PositionUnitToken(position_column);
  for (const DiagnosedEffect* e : EffectsInApplicationOrder(diagnosis)) {
    const bool law = IsFrictionLawReplacement(diagnosis, e->effect);
    rows.push_back({e->effect, law ? "friction law (replaces the model's)" : "missing effect",
                    fmt::format("{:.1f} %", 100.0 * e->score), fmt::format("{:.1f} %", 100.0 * e->cumulative_share),
                    ParametersWithUnits(*e, position_unit, outcome.primary_after().unit)});
  }
  report->Table({"effect", "kind", "share of remaining held-out residual explained", "cumulative", "parameters"},
                rows);
  // Each effect's description beside its evidence (the residual on the effect's own axis, the fit drawn over it), its
  // share and confidence; then the position periodogram with the chosen periods marked.
  AddEffectEvidence(report, out, outcome.compared, outcome.primary_after().unit, PositionUnitToken(position_column));
  if (outcome.equation_error_view && outcome.equation_error_view->diagnosis) {
    // Simulation mode: the same catalogue on the force the controller commanded against the plant's inverse.
    const EquationErrorView& view = *outcome.equation_error_view;
    report->Heading("Equation-error view: the commanded force against the plant's inverse");
    report->Paragraph(view.note);
    std::vector<std::vector<std::string>> view_rows;
    for (const DiagnosedEffect* e : EffectsInApplicationOrder(*view.diagnosis)) {
      view_rows.push_back({e->effect, fmt::format("{:.1f} %", 100.0 * e->score),
                           ParametersWithUnits(*e, position_unit, view.force_unit)});
    }
    report->Table({"effect", "share of remaining held-out force residual explained", "parameters"}, view_rows);
  }
  if (outcome.fallback.gpr) {
    report->Heading("What no catalogue effect explains (non-parametric fallback)");
    report->Paragraph(outcome.fallback.gpr->description);
  }
}

}  // namespace

std::vector<std::string> CompareOutputNames() {
  std::vector<std::string> names{kCompareJson, kCompareReport, kFallbackModel};
  for (const auto& name : DiagramDrawingFileNames()) names.push_back(name);
  for (const auto& name : FigureFileNames("*.png")) names.push_back(name);  // the residual figures
  return names;
}

json WriteCompareResults(const CompareOutcome& outcome, const MeasurementLog& log, const CompareFiles& files) {
  fs::create_directories(files.out);
  json result = outcome.ToJson(files.diagram, files.measurement);
  WriteFallbackAndDiagrams(outcome, files, &result);
  WriteJsonFile(result, files.out / kCompareJson);
  WriteCompareReport(outcome, log, files);
  return result;
}

void WriteCompareReport(const CompareOutcome& outcome, const MeasurementLog& log, const CompareFiles& files) {
  const DiagnosedComparison& compared = outcome.compared;
  const ComparedOutput& primary_after = outcome.primary_after();
  HtmlReport report(fmt::format("motionblocks compare: {} vs {}", fs::path(files.diagram).filename().string(),
                                fs::path(files.measurement).filename().string()),
                    InteractiveCharts{});
  report.Paragraph(fmt::format("{} mode; {} samples. Output '{}' compared with column '{}'.", Name(outcome.mode), log.rows(),
                               primary_after.connector, primary_after.column));
  std::vector<std::vector<std::string>> rows;
  for (std::size_t i = 0; i < compared.after.size(); ++i) {
    const ComparedOutput &before = compared.before[i], &after = compared.after[i];
    rows.push_back({after.connector, fmt::format("{:.5g}", before.rmse), fmt::format("{:.5g}", after.rmse),
                    fmt::format("{:.2f}", before.fit_percent), fmt::format("{:.2f}", after.fit_percent),
                    after.tracking_input.empty() ? "—"
                                                 : fmt::format("{:.2f} → {:.2f}", before.tracking_fit_percent,
                                                               after.tracking_fit_percent),
                    after.unit});
  }
  report.Table({"output", "RMSE before fit", "RMSE after fit", "fit % before", "fit % after",
                "tracking-error fit % (simulation mode)", "unit"},
               rows);
  AddDiagramDrawing(&report, compared.fitted_diagram, fs::path(files.diagram).parent_path(), files.diagram, {},
                    files.out);
  if (compared.fit) {
    report.Heading("Fitted parameters (Levenberg–Marquardt)");
    report.Table({"parameter", "initial", "estimate", "95 % CI", "unit"}, FittedParameterRows(compared));
    report.Paragraph(fmt::format("{}; {} iterations; condition number of the scaled Jacobian {:.3g}.",
                                 compared.fit->status, compared.fit->iterations, compared.fit->condition_number));
  }
  report.Heading("Where the model fails: what is missing");
  if (compared.diagnosis) {
    AddDiagnosisSection(outcome, files.position_column, files.out, &report);
  } else {
    report.Paragraph(compared.diagnosis_skipped);
  }
  report.Heading("Views");
  AddResidualFigures(&report, files.out, log, primary_after, primary_after.residual(), files.position_column);
  report.Heading("Residual analysis (as MATLAB resid): is the residual white and independent of the input?");
  AddResidFigures(&report, files.out, "", log, primary_after.residual(), nullptr,
                  ChooseResidInput(outcome.mode, compared.compared_diagram, fs::path(files.diagram).parent_path(), log,
                                   files.position_column));
  report.Heading("Frequency response: measured (as MATLAB tfestimate) vs the model linearised (as linmod, bode)");
  AddFrequencyResponseFigures(&report, files.out, outcome.mode, compared.fitted_diagram,
                              fs::path(files.diagram).parent_path(), log, primary_after);
  if (!compared.notes.empty()) {  // once (the intake's, then the diagnosis's), after the figures
    report.Heading("Notes");
    for (const auto& note : compared.notes) report.Paragraph(note);
  }
  report.Write(files.out / kCompareReport);
}

namespace {

// A diagram compare wrote elsewhere whose files lie outside its new folder: how to load it.
void PrintReadsOutsideNote(const std::string& written, const json& outside, std::ostream& notes) {
  if (outside.empty()) return;
  notes << fmt::format("note: {} reads files outside its folder ({}): load it with --allow-path DIR, or write it "
                       "beside the diagram\n",
                       written, fmt::join(outside.get<std::vector<std::string>>(), ", "));
}

// "; tracking-error fit 41.2 % → 63.0 % against 'reference'" in simulation mode (ComparedOutput::tracking_fit_percent).
std::string TrackingFit(const ComparedOutput& before, const ComparedOutput& after) {
  if (after.tracking_input.empty()) return "";
  return fmt::format("; tracking-error fit {:.1f} % → {:.1f} % against '{}'", before.tracking_fit_percent,
                     after.tracking_fit_percent, after.tracking_input);
}

}  // namespace

void PrintCompareSummary(const CompareOutcome& outcome, const json& written, const CompareFiles& files,
                         std::ostream& out, std::ostream& notes) {
  const ComparedOutput& before = outcome.primary_before();
  const ComparedOutput& after = outcome.primary_after();
  out << fmt::format("{}: RMSE {:.5g} → {:.5g} {} (fit {:.1f} % → {:.1f} %{})\n", after.connector, before.rmse,
                     after.rmse, after.unit, before.fit_percent, after.fit_percent, TrackingFit(before, after));
  if (const auto& diagnosis = outcome.compared.diagnosis) {
    out << diagnosis->summary << "\n";
    for (const DiagnosedEffect* e : EffectsInApplicationOrder(*diagnosis)) {  // the order --suggest applies them
      out << fmt::format("  {:<28} {:5.1f} %  {}\n", e->effect, 100.0 * e->score, e->description);
    }
  }
  if (outcome.equation_error_view && outcome.equation_error_view->diagnosis) {
    const DiagnosisResult& view = *outcome.equation_error_view->diagnosis;
    out << "equation-error view (the commanded force against the plant's inverse on the measured motion):\n";
    for (const DiagnosedEffect* e : EffectsInApplicationOrder(view)) {
      out << fmt::format("  {:<28} {:5.1f} %  {}\n", e->effect, 100.0 * e->score, e->description);
    }
  }
  if (outcome.fallback.gpr) out << outcome.fallback.gpr->description << "\n";
  for (const auto& note : outcome.compared.notes) out << "note: " << note << "\n";
  out << fmt::format("wrote {}/compare.json and report.html\n", files.out.string());
  const json suggested = written.value("suggested_diagram", json::object());
  if (outcome.suggestion && outcome.suggestion->diagram) {
    out << fmt::format("wrote {}: the diagram with {} added (free: their coefficients, refit by the next compare)\n",
                       files.suggest, fmt::join(outcome.suggestion->effects, ", then "));
  } else if (outcome.suggestion) {
    out << fmt::format("wrote no {}: {}\n", files.suggest, outcome.suggestion->why_not);
  }
  PrintReadsOutsideNote(files.suggest, suggested.value("reads_outside_its_folder", json::array()), notes);
  PrintReadsOutsideNote(files.write_fitted, written.value("fitted_diagram_reads_outside_its_folder", json::array()),
                        notes);
}

}  // namespace mb

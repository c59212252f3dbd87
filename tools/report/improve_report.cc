#include "tools/report/improve_report.h"

#include <fstream>
#include <set>
#include <stdexcept>
#include <system_error>

#include <fmt/format.h>

#include "engine/diagram_document.h"
#include "models/gpr/gpr_io.h"
#include "tools/report/output_files.h"
#include "tools/report/progress.h"
#include "tools/report/diagram_drawing.h"
#include "tools/report/report.h"
#include "tools/report/resid_figures.h"
#include "tools/report/residual_figures.h"
#include "tools/workflow/suggest.h"

namespace mb {

namespace fs = std::filesystem;
using nlohmann::json;

std::vector<std::string> ImproveOutputNames() {
  std::vector<std::string> names{"improve.json", "improved.json", "report.html", "residual_gpr.json",
                                 "improved_with_gp.json"};
  for (const auto& name : DiagramDrawingFileNames()) names.push_back(name);
  for (const auto& name : FigureFileNames("*.png")) names.push_back(name);
  return names;
}

void WriteImproveProgress(const ImproveResult& so_far, const fs::path& directory, const json& context) {
  fs::create_directories(directory);
  const fs::path folder = fs::path(context.value("diagram", "")).parent_path();  // the diagram's file names' base
  int k = 0;
  for (const auto& s : so_far.steps) {
    if (!s.accepted) continue;
    const fs::path dir = directory / fmt::format("step_{}", k++);
    fs::create_directories(dir);
    WriteDiagramFile(s.training.fitted_diagram, folder, dir / "diagram.json");
  }
  WriteDiagramFile(so_far.last_accepted().training.fitted_diagram, folder, directory / "improved.json");
  json j = context;
  j.update(so_far.ToJson());
  WriteJsonFile(j, directory / kImproveResultFile);
}

namespace {

// The id of step i's plots in the report (the step table links there): step 0's are the before/after figures.
std::string StepAnchor(std::size_t i) { return i == 0 ? "before-after" : fmt::format("step-{}", i); }

// A section per step tried after step 0 (id StepAnchor(i)): what it added, its verdict, and the residual on the
// measurement before it (the last accepted step's) and after its refit, against time.
void AddStepSections(HtmlReport* report, const ImproveResult& result, const MeasurementLog& training,
                     const fs::path& directory) {
  const ImproveStep* previous = &result.first();
  const auto t = ToStd(training.time());
  for (std::size_t i = 1; i < result.steps.size(); ++i) {
    const ImproveStep& s = result.steps[i];
    report->Heading(fmt::format("Step {}: + {} ({})", i, s.effect.empty() ? "(nothing)" : s.effect,
                                s.accepted ? "accepted" : "refused"),
                    StepAnchor(i));
    report->Paragraph(s.verdict);
    if (!s.training.after.empty() && !previous->training.after.empty() &&
        s.training.after.front().measured.size() == training.time().size()) {
      const ComparedOutput& before = previous->training.after.front();
      const ComparedOutput& after = s.training.after.front();
      Figure f{fmt::format("step_{}_residual.png", i),
               fmt::format("Step {}: residual against time, before it (RMSE {:.4g}) and after its refit (RMSE {:.4g})",
                           i, s.rmse_train_before, s.rmse_train),
               "time [s]", fmt::format("measured − model [{}]", after.unit), {}};
      f.series.push_back({t, ToStd(before.residual()), "before this step", "lines"});
      f.series.push_back({t, ToStd(after.residual()), s.accepted ? "after (accepted)" : "after (refused)", "lines"});
      f.x_link = "time";
      report->AddFigure(f, directory);
    }
    if (s.accepted) previous = &s;
  }
}

// The element names of a diagram's JSON (none for a diagram not given: a report written from parts).
std::vector<std::string> ElementNames(const nlohmann::json& diagram) {
  std::vector<std::string> names;
  if (!diagram.is_object() || !diagram.contains("elements") || !diagram["elements"].is_array()) return names;
  for (const auto& e : diagram["elements"]) {
    if (e.is_object() && e.contains("name") && e["name"].is_string()) names.push_back(e["name"]);
  }
  return names;
}

// Every element `improved` has and `given` has not: an effect's block and what wires it in (a sum).
std::vector<std::string> AddedElements(const nlohmann::json& given, const nlohmann::json& improved) {
  const std::vector<std::string> given_names = ElementNames(given);
  const std::set<std::string> before(given_names.begin(), given_names.end());
  std::vector<std::string> added;
  for (const auto& name : ElementNames(improved)) {
    if (!before.count(name)) added.push_back(name);
  }
  return added;
}

}  // namespace

void WriteImproveReport(const ImproveResult& result, const MeasurementLog& training, const MeasurementLog* validation,
                        const std::string& title, const fs::path& diagram_directory,
                        const std::string& position_column, const fs::path& directory) {
  fs::create_directories(directory);
  const ImproveStep& first = result.first();
  const ImproveStep& last = result.last_accepted();
  const std::string& unit = first.unit();
  HtmlReport report(title, InteractiveCharts{});
  report.Paragraph(fmt::format(
      "{} mode; output '{}' [{}]. Held-out error: {}. Stop: {}.", Name(first.training.mode),
      first.training.after.front().connector, unit,
      validation ? "the validation record " + validation->source() +
                       " (only the record's parameters refit: the ripple's position offset)"
                 : "contiguous 5-fold cross-validation on the measurement",
      result.stop_reason));
  std::vector<std::vector<std::string>> rows;
  std::vector<std::string> links;  // each row's step to its plots
  int k = 0;
  for (const auto& s : result.steps) {
    std::string key;
    if (s.training.fit) {
      for (std::size_t i = 0; i < s.training.parameters.size(); ++i) {
        if (s.element.empty() || s.training.parameters[i].block != s.element) continue;
        const auto p = static_cast<Eigen::Index>(i);
        if (s.training.parameters[i].parameter != "period" && s.training.parameters[i].parameter != "delay" &&
            s.training.parameters[i].parameter != "frequency_hz" && s.training.parameters[i].parameter != "gain") {
          continue;
        }
        key += fmt::format("{}{} = {:.6g} ± {:.2g}", key.empty() ? "" : "; ", s.training.parameters[i].name,
                           s.training.fit->estimate(p), s.training.fit->standard_error(p));
      }
    }
    if (key.empty() && s.diagnosed) key = DescribeParameters(s.diagnosed->parameters);
    links.push_back(StepAnchor(rows.size()));
    rows.push_back({s.accepted ? fmt::format("{}", k++) : "—", s.effect.empty() ? "(as given, refit)" : s.effect,
                    s.diagnosed ? fmt::format("{:.1f} %", 100.0 * s.diagnosed->score) : "", key,
                    fmt::format("{:.4g} → {:.4g}", s.rmse_train_before, s.rmse_train),
                    fmt::format("{:.4g} → {:.4g}", s.rmse_heldout_before, s.rmse_heldout), s.verdict});
  }
  report.Table({"step", "effect", "share explained", "key parameters (± 1 SE)", fmt::format("RMSE fit [{}]", unit),
                fmt::format("RMSE held out [{}]", unit), "verdict"},
               rows, links);

  DrawingMarks added;
  added.added_label = "added by improve";
  added.added = AddedElements(result.steps.front().training.fitted_diagram, last.training.fitted_diagram);
  AddDiagramDrawing(&report, last.training.fitted_diagram, diagram_directory, title, added, directory);

  report.Heading("RMSE per step");
  Figure bars{"rmse_per_step.png", "RMSE per accepted step", "step", fmt::format("RMSE [{}]", unit), {}};
  Series train{{}, {}, "fit (measurement)", "boxes"}, held{{}, {}, "held out", "boxes"};
  k = 0;
  for (const auto& s : result.steps) {
    if (!s.accepted) continue;
    train.x.push_back(k - 0.18);
    train.y.push_back(s.rmse_train);
    held.x.push_back(k + 0.18);
    held.y.push_back(s.rmse_heldout);
    bars.x_tick_labels.emplace_back(k, s.effect.empty() ? "0: as given" : fmt::format("{}: + {}", k, s.effect));
    ++k;
  }
  bars.series = {train, held};
  report.AddFigure(bars, directory);

  report.Heading("Before (step 0, refit) and after (improved): the measurement", StepAnchor(0));
  const std::string record = fs::path(training.source()).filename().string();
  AddBeforeAfterFigures(&report, directory, "", record, training, first.training.after.front(),
                        last.training.after.front(), position_column);
  AddResidualSpectrumAndHistogram(&report, directory, "", record, training, first.training.after.front(),
                                  last.training.after.front());
  if (validation && first.validation && last.validation) {
    report.Heading("Before and after: the validation record (held out)");
    const std::string held_out = fs::path(validation->source()).filename().string();
    AddBeforeAfterFigures(&report, directory, "heldout_", held_out, *validation, first.validation->outputs.front(),
                          last.validation->outputs.front(), position_column);
    AddResidualSpectrumAndHistogram(&report, directory, "heldout_", held_out, *validation,
                                    first.validation->outputs.front(), last.validation->outputs.front());
  }
  AddStepSections(&report, result, training, directory);
  if (last.training.diagnosis) {
    report.Heading("What is left");
    report.Paragraph(last.training.diagnosis->summary);
  }
  report.Heading("Residual analysis (as MATLAB resid), after the last accepted step");
  const Eigen::VectorXd residual_before = first.training.after.front().residual();
  AddResidFigures(&report, directory, "", training, last.training.after.front().residual(), &residual_before,
                  ChooseResidInput(first.training.mode, last.training.compared_diagram, diagram_directory, training,
                                   position_column));
  report.Write(directory / "report.html");
}


void RemoveEarlierImproveResult(const fs::path& out, const std::vector<std::string>& inputs) {
  const fs::path result = out / kImproveResultFile;
  std::error_code error;
  if (!fs::is_regular_file(result, error)) return;
  for (const auto& input : inputs) {
    if (!input.empty() && fs::equivalent(result, input, error)) return;
  }
  if (!fs::remove(result, error) && error) {
    throw std::runtime_error(fmt::format("{}: cannot remove the result of an earlier run ({}): remove it, or give "
                                         "another --out",
                                         result.string(), error.message()));
  }
}

json WriteImproveFallback(const ImproveResult& result, const FallbackOutcome& fallback, const fs::path& directory,
                          const fs::path& diagram_folder) {
  json record = ImproveFallbackRecord(fallback);
  if (fallback.gpr && fallback.gpr->model) {
    // The model and the amended diagram side by side in DIR: the diagram names the model by its file name and its
    // other files relative to DIR, so that it loads from there (an absolute name outside the diagram's folder is
    // refused by the loader). A fallback that cannot be added (no position or velocity input) is a note: the loop's
    // result stands, and improve ends normally.
    try {
      const ImproveStep& last = result.last_accepted();
      const fs::path model = directory / "residual_gpr.json";
      SaveGprModel(*fallback.gpr->model, model.string());
      record["model"] = fs::absolute(model).string();
      DiagramDocument fitted(last.training.fitted_diagram, diagram_folder);
      fitted.RelocateFiles(fs::absolute(directory));
      const json amended =
          SuggestGprFallbackBlock(fitted.json(), model.filename().string(), last.training.after.front().connector,
                                  directory);
      WriteDiagramFile(amended, directory, directory / "improved_with_gp.json");
      record["diagram"] = (directory / "improved_with_gp.json").string();
    } catch (const std::exception& e) {
      record["diagram_skipped"] = e.what();
      record["description"] = record.value("description", std::string()) +
                              " The fallback was not added to a diagram: " + std::string(e.what());
    }
  }
  std::ifstream in(directory / kImproveResultFile);
  json written = json::parse(in);
  written["nonparametric_fallback"] = record;
  WriteJsonFile(written, directory / kImproveResultFile);
  return record;
}

std::optional<json> WriteImproveResults(const ImproveOutcome& outcome, const MeasurementLog& training,
                                        const MeasurementLog* validation, const ImproveFiles& files) {
  std::optional<json> fallback_record;  // its files (residual_gpr.json, improved_with_gp.json) named in it
  if (outcome.fallback.attempted) {
    fallback_record = WriteImproveFallback(outcome.result, outcome.fallback, files.out, files.diagram_folder);
  }
  ProgressNote("improve: writing the report …");
  WriteImproveReport(outcome.result, training, validation,
                     fmt::format("motionblocks improve: {} on {}", fs::path(files.diagram).filename().string(),
                                 fs::path(files.measurement).filename().string()),
                     files.diagram_folder, files.position_column, files.out);
  // Last: improve.json whole, with the stop and its reason and "complete": true; the fallback's record with its files.
  json final_result = outcome.ToJson();
  if (fallback_record) final_result["nonparametric_fallback"] = *fallback_record;
  WriteJsonFile(final_result, files.out / kImproveResultFile);
  return fallback_record;
}

void PrintImproveSummary(const ImproveResult& result, const std::optional<json>& fallback, const fs::path& directory,
                         std::ostream& out) {
  int k = 0;
  for (const auto& s : result.steps) {
    out << fmt::format("{:>4}  {:<28} fit RMSE {:.4g} → {:.4g}  held out {:.4g} → {:.4g} {}  {}\n",
                       s.accepted ? fmt::format("{}", k++) : "—", s.effect.empty() ? "(as given, refit)" : s.effect,
                       s.rmse_train_before, s.rmse_train, s.rmse_heldout_before, s.rmse_heldout, s.unit(),
                       s.accepted ? "" : "(rejected)");
  }
  out << "stop: " << result.stop_reason << "\n";
  if (fallback) out << (*fallback)["description"].get<std::string>() << "\n";
  out << fmt::format("wrote {}/improved.json, improve.json, step_*/diagram.json and report.html\n",
                     directory.string());
}

}  // namespace mb

#include "tools/improve.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>

#include <fmt/format.h>

#include "engine/diagram_document.h"
#include "models/diagnosis/effect_registry.h"
#include "tools/output_files.h"
#include "tools/report.h"
#include "tools/suggest.h"

namespace mb {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

std::vector<std::string> FreeList(const json& diagram) { return DiagramDocument(diagram).FreeParameters(); }

bool HasElement(const json& diagram, const std::string& name) { return DiagramDocument(diagram).Has(name); }

std::string BlockOf(const std::string& parameter) { return parameter.substr(0, parameter.find('.')); }

// The held-out score of a fitted diagram on the validation record: only the record's parameters refit.
HeldOutScore ScoreHeldOut(const json& diagram, const fs::path& base_directory, const std::string& source,
                          const MeasurementLog& validation, const ImproveSettings& settings) {
  ModelComparison comparison(diagram, base_directory, source, validation, settings.measurement.column_map);
  if (ExperimentMode(diagram) == "equation_error") {
    comparison.set_output_filter(settings.measurement.derivative_cutoff_hz);
  }
  std::vector<std::string> names;
  for (const auto& n : settings.validation_free.empty() ? RecordParameters(diagram) : settings.validation_free) {
    if (HasElement(diagram, BlockOf(n))) names.push_back(n);  // an effect element not added yet: nothing to refit
  }
  HeldOutScore score;
  if (names.empty()) {
    score.outputs = comparison.Simulate();
    return score;
  }
  const auto params = ResolveFreeParameters(comparison.diagram_json(), names);
  score.fit = FitParameters(comparison, params);
  score.outputs = comparison.Simulate(params, score.fit->estimate);
  return score;
}

// The held-out RMSE of a step: the validation record's, else the diagnosis' cross-validated one.
double HeldOutRmse(const ImproveStep& step) {
  if (step.validation) return step.validation->rmse();
  if (step.training.diagnosis) return step.training.diagnosis->heldout_rmse_base;
  return step.training.after.front().rmse;
}

std::string Unit(const ImproveStep& step) { return step.training.after.front().unit; }

std::string DescribeParameters(const std::map<std::string, double>& parameters) {
  std::string s;
  for (const auto& [k, v] : parameters) s += fmt::format("{}{} = {:.5g}", s.empty() ? "" : ", ", k, v);
  return s;
}

// Runs one amended (or the input) diagram through the training comparison and the held-out score.
ImproveStep Evaluate(const json& diagram, const fs::path& base_directory, const std::string& source,
                     const MeasurementLog& training, const MeasurementLog* validation,
                     const ImproveSettings& settings) {
  ImproveStep step;
  step.training =
      CompareAndDiagnose(diagram, base_directory, source, training, settings.measurement, FreeList(diagram));
  if (validation) step.validation = ScoreHeldOut(step.training.fitted_diagram, base_directory, source, *validation, settings);
  step.rmse_train = step.training.after.front().rmse;
  step.rmse_heldout = HeldOutRmse(step);
  return step;
}

// The diagram amended with `effect`: suggested on the comparison's copy (the log's experiment, which the
// delay block's sample time may need), then given back the input's own defaultExperiment; the element's name.
json Amend(const ImproveStep& current, const DiagnosedEffect& effect, bool refine_periods, std::string* element) {
  DiagramDocument amended(
      SuggestAmendedDiagram(current.training.compared_diagram, effect, current.training.after.front().connector));
  amended.CopyExperimentFrom(DiagramDocument(current.training.fitted_diagram));
  const auto before = FreeList(current.training.fitted_diagram);
  for (const auto& name : amended.FreeParameters()) {
    if (std::find(before.begin(), before.end(), name) == before.end()) {
      *element = BlockOf(name);
      break;
    }
  }
  if (refine_periods && !element->empty()) {
    for (const auto& parameter : LookupEffect(effect.effect).block->refinable) {
      amended.AddFreeParameter(*element + "." + parameter);
    }
  }
  return amended.json();
}

}  // namespace

std::vector<std::string> RecordParameters(const json& diagram) {
  std::vector<std::string> names;
  const DiagramDocument document(diagram);
  for (const auto& element : document.ElementNames()) {
    for (const auto& parameter : RecordSpecificParameters(document.TypeOf(element))) {
      names.push_back(element + "." + parameter);
    }
  }
  return names;
}

std::string ToString(ImproveStop stop) {
  switch (stop) {
    case ImproveStop::kNoMissingEffect: return "no_missing_effect";
    case ImproveStop::kCatalogueExhausted: return "catalogue_exhausted";
    case ImproveStop::kNoHeldOutGain: return "no_heldout_gain";
    case ImproveStop::kMaxEffects: return "max_effects";
  }
  return "?";
}

const ImproveStep& ImproveResult::last_accepted() const {
  for (auto it = steps.rbegin(); it != steps.rend(); ++it) {
    if (it->accepted) return *it;
  }
  throw std::logic_error("ImproveResult without steps");
}

json ImproveStep::ToJson() const {
  json j = {{"round", round},
            {"accepted", accepted},
            {"effect", effect.empty() ? json(nullptr) : json(effect)},
            {"element", element.empty() ? json(nullptr) : json(element)},
            {"verdict", verdict},
            {"output", training.after.front().connector},
            {"unit", Unit(*this)},
            {"rmse",
             {{"train_before", rmse_train_before},
              {"train", rmse_train},
              {"heldout_before", rmse_heldout_before},
              {"heldout", rmse_heldout},
              {"heldout_source", validation ? "validation record" : "cross-validation on the measurement"}}}};
  if (diagnosed) {
    j["diagnosis"] = {{"share_explained", diagnosed->score},
                      {"cumulative_share", diagnosed->cumulative_share},
                      {"parameters", diagnosed->parameters},
                      {"description", diagnosed->description}};
  }
  if (training.fit) {
    // The new element's parameters first (the key ones), then every refit parameter.
    json key = json::array(), all = training.fit->ToJson();
    for (const auto& p : all["parameters"]) {
      if (!element.empty() && BlockOf(p["name"].get<std::string>()) == element) key.push_back(p);
    }
    j["key_parameters"] = key;
    j["fit"] = all;
  }
  if (validation && validation->fit) j["validation_fit"] = validation->fit->ToJson();
  if (training.diagnosis) {
    j["diagnosis_after"] = {{"missing_effect_found", training.diagnosis->missing_effect_found},
                            {"summary", training.diagnosis->summary},
                            {"heldout_rmse_cross_validated", training.diagnosis->heldout_rmse_base},
                            {"ljung_box_p", training.diagnosis->whiteness_before.p_value}};
  }
  return j;
}

json ImproveResult::ToJson() const {
  json steps_json = json::array(), table = json::array();
  int k = 0;
  for (const auto& s : steps) {
    json j = s.ToJson();
    if (s.accepted) {
      j["step"] = k;
      table.push_back({{"step", k},
                       {"effect", s.effect.empty() ? json(nullptr) : json(s.effect)},
                       {"rmse_train", s.rmse_train},
                       {"rmse_heldout", s.rmse_heldout}});
      ++k;
    }
    steps_json.push_back(j);
  }
  return {{"steps", steps_json},
          {"accepted", table},
          {"stop", ToString(stop)},
          {"stop_reason", stop_reason},
          {"residual_not_white", residual_not_white}};
}

ImproveResult ImproveModel(const json& diagram, const fs::path& base_directory, const std::string& source,
                           const MeasurementLog& training, const MeasurementLog* validation,
                           const ImproveSettings& settings, const std::function<void(const std::string&)>& progress,
                           const ImproveStepCallback& on_step) {
  if (settings.max_effects < 0) throw std::invalid_argument("--max-effects must be >= 0");
  if (settings.max_trials_per_round < 1) throw std::invalid_argument("--max-trials must be >= 1");
  if (!(settings.min_relative_gain >= 0.0 && settings.min_relative_gain < 1.0)) {
    throw std::invalid_argument("--min-gain must be in [0, 1), a share of the held-out RMSE (e.g. 0.002)");
  }
  const auto say = [&](const std::string& line) {
    if (progress) progress(line);
  };
  // Validate the held-out record before any fitting: a wrong column shows in a second, not after the loop.
  if (validation) ModelComparison(diagram, base_directory, source, *validation, settings.measurement.column_map);

  ImproveResult result;
  const auto finish = [&](ImproveStep step) {
    result.steps.push_back(std::move(step));
    if (on_step) on_step(result.steps.back(), result);
  };

  say(fmt::format("step 0: refitting {} free parameter(s) of the diagram as given on {} ({} samples) …",
                  FreeList(diagram).size(), training.source(), training.rows()));
  ImproveStep step0 = Evaluate(diagram, base_directory, source, training, validation, settings);
  step0.rmse_train_before = step0.training.before.front().rmse;
  step0.rmse_heldout_before = step0.rmse_heldout;
  step0.verdict = "the diagram as given, its free parameters refit";
  say(fmt::format("step 0: RMSE {:.4g} → {:.4g} {} after the refit; held out {:.4g} {}", step0.rmse_train_before,
                  step0.rmse_train, Unit(step0), step0.rmse_heldout, Unit(step0)));
  finish(std::move(step0));

  int accepted = 0;
  for (int round = 1;; ++round) {
    if (accepted >= settings.max_effects) {
      result.stop = ImproveStop::kMaxEffects;
      result.stop_reason = fmt::format("stopped after --max-effects {} effect(s)", settings.max_effects);
      break;
    }
    // Copy: result.steps grows below.
    const ImproveStep current = result.last_accepted();
    const DiagnosisResult* diagnosis = current.training.diagnosis ? &*current.training.diagnosis : nullptr;
    if (!diagnosis) {
      result.stop = ImproveStop::kNoMissingEffect;
      result.stop_reason = current.training.diagnosis_skipped;
      break;
    }
    if (!diagnosis->missing_effect_found) {
      result.stop = ImproveStop::kNoMissingEffect;
      result.stop_reason = diagnosis->summary;
      break;
    }
    std::vector<const DiagnosedEffect*> candidates;
    for (const auto& e : diagnosis->effects) {
      if (HasEffectBlock(e.effect)) candidates.push_back(&e);
    }
    if (candidates.empty()) {
      result.stop = ImproveStop::kCatalogueExhausted;
      result.stop_reason = fmt::format("the ranked effects have no block to add (first: {})",
                                       diagnosis->effects.front().effect);
      break;
    }
    if (static_cast<int>(candidates.size()) > settings.max_trials_per_round) {
      candidates.resize(static_cast<std::size_t>(settings.max_trials_per_round));
    }
    const double heldout_before = current.rmse_heldout;
    bool accepted_this_round = false;
    for (const DiagnosedEffect* effect : candidates) {
      say(fmt::format("round {}: trying {} ({}; {:.1f} % of the held-out residual) — amend, refit jointly …", round,
                      effect->effect, DescribeParameters(effect->parameters), 100.0 * effect->score));
      ImproveStep step;
      std::string element;
      try {
        const json amended = Amend(current, *effect, settings.refine_periods, &element);
        step = Evaluate(amended, base_directory, source, training, validation, settings);
      } catch (const std::exception& e) {
        step = ImproveStep{};
        step.training = current.training;
        step.validation = current.validation;
        step.rmse_train = current.rmse_train;
        step.rmse_heldout = current.rmse_heldout;
        step.accepted = false;
        step.verdict = fmt::format("could not be added: {}", e.what());
      }
      step.round = round;
      step.effect = effect->effect;
      step.diagnosed = *effect;
      step.element = element;
      step.rmse_train_before = current.rmse_train;
      step.rmse_heldout_before = heldout_before;
      if (step.verdict.empty()) {
        const double gain = 1.0 - step.rmse_heldout / heldout_before;
        step.accepted = gain >= settings.min_relative_gain;
        step.verdict = fmt::format("{}: held-out RMSE {:.4g} → {:.4g} {} ({:+.2f} %, {} {:.2f} %)",
                                   step.accepted ? "accepted" : "rejected", heldout_before, step.rmse_heldout,
                                   Unit(step), -100.0 * gain, step.accepted ? "≥" : "<",
                                   100.0 * settings.min_relative_gain);
      }
      say(fmt::format("round {}: {} {}; train RMSE {:.4g} → {:.4g} {}", round, effect->effect, step.verdict,
                      step.rmse_train_before, step.rmse_train, Unit(step)));
      const bool ok = step.accepted;
      finish(std::move(step));
      if (ok) {
        accepted_this_round = true;
        ++accepted;
        break;
      }
    }
    if (!accepted_this_round) {
      result.stop = ImproveStop::kNoHeldOutGain;
      result.stop_reason = fmt::format(
          "none of the {} effect(s) tried in round {} lowered the held-out RMSE by {:.2f} % or more", candidates.size(),
          round, 100.0 * settings.min_relative_gain);
      break;
    }
  }
  // Non-parametric fallback goes here: the loop stopped, no catalogue block helps, but the last accepted
  // residual is not white — the structure is outside the catalogue (a TISO-GPR component on x, ẋ can take it).
  const ImproveStep& last = result.last_accepted();
  if (last.training.diagnosis && result.stop != ImproveStop::kMaxEffects) {
    result.residual_not_white = !last.training.diagnosis->whiteness_before.white;
    if (result.residual_not_white) {
      result.stop_reason += fmt::format(
          "; the residual is still not white (Ljung–Box p = {:.2g}): structure outside the catalogue",
          last.training.diagnosis->whiteness_before.p_value);
    }
  }
  say("stop: " + result.stop_reason);
  return result;
}

void WriteImproveProgress(const ImproveResult& so_far, const fs::path& directory, const json& context) {
  fs::create_directories(directory);
  int k = 0;
  for (const auto& s : so_far.steps) {
    if (!s.accepted) continue;
    const fs::path dir = directory / fmt::format("step_{}", k++);
    fs::create_directories(dir);
    WriteJsonFile(s.training.fitted_diagram, dir / "diagram.json");
  }
  WriteJsonFile(so_far.last_accepted().training.fitted_diagram, directory / "improved.json");
  json j = context;
  j.update(so_far.ToJson());
  WriteJsonFile(j, directory / "improve.json");
}

namespace {

std::vector<double> ToStd(const Eigen::VectorXd& v) { return {v.data(), v.data() + v.size()}; }

void AddBeforeAfterFigures(HtmlReport* report, const fs::path& out, const std::string& prefix,
                           const std::string& record, const MeasurementLog& log, const ComparedOutput& before,
                           const ComparedOutput& after, const std::string& position_column) {
  const auto t = ToStd(log.time());
  const std::string unit = before.unit;
  Figure overlay{prefix + "model_vs_measurement.png",
                 fmt::format("{}: measured {} vs model, before (step 0) and after (improved)", record, before.connector),
                 "time [s]", fmt::format("{} [{}]", before.connector, unit), {}};
  overlay.series.push_back({t, ToStd(before.measured), "measured (" + before.column + ")", "lines"});
  overlay.series.push_back({t, ToStd(before.model), "model before", "lines"});
  overlay.series.push_back({t, ToStd(after.model), "model after", "lines"});
  report->AddFigure(overlay, out);

  const auto r_before = ToStd(before.residual()), r_after = ToStd(after.residual());
  Figure rt{prefix + "residual_vs_time.png", record + ": residual against time, before vs after", "time [s]",
            fmt::format("measured − model [{}]", unit), {}};
  rt.series.push_back({t, r_before, "before", "lines"});
  rt.series.push_back({t, r_after, "after", "lines"});
  report->AddFigure(rt, out);
  // The residual against a logged column (position, velocity), before and after on the same axes.
  const auto against = [&](const std::string& column, const std::string& quantity, const std::string& axis_unit) {
    if (!log.has_column(column)) return;
    const auto abscissa = ToStd(log.column(column));
    Figure f{fmt::format("{}residual_vs_{}.png", prefix, quantity),
             fmt::format("{}: residual against {}, before vs after", record, quantity),
             fmt::format("{} [{}]", quantity, axis_unit), fmt::format("residual [{}]", unit), {}};
    f.series.push_back({abscissa, r_before, "before", "dots"});
    f.series.push_back({abscissa, r_after, "after", "dots"});
    report->AddFigure(f, out);
  };
  const std::string position_unit = ColumnUnit(position_column).empty() ? "m" : ColumnUnit(position_column);
  against(position_column, "position", position_unit);
  against(DerivedVelocityColumn(position_column), "velocity", position_unit + "/s");
}

}  // namespace

void WriteImproveReport(const ImproveResult& result, const MeasurementLog& training, const MeasurementLog* validation,
                        const std::string& title, const std::string& position_column, const fs::path& directory) {
  fs::create_directories(directory);
  const ImproveStep& first = result.first();
  const ImproveStep& last = result.last_accepted();
  const std::string unit = Unit(first);
  HtmlReport report(title);
  report.Paragraph(fmt::format(
      "{} mode; output '{}' [{}]. Held-out error: {}. Stop: {}.", first.training.mode,
      first.training.after.front().connector, unit,
      validation ? "the validation record " + validation->source() +
                       " (only the record's parameters refit: the ripple's position offset)"
                 : "contiguous 5-fold cross-validation on the measurement",
      result.stop_reason));
  std::vector<std::vector<std::string>> rows;
  int k = 0;
  for (const auto& s : result.steps) {
    std::string key;
    if (s.training.fit) {
      for (std::size_t i = 0; i < s.training.parameters.size(); ++i) {
        if (s.element.empty() || BlockOf(s.training.parameters[i].name) != s.element) continue;
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
    rows.push_back({s.accepted ? fmt::format("{}", k++) : "—", s.effect.empty() ? "(as given, refit)" : s.effect,
                    s.diagnosed ? fmt::format("{:.1f} %", 100.0 * s.diagnosed->score) : "", key,
                    fmt::format("{:.4g} → {:.4g}", s.rmse_train_before, s.rmse_train),
                    fmt::format("{:.4g} → {:.4g}", s.rmse_heldout_before, s.rmse_heldout), s.verdict});
  }
  report.Table({"step", "effect", "share explained", "key parameters (± 1 SE)", fmt::format("RMSE fit [{}]", unit),
                fmt::format("RMSE held out [{}]", unit), "verdict"},
               rows);

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

  report.Heading("Before (step 0, refit) and after (improved): the measurement");
  AddBeforeAfterFigures(&report, directory, "", fs::path(training.source()).filename().string(), training,
                        first.training.after.front(), last.training.after.front(), position_column);
  if (validation && first.validation && last.validation) {
    report.Heading("Before and after: the validation record (held out)");
    AddBeforeAfterFigures(&report, directory, "heldout_", fs::path(validation->source()).filename().string(),
                          *validation, first.validation->outputs.front(), last.validation->outputs.front(),
                          position_column);
  }
  if (last.training.diagnosis) {
    report.Heading("What is left");
    report.Paragraph(last.training.diagnosis->summary);
  }
  report.Write(directory / "report.html");
}

}  // namespace mb

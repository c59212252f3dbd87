#include "tools/workflow/compare.h"

#include <stdexcept>

#include <fmt/format.h>

#include "engine/diagram_document.h"
#include "tools/workflow/suggest.h"

namespace mb {

using nlohmann::json;

namespace {

void Say(const std::function<void(const std::string&)>& progress, const std::string& line) {
  if (progress) progress(line);
}

// An amended diagram (suggested on the comparison's copy) with the input diagram's own defaultExperiment.
json WithExperimentOf(const json& amended, const json& input) {
  DiagramDocument document(amended);
  document.CopyExperimentFrom(DiagramDocument(input));
  return document.json();
}

}  // namespace

CompareSuggestion SuggestFromComparison(const json& input_diagram, const DiagnosedComparison& compared,
                                        const FallbackOutcome& fallback, const CompareSettings& settings,
                                        const std::function<void(const std::string&)>& progress) {
  CompareSuggestion suggestion;
  const std::string& output = compared.after.front().connector;
  const DiagnosisResult& diagnosis = *compared.diagnosis;
  json amended = compared.compared_diagram;
  // Adds `e`'s block to `amended`; one that cannot be added is skipped with the reason.
  const auto add = [&](const DiagnosedEffect& e) {
    try {
      if (!HasEffectBlock(e.effect)) {
        throw std::invalid_argument("no block for it yet: add it by hand (docs/diagnosis.md lists the catalogue)");
      }
      amended = SuggestAmendedDiagram(amended, e, output, compared.drive_force_source);
    } catch (const std::invalid_argument& error) {  // e.g. a negative delay: say why, go on with the next effect
      Say(progress, fmt::format("not suggesting {}: {}", e.effect, error.what()));
      suggestion.skipped.push_back({{"effect", e.effect}, {"why_not", error.what()}});
      return false;
    }
    suggestion.effects.push_back(e.effect);
    return true;
  };
  std::string why = "no missing effect found";
  if (!settings.suggest_effect.empty()) {
    why = fmt::format("no effect '{}' among the ranked ones", settings.suggest_effect);
    for (const auto& e : diagnosis.effects) {
      if (e.effect == settings.suggest_effect && add(e)) break;
    }
  } else {
    // compare's order: every friction-law replacement, then the top missing effect that can be added.
    for (const DiagnosedEffect* e : EffectsInApplicationOrder(diagnosis)) {
      if (add(*e) && !IsFrictionLawReplacement(diagnosis, e->effect)) break;
    }
  }
  if (!suggestion.effects.empty()) {
    suggestion.diagram = WithExperimentOf(amended, input_diagram);
    suggestion.effect = suggestion.effects.back();
    return suggestion;
  }
  if (!suggestion.skipped.empty()) why = "no ranked effect could be added (see skipped)";
  // Nothing in the catalogue named, but something left that depends on (x, v): the fallback's GP as a block. (Only
  // then: with effects named, the GP learned what their corrections leave, not the residual of this diagram.)
  const bool want_fallback = settings.suggest_effect.empty() || settings.suggest_effect == "nonparametric_fallback";
  if (want_fallback && diagnosis.effects.empty() && fallback.gpr && fallback.gpr->model) {
    suggestion.diagram = WithExperimentOf(
        SuggestGprFallbackBlock(compared.compared_diagram, settings.fallback_model_path, output), input_diagram);
    suggestion.effect = "nonparametric_fallback";
    suggestion.effects = {suggestion.effect};
    suggestion.model = settings.fallback_model_path;
    return suggestion;
  }
  suggestion.why_not = why;
  return suggestion;
}

namespace {

// compare.json's "diagnosis" (the ranked effects) and what the diagnosis says, or why there is none.
void AddDiagnosisJson(const DiagnosedComparison& compared, json* result) {
  json ranked = json::array();
  if (compared.diagnosis) {
    const DiagnosisResult& diagnosis = *compared.diagnosis;
    for (const auto& e : diagnosis.effects) {
      ranked.push_back({{"effect", e.effect}, {"score", e.score}, {"parameters", e.ParametersJson()},
                        {"description", e.description}});
    }
    (*result)["missing_effect_found"] = diagnosis.missing_effect_found;
    (*result)["position_time_indistinguishable"] = diagnosis.position_time_indistinguishable;
    (*result)["summary"] = diagnosis.summary;
    (*result)["details"] = diagnosis.ToJson();
  } else {
    (*result)["missing_effect_found"] = false;
    (*result)["summary"] = compared.diagnosis_skipped;
  }
  (*result)["diagnosis"] = ranked;
  (*result)["notes"] = compared.notes;  // the intake's (merged rows, resampling, gaps), then the diagnosis's
}

// The fallback's record (the report library saves the model and adds its path).
void AddFallbackJson(const FallbackOutcome& fallback, json* result) {
  if (fallback.gpr) {
    (*result)["nonparametric_fallback"] = fallback.gpr->ToJson();
  } else if (!fallback.skipped.empty()) {
    (*result)["nonparametric_fallback"] = {{"useful", false}, {"skipped", fallback.skipped}};
  }
}

}  // namespace

json CompareOutcome::ToJson(const std::string& diagram, const std::string& measurement) const {
  json result = {{"diagram", diagram},
                 {"measurement", measurement},
                 {"mode", mode},
                 {"samples", samples},
                 {"output", primary_after().connector},
                 {"unit", primary_after().unit},
                 {"rmse_before", primary_before().rmse},
                 {"rmse_after", primary_after().rmse},
                 {"fit_percent_before", primary_before().fit_percent},
                 {"fit_percent_after", primary_after().fit_percent},
                 {"outputs", ComparedOutputsJson(compared.before, compared.after)}};
  if (compared.fit) result["fit"] = compared.fit->ToJson();
  AddDiagnosisJson(compared, &result);
  if (equation_error_view) result["equation_error_view"] = equation_error_view->ToJson();
  AddFallbackJson(fallback, &result);
  return result;
}

CompareOutcome Compare(const DiagramDocument& document, const MeasurementLog& log, const CompareSettings& settings,
                       const std::function<void(const std::string&)>& progress) {
  const json& diagram = document.json();
  CompareOutcome outcome;
  outcome.mode = ModeOf(diagram);
  outcome.samples = log.rows();
  // Refit the free parameters (settings.fit, else the diagram's "free" list).
  std::vector<std::string> fit_names = settings.fit;
  if (fit_names.empty() && !settings.no_fit) fit_names = document.FreeParameters();
  if (settings.no_fit) fit_names.clear();
  Say(progress, fmt::format("fitting {} parameter(s) by Levenberg–Marquardt, diagnosing the residual …",
                            fit_names.size()));
  outcome.compared = CompareAndDiagnose(diagram, document.base_directory(), document.source(), log,
                                        settings.measurement, fit_names);
  if (outcome.mode == ExperimentMode::kSimulation && outcome.compared.diagnosis) {
    Say(progress, "the equation-error view: the commanded force against the plant's inverse …");
    try {
      outcome.equation_error_view = DiagnoseEquationErrorView(outcome.compared, document.base_directory(),
                                                              document.source(), log, settings.measurement);
    } catch (const std::exception& e) {  // an opened diagram that cannot run: the position view stands, and it is said
      outcome.equation_error_view = EquationErrorView{};
      outcome.equation_error_view->skipped = fmt::format("the diagram opened at the plant could not run: {}", e.what());
    }
    const EquationErrorView& view = *outcome.equation_error_view;
    outcome.compared.notes.push_back(view.diagnosis ? view.note : "no equation-error view: " + view.skipped);
  }
  if (settings.gpr_fallback) outcome.fallback = FitCompareFallback(outcome.compared, progress);
  if (settings.suggest && outcome.compared.diagnosis) {
    outcome.suggestion = SuggestFromComparison(diagram, outcome.compared, outcome.fallback, settings, progress);
  }
  return outcome;
}

}  // namespace mb

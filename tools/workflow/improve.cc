#include "tools/workflow/improve.h"

#include <algorithm>
#include <cmath>
#include <set>
#include <stdexcept>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "engine/diagram_document.h"
#include "engine/numerical_error.h"
#include "models/diagnosis/effect_block.h"
#include "models/diagnosis/effect_registry.h"
#include "models/diagnosis/signal_processing.h"
#include "tools/workflow/measurement.h"
#include "tools/workflow/suggest.h"

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
  if (ModeOf(diagram) == ExperimentMode::kEquationError) {
    comparison.set_output_filter(settings.measurement.derivative_cutoff_hz);
  }
  std::vector<std::string> names;
  for (const auto& n : settings.validation_free.empty() ? RecordParameters(diagram) : settings.validation_free) {
    if (HasElement(diagram, BlockOf(n))) names.push_back(n);  // an effect element not added yet: nothing to refit
  }
  HeldOutScore score;
  if (names.empty()) {
    score.outputs = comparison.Simulate();
  } else {
    const auto params = ResolveFreeParameters(comparison.diagram_json(), names);
    score.fit = FitParameters(comparison, params);
    score.outputs = comparison.Simulate(params, score.fit->estimate);
  }
  const ComparedOutput& primary = score.outputs.front();
  score.primary_rmse = primary.rmse;
  if (comparison.output_filter_hz() > 0.0) {
    const double dt = MedianTimeStep(validation.time());
    const double cutoff = DerivativeCutoffHz(settings.measurement, validation);
    score.edge_samples = FilterEdgeSamples(validation.rows(), dt, cutoff);
    score.primary_rmse = InteriorRmse(primary.measured, primary.model, validation.segment_starts(), dt, cutoff);
  }
  return score;
}

// The held-out RMSE of a step: the validation record's, else the diagnosis' cross-validated one.
double HeldOutRmse(const ImproveStep& step) {
  if (step.validation) return step.validation->rmse();
  if (step.training.diagnosis) return step.training.diagnosis->heldout_rmse_base;
  return step.training.after.front().rmse;
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
      SuggestAmendedDiagram(current.training.compared_diagram, effect, current.training.after.front().connector,
                            current.training.drive_force_source));
  amended.CopyExperimentFrom(DiagramDocument(current.training.fitted_diagram));
  const std::optional<EffectBlockTemplate> block = BlockFor(LookupEffect(effect.effect));  // held: the loop reads it
  // The element added: the block of the first new free parameter of the template's type (a factor's element, a
  // friction factor's sign with its slip velocity free, may come first), else of the first new free parameter.
  const auto before = FreeList(current.training.fitted_diagram);
  for (const auto& name : amended.FreeParameters()) {
    if (std::find(before.begin(), before.end(), name) != before.end()) continue;
    if (element->empty()) *element = BlockOf(name);
    if (amended.TypeOf(BlockOf(name)) == block->block_type) {
      *element = BlockOf(name);
      break;
    }
  }
  if (element->empty()) {  // a block whose gain is its physics (an actuator lag's 1): the element it added
    const DiagramDocument was(current.training.fitted_diagram);
    for (const auto& name : amended.ElementsOfType(block->block_type)) {
      if (!was.Has(name)) *element = name;
    }
  }
  if (refine_periods && !element->empty()) {
    for (const auto& parameter : block->refinable) {
      amended.AddFreeParameter(*element + "." + parameter);
    }
  }
  return amended.json();
}

}  // namespace

std::string DescribeParameters(const std::map<std::string, double>& parameters) {
  std::string s;
  for (const auto& [k, v] : parameters) s += fmt::format("{}{} = {:.5g}", s.empty() ? "" : ", ", k, v);
  return s;
}

std::string NotSignificantReason(const FitResult& fit, const std::string& element,
                                 const std::vector<std::string>& exempt) {
  std::vector<std::string> held_zero;
  for (std::size_t i = 0; i < fit.parameters.size(); ++i) {
    const FreeParameter& p = fit.parameters[i];
    if (p.block != element || std::find(exempt.begin(), exempt.end(), p.parameter) != exempt.end()) continue;
    const auto k = static_cast<Eigen::Index>(i);
    const double estimate = fit.estimate(k), half_width = 1.96 * fit.standard_error(k);
    if (std::isfinite(half_width) && std::abs(estimate) > half_width) return "";
    held_zero.push_back(fmt::format("{} = {:.3g} ± {:.2g}", p.name, estimate, half_width));
  }
  if (held_zero.empty()) return "";
  return fmt::format("not significant: the 95 % interval of each of its parameters holds zero ({})",
                     fmt::join(held_zero, ", "));
}

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
            {"unit", unit()},
            {"rmse",
             {{"train_before", rmse_train_before},
              {"train", rmse_train},
              {"heldout_before", rmse_heldout_before},
              {"heldout", rmse_heldout},
              {"heldout_source", validation ? "validation record" : "cross-validation on the measurement"}}}};
  if (diagnosed) {
    j["diagnosis"] = {{"share_explained", diagnosed->score},
                      {"cumulative_share", diagnosed->cumulative_share},
                      {"parameters", diagnosed->ParametersJson()},
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
  if (validation) j["rmse"]["heldout_edge_samples"] = validation->edge_samples;
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
          {"noise_floor", noise_floor},
          {"stop", ToString(stop)},
          {"stop_reason", stop_reason},
          {"residual_not_white", residual_not_white}};
}

namespace {

void CheckImproveSettings(const ImproveSettings& settings) {
  if (settings.max_effects < 0) throw std::invalid_argument("--max-effects must be >= 0");
  if (settings.max_trials_per_round < 1) throw std::invalid_argument("--max-trials must be >= 1");
  if (!(settings.min_relative_gain >= 0.0 && settings.min_relative_gain < 1.0)) {
    throw std::invalid_argument("--min-gain must be in [0, 1), a share of the held-out RMSE (e.g. 0.002)");
  }
}

// A --validation-fit name must name an element of the diagram or one improve may add (an effect block's element:
// "ripple", "ripple_2", …); a misspelt one was skipped on every step without a word (tests/hostile).
void CheckValidationFree(const json& diagram, const ImproveSettings& settings) {
  std::set<std::string> addable;
  for (const EffectType* e : EffectRegistry::Global().Effects()) {
    if (const auto block = BlockFor(*e)) addable.insert(block->element_name);
  }
  for (const auto& name : settings.validation_free) {
    const std::string element = BlockOf(name);
    std::string stem = element;  // "ripple_2" → "ripple"
    if (const auto under = stem.rfind('_'); under != std::string::npos && under + 1 < stem.size() &&
        stem.find_first_not_of("0123456789", under + 1) == std::string::npos) {
      stem.resize(under);
    }
    if (HasElement(diagram, element) || addable.count(stem) > 0) continue;
    throw std::invalid_argument(fmt::format(
        "--validation-fit {}: no element '{}' in the diagram, nor one improve adds ({}); name a parameter as "
        "element.parameter",
        name, element, fmt::join(addable, ", ")));
  }
}

// The ranked effects of `current`'s diagnosis that a round tries, in compare's order (EffectsInApplicationOrder:
// the friction-law replacements first), those with a block; or none with `result`'s stop and reason set.
std::vector<const DiagnosedEffect*> RoundCandidates(const ImproveStep& current, ImproveResult* result) {
  const DiagnosisResult* diagnosis = current.training.diagnosis ? &*current.training.diagnosis : nullptr;
  if (!diagnosis) {
    result->stop = ImproveStop::kNoMissingEffect;
    result->stop_reason = current.training.diagnosis_skipped;
    return {};
  }
  if (!diagnosis->missing_effect_found) {
    result->stop = ImproveStop::kNoMissingEffect;
    result->stop_reason = diagnosis->summary;
    return {};
  }
  std::vector<const DiagnosedEffect*> candidates;
  for (const DiagnosedEffect* e : EffectsInApplicationOrder(*diagnosis)) {
    if (HasEffectBlock(e->effect)) candidates.push_back(e);
  }
  if (candidates.empty()) {
    result->stop = ImproveStop::kCatalogueExhausted;
    result->stop_reason =
        fmt::format("the ranked effects have no block to add (first: {})", diagnosis->effects.front().effect);
    return {};
  }
  return candidates;  // the round stops after max_trials_per_round of them were added and tried
}

// The added element's refit parameters that left their physical range (EffectBlockTemplate::physical_range), in
// words; "" when all stayed inside.
std::string OutOfPhysicalRange(const FitResult& fit, const std::string& element, const EffectBlockTemplate& block) {
  std::vector<std::string> outside;
  for (std::size_t i = 0; i < fit.parameters.size(); ++i) {
    const FreeParameter& p = fit.parameters[i];
    const auto range = block.physical_range.find(p.parameter);
    if (p.block != element || range == block.physical_range.end()) continue;
    const double value = fit.estimate(static_cast<Eigen::Index>(i));
    if (value >= range->second.first && value <= range->second.second) continue;
    outside.push_back(fmt::format("{} = {:.4g} outside [{:g}, {:g}]", p.name, value, range->second.first,
                                  range->second.second));
  }
  if (outside.empty()) return "";
  return fmt::format("the joint refit took it out of its physical range ({}): no longer the effect diagnosed",
                     fmt::join(outside, ", "));
}

// One trial of a round: `current` amended with `effect`, refit jointly, scored held out and accepted when the
// held-out RMSE falls by min_relative_gain; a suggestion or refit that fails is a rejected step with the reason.
ImproveStep TryEffect(const ImproveStep& current, const DiagnosedEffect& effect, int round,
                      const fs::path& base_directory, const std::string& source, const MeasurementLog& training,
                      const MeasurementLog* validation, const ImproveSettings& settings, double leak_floor) {
  ImproveStep step;
  std::string element;
  bool block_added = false;
  try {
    const json amended = Amend(current, effect, settings.refine_periods, &element);
    block_added = true;
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
  step.block_added = block_added;
  step.round = round;
  step.effect = effect.effect;
  step.diagnosed = effect;
  step.element = element;
  step.rmse_train_before = current.rmse_train;
  step.rmse_heldout_before = current.rmse_heldout;
  if (step.verdict.empty()) {
    const double gain = 1.0 - step.rmse_heldout / current.rmse_heldout;
    const EffectBlockTemplate block = *BlockFor(LookupEffect(effect.effect));  // the step was suggested: it has one
    const std::string not_significant =
        step.training.fit ? NotSignificantReason(*step.training.fit, step.element, block.refinable) : std::string();
    const std::string unphysical =
        step.training.fit ? OutOfPhysicalRange(*step.training.fit, step.element, block) : std::string();
    const double leak_limit = settings.leak_floor_ratio * leak_floor;
    const std::string leak =
        step.rmse_heldout < leak_limit
            ? fmt::format("a leak: its held-out RMSE lies below {:g} × the record's white noise floor ({:.4g} {}), "
                          "which no model of the physics can reach; it fits the measurement's own noise",
                          settings.leak_floor_ratio, leak_floor, step.unit())
            : std::string();
    step.accepted =
        gain >= settings.min_relative_gain && not_significant.empty() && unphysical.empty() && leak.empty();
    step.verdict = fmt::format("{}: held-out RMSE {:.4g} → {:.4g} {} ({:+.2f} %, {} {:.2f} %)",
                               step.accepted ? "accepted" : "rejected", current.rmse_heldout, step.rmse_heldout,
                               step.unit(), -100.0 * gain, gain >= settings.min_relative_gain ? "≥" : "<",
                               100.0 * settings.min_relative_gain);
    for (const std::string* reason : {&not_significant, &unphysical, &leak}) {
      if (!reason->empty()) step.verdict += "; " + *reason;
    }
  }
  return step;
}

// When the loop stopped before max_effects: is the last accepted residual still not white? Then the structure is
// outside the catalogue, and a non-parametric component (TISO-GPR on x, ẋ; fallback.h) can take it.
void NoteResidualWhiteness(ImproveResult* result) {
  const ImproveStep& last = result->last_accepted();
  if (!last.training.diagnosis || result->stop == ImproveStop::kMaxEffects) return;
  result->residual_not_white = !last.training.diagnosis->whiteness_before.white;
  if (result->residual_not_white) {
    result->stop_reason +=
        fmt::format("; the residual is still not white (Ljung–Box p = {:.2g}): structure outside the catalogue",
                    last.training.diagnosis->whiteness_before.p_value);
  }
}

}  // namespace

ImproveResult ImproveModel(const DiagramDocument& document, const MeasurementLog& training,
                           const MeasurementLog* validation, const ImproveSettings& settings,
                           const std::function<void(const std::string&)>& progress,
                           const ImproveStepCallback& on_step) {
  const json& diagram = document.json();
  const fs::path& base_directory = document.base_directory();
  const std::string& source = document.source();
  CheckImproveSettings(settings);
  CheckValidationFree(diagram, settings);
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
  // A log the diagram's parameters cannot be estimated from (no motion, collinear regressors) gives nothing to improve
  // on: refused as `fit` refuses it (exit 3), not a loop of meaningless steps (tests/hostile).
  if (step0.training.fit && !step0.training.fit->identifiable) {
    throw NumericalError(fmt::format("{}: the diagram's free parameters cannot be estimated from this log: {}; "
                                     "nothing to improve on (motionblocks fit says the same)",
                                     training.source(), step0.training.fit->identifiability_problem));
  }
  step0.rmse_train_before = step0.training.before.front().rmse;
  step0.rmse_heldout_before = step0.rmse_heldout;
  step0.verdict = "the diagram as given, its free parameters refit";
  // The floor reported is the whole (with the position's quantization); the leak guard compares with its white part,
  // as the diagnosis does (DiagnoseMissingEffects).
  double leak_floor = 0.0;
  if (step0.training.diagnosis) {
    result.noise_floor = step0.training.diagnosis->noise_floor.rms;
    leak_floor = step0.training.diagnosis->noise_floor.white_rms;
  }
  say(fmt::format("step 0: RMSE {:.4g} → {:.4g} {} after the refit; held out {:.4g} {}", step0.rmse_train_before,
                  step0.rmse_train, step0.unit(), step0.rmse_heldout, step0.unit()));
  finish(std::move(step0));

  for (int round = 1, accepted = 0;; ++round) {
    if (accepted >= settings.max_effects) {
      result.stop = ImproveStop::kMaxEffects;
      result.stop_reason = fmt::format("stopped after --max-effects {} effect(s)", settings.max_effects);
      break;
    }
    const ImproveStep current = result.last_accepted();  // a copy: result.steps grows below
    const std::vector<const DiagnosedEffect*> candidates = RoundCandidates(current, &result);
    if (candidates.empty()) break;
    bool accepted_this_round = false;
    int tried = 0;
    for (const DiagnosedEffect* effect : candidates) {
      if (tried >= settings.max_trials_per_round) break;
      say(fmt::format("round {}: trying {} ({}; {:.1f} % of the held-out residual) — amend, refit jointly …", round,
                      effect->effect, DescribeParameters(effect->parameters), 100.0 * effect->score));
      ImproveStep step =
          TryEffect(current, *effect, round, base_directory, source, training, validation, settings, leak_floor);
      say(fmt::format("round {}: {} {}; train RMSE {:.4g} → {:.4g} {}", round, effect->effect, step.verdict,
                      step.rmse_train_before, step.rmse_train, step.unit()));
      if (step.block_added) ++tried;
      // A product the training record could not tell from this one (DiagnosedEffect::alike_effects: the multipliers
      // differ too little over it) is tried in its place, and the held-out record decides — a record where they
      // differ tells them apart, as the diagnosis' note says. The one set aside is kept in the steps, not accepted.
      for (const DiagnosedEffect& alike : effect->alike_effects) {
        ImproveStep other =
            TryEffect(current, alike, round, base_directory, source, training, validation, settings, leak_floor);
        const bool better = other.accepted && (!step.accepted || other.rmse_heldout < step.rmse_heldout);
        ImproveStep& aside = better ? step : other;
        const ImproveStep& kept = better ? other : step;
        if (aside.block_added && kept.block_added && kept.accepted) {
          aside.verdict += fmt::format("; the training record could not tell {} from {}, the held-out one prefers {} "
                                       "(held-out RMSE {:.4g} against {:.4g} {})",
                                       effect->effect, alike.effect, kept.effect, kept.rmse_heldout,
                                       aside.rmse_heldout, kept.unit());
        }
        if (aside.accepted && aside.verdict.starts_with("accepted")) aside.verdict.replace(0, 8, "set aside");
        aside.accepted = false;
        say(fmt::format("round {}: {} tried in the place of {}: {}", round, alike.effect, effect->effect,
                        other.verdict));
        if (better) std::swap(step, other);
        finish(std::move(other));  // the one set aside, before the one kept
      }
      accepted_this_round = step.accepted;
      finish(std::move(step));
      if (accepted_this_round) break;
    }
    if (!accepted_this_round) {
      result.stop = ImproveStop::kNoHeldOutGain;
      result.stop_reason = fmt::format(
          "none of the {} effect(s) tried in round {} lowered the held-out RMSE by {:.2f} % or more with a "
          "significant coefficient", tried, round, 100.0 * settings.min_relative_gain);
      break;
    }
    ++accepted;
  }
  NoteResidualWhiteness(&result);
  say("stop: " + result.stop_reason);
  return result;
}

json ImproveOutcome::Head(bool complete) const {
  return {{"diagram", diagram},
          {"measurement", measurement},
          {"validation", validation ? json(*validation) : json(nullptr)},
          {"mode", mode},
          {"max_effects", max_effects},
          {"min_relative_gain", min_relative_gain},
          {"complete", complete}};
}

json ImproveOutcome::ToJson() const {
  json j = Head(true);
  j.update(result.ToJson());
  if (fallback.attempted) j["nonparametric_fallback"] = ImproveFallbackRecord(fallback);
  return j;
}

ImproveOutcome ImproveToMeasurement(const DiagramDocument& document, const MeasurementLog& training,
                                    const std::string& training_name, const MeasurementLog* validation,
                                    const std::string& validation_name, const ImproveSettings& settings,
                                    const std::function<void(const std::string&)>& progress,
                                    const ImproveProgressCallback& on_step) {
  ImproveOutcome outcome;
  outcome.diagram = document.source();
  outcome.measurement = training_name;
  if (validation) outcome.validation = validation_name;
  outcome.mode = document.Mode();
  outcome.max_effects = settings.max_effects;
  outcome.min_relative_gain = settings.min_relative_gain;
  const json head = outcome.Head(false);
  ImproveStepCallback each_step;
  if (on_step) each_step = [&](const ImproveStep&, const ImproveResult& so_far) { on_step(so_far, head); };
  outcome.result = ImproveModel(document, training, validation, settings, progress, each_step);
  if (settings.fallback) outcome.fallback = FitImproveFallback(outcome.result, progress);
  return outcome;
}

}  // namespace mb

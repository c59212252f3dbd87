#include "tools/workflow/fallback.h"

#include <exception>

#include "models/diagnosis/effect_registry.h"
#include "tools/workflow/improve.h"

namespace mb {

namespace {

void ReportFallbackProgress(const std::function<void(const std::string&)>& progress, const std::string& line) {
  if (progress) progress(line);
}

}  // namespace

FallbackOutcome FitCompareFallback(const DiagnosedComparison& compared,
                                   const std::function<void(const std::string&)>& progress) {
  FallbackOutcome outcome;
  if (!compared.diagnosis) return outcome;
  ReportFallbackProgress(progress,
                         "fitting the non-parametric fallback (TISO-GPR on position and velocity) to what is left …");
  outcome.attempted = true;
  try {
    outcome.gpr = FitResidualGprAfterDiagnosis(compared.signals, compared.base, *compared.diagnosis);
  } catch (const std::exception& e) {
    outcome.skipped = e.what();
    ReportFallbackProgress(progress, "no non-parametric fallback: " + outcome.skipped);
  }
  return outcome;
}

FallbackOutcome FitImproveFallback(const ImproveResult& result,
                                   const std::function<void(const std::string&)>& progress) {
  FallbackOutcome outcome;
  const ImproveStep& last = result.last_accepted();
  if (!result.residual_not_white || !last.training.diagnosis) return outcome;
  ReportFallbackProgress(progress,
                         "fitting the non-parametric fallback (TISO-GPR on position and velocity) to what is left …");
  outcome.attempted = true;
  ResidualGprOptions options;
  options.position_unit = last.training.diagnosis->position_unit;
  for (const auto& step : result.steps) {
    if (step.accepted && step.diagnosed && step.diagnosed->parameters.count("period") &&
        LookupEffect(step.effect).traits.periodicity == Periodicity::kPosition) {
      options.period = step.diagnosed->parameters.at("period");
      break;  // the first accepted period: the strongest (later ones are often its harmonics)
    }
  }
  try {
    outcome.gpr = FitResidualGpr(last.training.signals, last.training.signals.residual, options);
  } catch (const std::exception& e) {  // the loop's result stands without it (e.g. a log too short for the folds)
    outcome.skipped = e.what();
    ReportFallbackProgress(progress, std::string("no non-parametric fallback: ") + e.what());
  }
  return outcome;
}

nlohmann::json ImproveFallbackRecord(const FallbackOutcome& fallback) {
  if (fallback.gpr) return fallback.gpr->ToJson();
  return {{"useful", false}, {"skipped", fallback.skipped}, {"description", "no fallback: " + fallback.skipped}};
}

}  // namespace mb

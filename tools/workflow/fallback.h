#pragma once
// Fallback: when the catalogue of physical effects (models/diagnosis/effect_registry.h) leaves a residual that still
// depends on position and velocity, a TISO-GPR on (x, ẋ) takes over (models/gpr/residual_gpr.h): "PS" at the period
// of a position-periodic effect, else "DS", scored on held-out blocks. `compare` fits it to what the ranked effects
// leave; `improve` to the last accepted diagram's residual when the loop stops with a residual that is not white.

#include <functional>
#include <optional>
#include <string>

#include <nlohmann/json.hpp>

#include "models/gpr/residual_gpr.h"
#include "tools/workflow/comparison.h"

namespace mb {

struct ImproveResult;

/// A fitted fallback, or why there is none.
struct FallbackOutcome {
  bool attempted = false;                ///< the fit was needed and tried
  std::optional<ResidualGprResult> gpr;  ///< none: not fitted (not needed, or skipped)
  std::string skipped;                   ///< why the fit failed (e.g. a log too short for its folds); "" otherwise
};

/// compare's fallback: FitResidualGprAfterDiagnosis on the comparison's diagnosis signals and base regressors, when
/// the comparison was diagnosed. A fit that fails is recorded in `skipped` (the comparison stands without it).
/// `progress` gets one line per stage and the reason for a skip (may be empty).
FallbackOutcome FitCompareFallback(const DiagnosedComparison& compared,
                                   const std::function<void(const std::string&)>& progress = {});

/// improve's fallback: when the loop stopped with a residual that is not white and the last accepted step was
/// diagnosed, a TISO-GPR fitted to that step's residual — "PS" at the period of the first accepted
/// position-periodic effect (the strongest; later ones are often its harmonics), else "DS". A fit that fails is
/// recorded in `skipped`. `progress` as above.
FallbackOutcome FitImproveFallback(const ImproveResult& result,
                                   const std::function<void(const std::string&)>& progress = {});

/// improve.json's "nonparametric_fallback" record without the files: ResidualGprResult::ToJson, or {"useful": false,
/// "skipped", "description"} when the fit failed.
nlohmann::json ImproveFallbackRecord(const FallbackOutcome& fallback);

}  // namespace mb

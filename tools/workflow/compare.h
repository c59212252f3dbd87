#pragma once
// Compare: one `motionblocks compare` as a library call. The diagram bound to a measurement, its free parameters
// refit, the primary output's residual diagnosed (CompareAndDiagnose, comparison.h), the non-parametric fallback
// fitted to what the ranked effects leave (fallback.h), and the diagram amended with the friction-law replacements and
// the top missing effect (suggest.h). Nothing is written: tools/report/compare_report.h writes compare.json and report.html.

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/diagram_document.h"
#include "models/diagnosis/measurement_log.h"
#include "tools/workflow/comparison.h"
#include "tools/workflow/equation_error_view.h"
#include "tools/workflow/fallback.h"

namespace mb {

/// What `compare` is asked for.
struct CompareSettings {
  MeasurementSettings measurement;  ///< as the log was read (ReadMeasurementFor)
  /// Parameters to refit ("block.param"); empty: the diagram's "free" list. Ignored with `no_fit`.
  std::vector<std::string> fit;
  bool no_fit = false;              ///< compare as is, refit nothing
  bool gpr_fallback = true;         ///< fit the TISO-GPR fallback to what the diagnosis leaves
  bool suggest = false;             ///< amend the diagram with a ranked effect's block
  /// With `suggest`: the highest-ranked effect of this catalogue name instead of the top one; "" = the top one.
  /// "nonparametric_fallback" asks for the fallback's gpr block only.
  std::string suggest_effect;
  /// Where the fallback's model will be saved (absolute): the gpr block of a fallback suggestion loads it.
  std::string fallback_model_path;
};

/// The diagram amended with a diagnosed effect's block (or the fallback's gpr block), or why there is none.
struct CompareSuggestion {
  std::optional<nlohmann::json> diagram;  ///< the amended diagram, with the input diagram's own defaultExperiment
  /// The effects whose blocks it holds, in the order applied: the friction-law replacements, then the top missing
  /// effect (or the one effect asked for, or "nonparametric_fallback").
  std::vector<std::string> effects;
  std::string effect;                     ///< the last of `effects`: the top missing effect when there is one
  std::string model;                      ///< the fallback's model path (effect "nonparametric_fallback")
  std::string why_not;                    ///< no diagram: why
  nlohmann::json skipped = nlohmann::json::array();  ///< [{"effect", "why_not"}]: ranked effects that failed
};

/// Everything one compare found: fit, diagnosis, fallback, suggestion.
struct CompareOutcome {
  ExperimentMode mode = ExperimentMode::kSimulation;
  DiagnosedComparison compared;                 ///< the fit and the diagnosis (comparison.h)
  FallbackOutcome fallback;                     ///< the TISO-GPR fallback (set when diagnosed and asked)
  std::optional<CompareSuggestion> suggestion;  ///< set when asked and diagnosed
  /// Simulation mode, diagnosed: the commanded force against the plant's inverse (equation_error_view.h); its
  /// `skipped` says why there is none.
  std::optional<EquationErrorView> equation_error_view;
  Eigen::Index samples = 0;                     ///< the log's rows
  const ComparedOutput& primary_before() const { return compared.before.front(); }
  const ComparedOutput& primary_after() const { return compared.after.front(); }
  /// compare.json's content without the files a compare writes: `diagram` and `measurement` (as the caller names
  /// them), mode, samples, the primary output's RMSE and fit % before and after, every output, the fit, the ranked
  /// effects and the fallback's record (no "model" path, no fitted or suggested diagram). What the Python module's
  /// CompareOutcome.to_dict() gives; tools/report/compare_report.h adds the files.
  nlohmann::json ToJson(const std::string& diagram, const std::string& measurement) const;
};

/// Runs one compare of `diagram` (it holds its folder and its source for messages; --set already applied) against
/// `log` (read with ReadMeasurementFor and settings.measurement). `progress` gets one line per stage and why a ranked
/// effect could not be suggested (stderr in the command; may be empty). @throws as CompareAndDiagnose.
CompareOutcome Compare(const DiagramDocument& diagram, const MeasurementLog& log, const CompareSettings& settings,
                       const std::function<void(const std::string&)>& progress = {});

/// The suggestion step of Compare: the compared diagram amended, in compare's order (EffectsInApplicationOrder,
/// suggest.h), with every friction-law replacement and then the first missing effect whose block
/// SuggestAmendedDiagram can insert; with settings.suggest_effect, that effect's block alone. An effect that cannot be
/// added is skipped with the reason (CompareSuggestion::skipped). When no effect is named but the fallback has a
/// model, the fallback's gpr block. The amended diagram gets `input_diagram`'s defaultExperiment.
CompareSuggestion SuggestFromComparison(const nlohmann::json& input_diagram, const DiagnosedComparison& compared,
                                        const FallbackOutcome& fallback, const CompareSettings& settings,
                                        const std::function<void(const std::string&)>& progress = {});

}  // namespace mb

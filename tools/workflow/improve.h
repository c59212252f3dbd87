#pragma once
// `motionblocks improve`: the loop compare → suggest → fit → compare in one command (DIAGNOSIS.md, forward
// selection with the physical effect blocks in the diagram instead of regressors).
//
//   step 0   the diagram as given, its declared free parameters refit on the measurement (CompareAndDiagnose,
//            the path `compare` takes), scored on the measurement and on the held-out record;
//   round k  the ranked effects of the last accepted step's residual are tried in compare's order
//            (EffectsInApplicationOrder, suggest.h: the friction-law replacements first, then the missing effects by
//            share): the diagram is amended with the effect's block (SuggestAmendedDiagram), every free parameter is
//            refit jointly (base + all effects so far), and the amended diagram is scored again. The first effect
//            that lowers the held-out RMSE by at least min_relative_gain and has a significant coefficient (a 95 %
//            interval of one of the new element's refit parameters, its period aside, excludes zero) is accepted
//            and becomes step k; the ones before it are rejected (reported in improve.json, nothing of them kept in
//            improved.json).
//   stop     when the diagnosis finds no missing effect, when no ranked effect lowers the held-out error, or
//            after max_effects accepted effects.
//
// Held-out error. With a validation record: the RMSE of the primary output on that record (in equation-error mode
// without the derivative filter's edge transient at its ends, HeldOutScore::edge_samples), where only the
// parameters that belong to the record are refit — the position_offset x₀ of every position_periodic /
// velocity_dependent_ripple element (an incremental encoder is zeroed anew at each power-up; the ripple's shape
// belongs to the machine, its phase to the record) — everything else keeps its value from the measurement.
// Without one: the contiguous-block (5-fold) cross-validated RMSE of the diagnosis' linearised refit of the
// step's free parameters on the measurement (DiagnosisResult::heldout_rmse_base).

#include <filesystem>
#include <functional>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/diagram_document.h"
#include "engine/experiment_mode.h"
#include "models/diagnosis/diagnosis.h"
#include "models/diagnosis/measurement_log.h"
#include "tools/workflow/comparison.h"
#include "tools/workflow/fallback.h"

namespace mb {

struct ImproveSettings {
  MeasurementSettings measurement;  ///< columns, position column, derivative cut-off (as compare)
  int max_effects = 3;              ///< accepted effects at most (rounds), >= 0
  int max_trials_per_round = 3;     ///< ranked effects whose block was added, tried per round before giving up, >= 1
  double min_relative_gain = 0.002;  ///< accept an effect when held-out RMSE falls by at least this share, [0, 1)
  /// Free the refinable parameters of an added element (EffectBlockTemplate::refinable: the period of a
  /// position-periodic ripple) in the joint refit (as suggest frees a vibration's frequency): the periodogram's
  /// period is refined and gets a standard error.
  bool refine_periods = true;
  /// Parameters refit on the validation record ("block.param"); empty: RecordParameters of each step's diagram.
  std::vector<std::string> validation_free;
  /// ImproveToMeasurement: fit the TISO-GPR fallback when the loop stops with a residual that is not white
  /// (FitImproveFallback, fallback.h). ImproveModel, the loop alone, ignores it.
  bool fallback = true;
  /// No step may fit the noise: a step whose held-out RMSE falls below this fraction of the record's white noise floor
  /// (the first diagnosis' DiagnosisResult::noise_floor.white_rms) is refused as a leak. 0 = off.
  double leak_floor_ratio = 0.7;
};

/// The parameters that belong to a record rather than to the machine: "<element>.<parameter>" of every element whose
/// block type an effect's block template marks record-specific (RecordSpecificParameters, effect_registry.h: the
/// position_offset of the ripple blocks, the encoder's zero).
std::vector<std::string> RecordParameters(const nlohmann::json& diagram);

/// A diagnosed effect's parameters in words: "period = 0.0225, amplitude = 1.5" (sorted by name, 5 digits).
std::string DescribeParameters(const std::map<std::string, double>& parameters);

/// Why the element `element` that a step added is not significant, or "" when it is: the step fitted noise when the
/// 95 % interval (estimate ± 1.96 standard errors, FitResult) of every one of the element's refit parameters holds
/// zero or was not estimated (an infinite standard error), those named in `exempt` aside (EffectBlockTemplate::
/// refinable: a ripple's period, never near zero). "" too when `fit` refits nothing of the element. On EMPS a
/// 4.21 mm ripple of 0.001 N was accepted for a held-out gain alone (issue 27).
std::string NotSignificantReason(const FitResult& fit, const std::string& element,
                                 const std::vector<std::string>& exempt);

/// A diagram scored on the validation record.
struct HeldOutScore {
  std::vector<ComparedOutput> outputs;  ///< the first is the primary
  std::optional<FitResult> fit;         ///< of the record's parameters (none: nothing refit)
  /// Equation-error mode: samples left out of the score at each end of the record — the output filter's and the
  /// derived motion's edge transient (FilterEdgeSamples at the derivative cut-off), where the zero-phase low-pass
  /// reads its own padding, not the physics; per segment as the filter runs. 0 in simulation mode (the position as
  /// logged) or without the filter.
  Eigen::Index edge_samples = 0;
  /// The primary output's RMSE over the samples scored (all but edge_samples at each end) [its unit].
  double primary_rmse = 0.0;
  double rmse() const { return primary_rmse; }
};

/// One diagram of the loop: step 0 (the input) or an amended one, accepted or rejected.
struct ImproveStep {
  int round = 0;                       ///< 0 for the diagram as given
  bool accepted = true;
  std::string effect;                  ///< catalogue name of the added effect ("" at step 0)
  std::optional<DiagnosedEffect> diagnosed;  ///< the effect as the previous step's diagnosis ranked it
  std::string element;                 ///< name of the element the suggestion added
  std::string verdict;                 ///< why accepted or rejected, in words
  /// false: the effect's block could not be added to the diagram (the verdict says why: no block, a refusal); such a
  /// step is not one of a round's trials (ImproveSettings::max_trials_per_round).
  bool block_added = true;
  DiagnosedComparison training;        ///< joint refit and diagnosis on the measurement
  std::optional<HeldOutScore> validation;
  double rmse_train_before = 0.0;      ///< primary output, the last accepted step's after its refit
  double rmse_train = 0.0;             ///< after this step's refit
  double rmse_heldout_before = 0.0;    ///< the last accepted step's held-out RMSE
  double rmse_heldout = 0.0;           ///< this step's (validation record, or cross-validated: see above)
  /// Per step JSON for improve.json: effect, its diagnosis (share explained, parameters), the new element's
  /// fitted parameters with standard errors and 95 % intervals, RMSE train/held-out before and after.
  nlohmann::json ToJson() const;
  /// The primary output's unit.
  const std::string& unit() const { return training.after.front().unit; }
};

enum class ImproveStop {
  kNoMissingEffect,     ///< the diagnosis finds nothing (residual explained, or white)
  kCatalogueExhausted,  ///< effects found, but none has a block SuggestAmendedDiagram can insert
  kNoHeldOutGain,       ///< no tried effect lowered the held-out error with a significant coefficient
  kMaxEffects,          ///< max_effects accepted
};
std::string ToString(ImproveStop stop);

struct ImproveResult {
  std::vector<ImproveStep> steps;  ///< in the order tried; steps[0] is the diagram as given
  ImproveStop stop = ImproveStop::kMaxEffects;
  std::string stop_reason;         ///< in words, with the last diagnosis' whiteness when it matters
  /// When the loop stops with a residual that is still not white (Ljung–Box p < 0.01) and no catalogue effect
  /// explains it: the place for a non-parametric component (TISO-GPR on x, ẋ) to take over.
  bool residual_not_white = false;
  /// The training record's noise floor (RMS, the primary output's unit; 0 = unknown): no step can honestly go below it.
  double noise_floor = 0.0;
  const ImproveStep& first() const { return steps.front(); }
  const ImproveStep& last_accepted() const;
  nlohmann::json ToJson() const;
};

/// Called as each step completes (accepted or rejected), before the next starts: progress and files.
using ImproveStepCallback = std::function<void(const ImproveStep& step, const ImproveResult& so_far)>;

/// Runs the loop on `diagram` (it holds its folder and its source for messages) against `training`
/// and, if given, `validation` (both read with ReadMeasurementFor and the same settings). `progress` gets one line
/// per stage (stderr in the command). @throws std::invalid_argument for settings out of range, a validation record
/// the diagram cannot be compared with (checked before any fitting; the message names the file), and as
/// CompareAndDiagnose for step 0; NumericalError when step 0's parameters cannot be estimated from `training`
/// (FitResult::identifiable false: no motion, parameters that cannot be told apart). An amended diagram that fails (a suggestion that needs an input the diagram
/// lacks, a diverging refit) is a rejected step with the reason, not an error.
ImproveResult ImproveModel(const DiagramDocument& diagram, const MeasurementLog& training,
                           const MeasurementLog* validation, const ImproveSettings& settings,
                           const std::function<void(const std::string&)>& progress = {},
                           const ImproveStepCallback& on_step = {});

/// The improve use case (`motionblocks improve`, Python `motionblocks.improve`): the loop, its fallback, and what
/// improve.json's head names. The command line and the Python module only fill ImproveSettings, call
/// ImproveToMeasurement and print, write (tools/report/improve_report.h) or convert its ImproveOutcome.
struct ImproveOutcome {
  std::string diagram;                    ///< the diagram's source (DiagramDocument::source)
  std::string measurement;                ///< the training log's name, as given
  std::optional<std::string> validation;  ///< the held-out log's name; none: cross-validated on the measurement
  ExperimentMode mode = ExperimentMode::kSimulation;
  int max_effects = 0;                    ///< as asked (ImproveSettings)
  double min_relative_gain = 0.0;         ///< as asked (ImproveSettings)
  ImproveResult result;                   ///< the loop's steps and why it stopped
  FallbackOutcome fallback;               ///< attempted only with ImproveSettings::fallback, when needed
  /// improve.json's head: diagram, measurement, validation (null when none), mode, max_effects, min_relative_gain
  /// and "complete" (false in the files written while the loop runs).
  nlohmann::json Head(bool complete) const;
  /// improve.json less the files the command writes: Head(true), ImproveResult::ToJson and, when the fallback was
  /// attempted, its "nonparametric_fallback" record (ImproveFallbackRecord).
  nlohmann::json ToJson() const;
};

/// Called as each step completes with the result so far and improve.json's head (Head(false)): what
/// WriteImproveProgress (tools/report/improve_report.h) takes.
using ImproveProgressCallback = std::function<void(const ImproveResult& so_far, const nlohmann::json& head)>;

/// Runs ImproveModel on `document` (its folder and source) against `training` (named `training_name`) and, if
/// given, `validation` (named `validation_name`), then, with settings.fallback, FitImproveFallback. `progress` gets
/// the loop's and the fallback's lines. @throws as ImproveModel.
ImproveOutcome ImproveToMeasurement(const DiagramDocument& document, const MeasurementLog& training,
                                    const std::string& training_name, const MeasurementLog* validation,
                                    const std::string& validation_name, const ImproveSettings& settings,
                                    const std::function<void(const std::string&)>& progress = {},
                                    const ImproveProgressCallback& on_step = {});

}  // namespace mb

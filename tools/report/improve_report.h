#pragma once
// What `motionblocks improve` writes from an ImproveResult (tools/workflow/improve.h): the diagrams of the accepted
// steps as they complete, improve.json, report.html with the before/after figures (residual_figures.h), and the
// non-parametric fallback's files.

#include <filesystem>
#include <optional>
#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "models/diagnosis/measurement_log.h"
#include "tools/workflow/fallback.h"
#include "tools/workflow/improve.h"

namespace mb {

/// improve.json, the file that says whether the result is whole ("complete").
inline constexpr const char* kImproveResultFile = "improve.json";

/// Removes DIR/improve.json of an earlier run, unless it is one of `inputs` (paths as given; "" ignored), so that what
/// DIR holds while this run works is never taken for a finished result. @throws std::runtime_error naming the file
/// when it cannot be removed.
void RemoveEarlierImproveResult(const std::filesystem::path& out, const std::vector<std::string>& inputs);

/// The files an improve writes into its folder (exact names and figure patterns; "plot/…" for what draws the
/// figures), for RefuseOutputsOverInputs.
std::vector<std::string> ImproveOutputNames();

/// Writes DIR/step_<k>/diagram.json for an accepted step (k = accepted steps so far, 0 = the input refit),
/// DIR/improved.json (the best diagram so far) and DIR/improve.json (every step so far): call from on_step, so
/// that an interrupted run keeps what it finished. `context` (the inputs: diagram, logs) heads improve.json; its
/// "diagram" (the input diagram's path) is what the diagrams' file names are rewritten from (WriteDiagramFile).
/// @throws std::runtime_error if a file cannot be written.
void WriteImproveProgress(const ImproveResult& so_far, const std::filesystem::path& directory,
                          const nlohmann::json& context);

/// DIR/report.html: the table of steps (each row's first cell a link to its step's plots), the improved diagram drawn
/// (diagram_drawing.h; subsystem files against `diagram_directory`, the input diagram's folder) with the elements the
/// accepted steps added in kAddedColour, the RMSE per step (train and held-out bars), figures before (step 0) vs after
/// (last accepted) — measured vs model, the residual against time, position and velocity on the same axes, the
/// residual's spectrum and distribution (AddResidualSpectrumAndHistogram) — under the id "before-after", and a section
/// per step tried (id "step-<i>", i its index among the steps): its verdict and the residual before it and after its
/// refit. `position_column` as in the settings.
void WriteImproveReport(const ImproveResult& result, const MeasurementLog& training, const MeasurementLog* validation,
                        const std::string& title, const std::filesystem::path& diagram_directory,
                        const std::string& position_column, const std::filesystem::path& directory);

/// The fallback's files (FitImproveFallback, fallback.h): with a model, DIR/residual_gpr.json and
/// DIR/improved_with_gp.json (the last accepted diagram with the gpr block, SuggestGprFallbackBlock); its record
/// (ResidualGprResult::ToJson, or {"useful": false, "skipped", "description"}) is added to DIR/improve.json under
/// "nonparametric_fallback" and returned. Call after WriteImproveProgress. @throws std::runtime_error if a file cannot
/// be written or DIR/improve.json read. `diagram_folder`: the input diagram's folder (the diagrams' file names are
/// rewritten for DIR, WriteDiagramFile).
nlohmann::json WriteImproveFallback(const ImproveResult& result, const FallbackOutcome& fallback,
                                    const std::filesystem::path& directory,
                                    const std::filesystem::path& diagram_folder);

/// Where an improve's results go and what heads its report (as CompareFiles, compare_report.h).
struct ImproveFiles {
  std::string diagram;                          ///< the diagram file improved (as given)
  std::string measurement;                      ///< the training log (as given)
  std::filesystem::path diagram_folder;         ///< the diagram's folder (DiagramDocument::base_directory)
  std::filesystem::path out;                    ///< output folder
  std::string position_column = "position_m";  ///< for the residual-against-position figures
};

/// The files of an improve once its loop ended (ImproveToMeasurement, whose on_step wrote the steps with
/// WriteImproveProgress): the fallback's when it was attempted (WriteImproveFallback), report.html (WriteImproveReport,
/// titled "motionblocks improve: <diagram's file name> on <measurement's file name>"), and last improve.json whole
/// (ImproveOutcome::ToJson, "complete": true, with the fallback's record naming its files). Returns that record
/// (none when the fallback was not attempted). @throws std::runtime_error if a file cannot be written.
std::optional<nlohmann::json> WriteImproveResults(const ImproveOutcome& outcome, const MeasurementLog& training,
                                                  const MeasurementLog* validation, const ImproveFiles& files);

/// What `motionblocks improve` prints once WriteImproveResults wrote the files: a line per step tried (its number
/// among the accepted ones, or "—" when rejected; the effect; the fit and held-out RMSE before → after), the stop
/// and its reason, the fallback's description (`fallback`: its record) and the files written into `directory`.
void PrintImproveSummary(const ImproveResult& result, const std::optional<nlohmann::json>& fallback,
                         const std::filesystem::path& directory, std::ostream& out);

}  // namespace mb

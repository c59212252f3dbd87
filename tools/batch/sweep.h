#pragma once
// Parameter sweeps (`motionblocks sweep`): one diagram run many times with `id.param` values taken from a grid,
// an explicit list or a seeded random sample (the sweep file: sweep_spec.h); runs in parallel (TBB), one row of
// metrics per run in runs.csv and runs.json; resumable (runs already recorded as "ok", with the same values and finite
// metrics, are not run again). The steps shared with the MPI and shard runners: sweep_runner.h.

#include <filesystem>
#include <functional>
#include <map>
#include <ostream>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/simulator.h"
#include "tools/batch/sweep_spec.h"

namespace mb {

/// The diagram JSON with `assignments` written in: "defaultExperiment.*" and "solver.*" into those sections,
/// the rest through ApplyOverrides. @throws DiagramError for an unknown element (listing the elements).
nlohmann::json ApplySweepAssignments(nlohmann::json diagram,
                                     const std::vector<std::pair<std::string, nlohmann::json>>& assignments,
                                     const std::string& source);

/// One row of runs.csv / runs.json.
struct SweepRow {
  std::string id;
  std::string status;  ///< "ok" or "failed"
  std::vector<std::pair<std::string, nlohmann::json>> assignments;
  std::map<std::string, double> metrics;  ///< the diagram's metrics, SI units
  double wall_time_s = 0.0;
  std::string error;   ///< the exception's message for a failed run
  bool resumed = false;  ///< read back from an earlier runs.csv, not run now
};

struct SweepOptions {
  int jobs = 0;        ///< parallel runs; 0 = all hardware threads
  /// Skip runs recorded "ok" in an existing runs.csv with finite metrics (a row with a NaN or infinite metric, or a
  /// cell that is not a number, is run again); false: run everything, overwrite.
  bool resume = true;
  bool save_logs = false;  ///< also write <out>/runs/<id>/signals.csv for each run
  bool progress = true;    ///< a ProgressLine on stderr
  /// Also write <out>/report.html (WriteSweepReport, tools/report/sweep_report.h) once runs.csv and runs.json are.
  bool report = true;
  /// Called on the worker thread when a run finishes successfully, with the run's index in SweepSpec::runs and
  /// its result (logged signals and metrics). Not called for resumed runs. Must be thread-safe across indices.
  std::function<void(std::size_t, const SimulationResult&)> on_result;
};

struct SweepOutcome {
  std::vector<SweepRow> rows;  ///< one per run, in sweep order
  std::vector<std::string> metric_names;
  std::map<std::string, std::string> metric_units;
  int ran = 0;
  int resumed = 0;
  int failed = 0;
};

/// Runs the sweep over the diagram file and writes <out>/runs.csv (columns: id, status, the swept keys, the
/// diagram's metrics, wall_time_s, error; a row is appended as each run finishes, and the file is rewritten in
/// sweep order at the end) and <out>/runs.json (the same rows plus the diagram, the sweep and the metric units), then
/// <out>/report.html and its figures (options.report; tools/report/sweep_report.h).
/// A run that throws is recorded as "failed" with the message; the others go on.
/// @throws DiagramError if the diagram or an assignment's element is invalid (checked before any run),
/// std::runtime_error if runs.csv exists with other columns or records another value for a run id (a different
/// sweep: use another --out), or if an output file cannot be written (report.html: as WriteSweepReport).
SweepOutcome RunSweep(const std::filesystem::path& diagram, const SweepSpec& spec,
                      const std::filesystem::path& out, const SweepOptions& options = {});

/// CSV cell of a value: a JSON string without quotes, anything else as compact JSON.
std::string SweepValueText(const nlohmann::json& value);

/// The names of the files a sweep, or a shard of one, writes into its folder (runs.csv, runs.json, the shard's
/// manifest, the report's: SweepReportFileNames), for RefuseOutputsOverInputs (tools/report/output_files.h).
std::vector<std::string> SweepOutputNames();

/// Above kDefaultMaxSweepRuns (only with --max-runs raised), says on stderr (ProgressNote) how much memory the rows
/// will hold before runs.csv and runs.json are written; otherwise nothing.
void NoteSweepMemory(const SweepSpec& spec);

/// What `motionblocks sweep` prints once its runs are done: how many ran now, were already done and failed (of the
/// sweep's `kind`, and of shard `shard_label` unless it is ""), each failed run's error, and the files written into
/// `folder` (with runs/<id>/signals.csv when `saved_logs`).
void PrintSweepSummary(const SweepOutcome& outcome, const std::string& kind, const std::string& shard_label,
                       const std::string& folder, bool saved_logs, std::ostream& out);

}  // namespace mb

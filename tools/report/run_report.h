#pragma once
// What `motionblocks run` writes from a RunOutcome (tools/workflow/run.h): DIR/signals.csv (streamed during the run,
// RunSignalsFile), DIR/summary.json (metrics in SI units with their units, solver statistics, wall time) and
// DIR/report.html (the diagram's picture, the metrics and every logged signal as an interactive chart, time axes
// linked, with the PNGs as fallback). Complete or absent: RemoveEarlierRunFiles clears what an earlier run left, and
// each file is written whole by rename, so an interrupted run leaves no summary.json.

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/diagram.h"
#include "tools/workflow/run.h"

namespace mb {

/// Where a run's results go and what heads them.
struct RunFiles {
  std::string diagram;                 ///< the diagram file (as given)
  std::vector<std::string> overrides;  ///< the --set overrides (as given)
  std::filesystem::path out;           ///< output folder
};

/// The path of the streamed log in `out`: out/signals.csv.
std::filesystem::path RunSignalsFile(const std::filesystem::path& out);

/// The names of the files a run writes into its folder (patterns with '*' for the figures; "plot/…" for their
/// gnuplot scripts and data and the diagram's DOT text), for RefuseOutputsOverInputs (output_files.h).
std::vector<std::string> RunOutputNames();

/// Removes from `out` and its plot/ subfolder what an earlier run wrote there (RunOutputNames, and the temporary files
/// of a run that was killed: "<name>.tmp<pid>"), so that only one run's files are ever found beside each other.
/// Returns how many files were removed. @throws std::runtime_error naming a file that cannot be removed.
int RemoveEarlierRunFiles(const std::filesystem::path& out);

/// summary.json's content: diagram (absolute path), name, overrides, metrics [SI] and metric_units, solver
/// (type, steps, rhs_evaluations, roots_found, reinitialisations), wall_time_s, samples.
nlohmann::json RunSummaryJson(const Diagram& diagram, const RunFiles& files, const RunOutcome& outcome);

/// Writes summary.json and report.html into files.out (which must exist: signals.csv was streamed there).
/// @throws std::runtime_error if a file cannot be written.
void WriteRunResults(const Diagram& diagram, const RunFiles& files, const RunOutcome& outcome);

}  // namespace mb

#pragma once
// What `motionblocks compare` writes from a CompareOutcome (tools/workflow/compare.h): DIR/compare.json, the
// fallback's model DIR/residual_gpr.json, the fitted and the amended diagrams where asked, and DIR/report.html with
// the residual figures (residual_figures.h).

#include <filesystem>
#include <ostream>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "models/diagnosis/measurement_log.h"
#include "tools/workflow/compare.h"

namespace mb {

/// Where a compare's results go and what heads them.
struct CompareFiles {
  std::string diagram;              ///< the diagram file compared (as given)
  std::string measurement;          ///< the measurement log (as given)
  std::filesystem::path out;        ///< output folder: compare.json, report.html, residual_gpr.json
  std::string write_fitted;         ///< write the fitted diagram here ("" = not)
  std::string suggest;              ///< write the amended diagram here ("" = not asked)
  std::string position_column = "position_m";  ///< for the residual-against-position figures
};

/// The names of the files WriteCompareResults writes into CompareFiles::out (patterns with '*' for the figures;
/// "plot/…" for their gnuplot scripts and data and the diagram's DOT text), for RefuseOutputsOverInputs
/// (output_files.h).
std::vector<std::string> CompareOutputNames();

/// Writes every file of a compare (the folder is created) and returns compare.json's content: diagram,
/// CompareOutcome::ToJson plus the fallback's model path and the fitted and suggested diagrams' entries.
/// @throws std::runtime_error if a file cannot be written.
nlohmann::json WriteCompareResults(const CompareOutcome& outcome, const MeasurementLog& log, const CompareFiles& files);

/// DIR/report.html of a compare: the outputs before and after the fit, the fitted parameters, the ranked effects
/// and the residual figures. @throws std::runtime_error if it cannot be written.
void WriteCompareReport(const CompareOutcome& outcome, const MeasurementLog& log, const CompareFiles& files);

/// What `motionblocks compare` prints once WriteCompareResults wrote the files (`written`, compare.json's content): on
/// `out`, the primary output's RMSE and fit before → after, the diagnosis' summary and its effects in the order
/// --suggest applies them, the fallback's description, the notes, the files written and what --suggest wrote or why
/// not; on `notes` (stderr), for a written diagram that reads files outside its new folder, how to load it.
void PrintCompareSummary(const CompareOutcome& outcome, const nlohmann::json& written, const CompareFiles& files,
                         std::ostream& out, std::ostream& notes);

}  // namespace mb

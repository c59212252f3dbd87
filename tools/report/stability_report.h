#pragma once
// The files of `motionblocks stability`: stability.json (the analysis, models/stability/stability.h ToJson, with
// the inputs named) and report.html (the terms of section 4.2 side by side, the verdict, the notes, and the Bode
// magnitude and phase of eq. 6, 7 and 12, continuous against the sampled loop).

#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "models/stability/stability.h"

namespace mb {

/// What a stability analysis was run on, as the command names it.
struct StabilityFiles {
  std::string diagram;                 ///< the diagram file, as given
  std::string gpr;                     ///< the GPR model file, as given ("" = none)
  std::vector<std::string> overrides;  ///< the --set values
  std::filesystem::path out;           ///< the output folder (created)
};

/// The names WriteStabilityResults writes into StabilityFiles::out (OutputFolder::names).
std::vector<std::string> StabilityOutputNames();

/// Writes out/stability.json and out/report.html; `diagram_name` titles the report and `impulse_samples` is the
/// length the analysis used (StabilityOptions). Returns stability.json's content.
/// @throws std::runtime_error if a file cannot be written.
nlohmann::json WriteStabilityResults(const StabilityReport& report, const std::string& diagram_name,
                                     int impulse_samples, const StabilityFiles& files);

/// "1.234 N", "—" for NaN, "+∞"/"−∞": a term as the report and the command print it.
std::string StabilityTermText(double value, const char* unit = "");

}  // namespace mb

#pragma once
// The picture of a linearised diagram (`motionblocks linearize --report`): for each output–input pair, its gain and
// phase against frequency (Bode), with the operating point and the state list, as one interactive HTML page.

#include <filesystem>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "engine/linearization.h"

namespace mb {

/// The files WriteBodeReport writes into its folder (OutputFolder::names): report.html and the figures' files.
std::vector<std::string> BodeReportFileNames();

/// Writes `folder`/report.html with the Bode figures of `model` at `frequency_hz` (bode_gain.png, bode_phase.png and
/// their data beside it). @throws std::runtime_error if a file cannot be written.
void WriteBodeReport(const LinearModel& model, const Eigen::VectorXd& frequency_hz, const std::string& title,
                     const std::filesystem::path& folder);

}  // namespace mb

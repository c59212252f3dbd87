#pragma once
// Simulation mode's last refit of the chosen effects through the full diagram (DiagnoseMissingEffects, step 3g;
// simulated_refit.cc).

#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "models/diagnosis/diagnosis.h"
#include "models/diagnosis/joint_refinement.h"

namespace mb::diagnosis_detail {

// 3g. Simulation mode with a loop that can simulate (LoopResponse::can_simulate): the chosen effects' columns are
// simulated through the full diagram — the output's exact response to each force, where the search used the loop
// linearised at one stretch — and the ranking is rebuilt on them (their shares recomputed in the order chosen). An
// effect whose simulated columns the base's own parameters reproduce (DiagnosisOptions::redundant_with_base) is the
// base's and is dropped with a note: through the linearised loop it differed from the base's sensitivity by the
// linearisation's error alone, which it then fitted; so is one that, simulated, lowers the held-out error by less than
// DiagnosisOptions::min_gain (the selection's least gain). Returns the number of law replacements left. Throws what
// the simulation throws.
std::size_t RefitThroughTheDiagram(const DiagnosisSignals& signals, const Eigen::MatrixXd& base_cols,
                                   const DiagnosisOptions& options, std::size_t laws, Ranking* out,
                                   std::vector<std::string>* notes);

}  // namespace mb::diagnosis_detail

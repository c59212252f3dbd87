#pragma once
// 3e. A third factor by modulation (amplitude_selection.cc; issue 45, item 3): after the effects are chosen, each
// chosen product of the grammar is tried with its amplitude following time or each unread log column that is a new
// signal (amplitude_factor.h), and the best is kept on held-out evidence.

#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "models/diagnosis/diagnosis.h"
#include "models/diagnosis/joint_refinement.h"

namespace mb::diagnosis_detail {

// For each chosen effect after the `laws` friction-law replacements that is a product of the grammar
// (EffectType::multiplier; not a delay, a mode, a saturation or a law), the ranking's held-out error with its columns
// joined by its force times z̃ (amplitude_factor.h), for z the time and each unread column that varies and is a new
// signal (but the column the pair follows already). The best source is kept when the held-out
// gain over the ranking as it stands reaches options.min_gain, stays above the leak floor, and is significant
// (Diebold–Mariano, GainSignificance) at the family-wise t over the sources tried (FamilyWiseT); the ranking is then
// rebuilt with it (InstallRefined). Before that test, the factor may take over another chosen effect j that imitated
// it (a force settling in time where the amplitude drifts): with j left out the factor is significant, j beside it is
// not (backward elimination) and the two together beat the ranking by options.min_gain; then j is left out. A note
// says what was kept, or the best that was not and why. First, a chosen pair
// X × 1 and a chosen X × a column are merged into X whose amplitude follows that column (the same span; improve then
// adds them as one effect).
void ModulateChosenEffects(const DiagnosisSignals& signals, const Eigen::MatrixXd& base_cols,
                           const DiagnosisOptions& options, std::size_t laws, Ranking* out,
                           std::vector<std::string>* notes);

}  // namespace mb::diagnosis_detail

#pragma once
// A chosen effect compared again with its rivals of the same round, each at its refined shape
// (rival_reconsideration.cc; DiagnoseMissingEffects, step 3c′).

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "models/diagnosis/diagnosis.h"
#include "models/diagnosis/joint_refinement.h"

namespace mb::diagnosis_detail {

// 3c′. The forward selection compares candidates at the shapes the proposals found, each on the residual alone: a period,
// a frequency, a lag, a break time scanned with different precision. The chosen effect's shape is then refined with
// the others (RefineChosenEffects), its rivals' never were. Each rival (a candidate of the chosen one's round whose
// held-out MSE came within kRivalMargin of its own) is refit in its place, its shape parameter re-estimated jointly
// with the chosen effects (JointRefinement), and takes the place where the whole set's held-out MSE, under the
// ranking's weights, is lower by more than kHeldOutTie (the forward selection's ties): the selection's own criterion,
// each candidate at its best — a sequential replacement (Miller, Subset Selection in Regression, 2nd ed., 2002, ch. 3)
// among the round's near-equals. Grammar draw 878, a quadratic drag vibrating at 34.9 Hz: a 1.3 ms actuator lag, scanned finely, was chosen
// over the vibration at the periodogram's frequency; refit in its place, the vibration leaves a held-out MSE of 0.971
// against the lag's 1.174. A note says what each rival reached.
// Equation-error mode and simulation mode alike. Throws nothing of its own.
void ReconsiderRivals(const DiagnosisSignals& signals, const Eigen::MatrixXd& base_cols, const DiagnosisOptions& options,
                      std::size_t laws, const std::vector<std::pair<std::size_t, EffectInstance>>& rivals, Ranking* out,
                      std::vector<std::string>* notes);

}  // namespace mb::diagnosis_detail

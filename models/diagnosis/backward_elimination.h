#pragma once
// Pruning of the chosen effects once their parameters are refined (backward_elimination.cc; DiagnoseMissingEffects,
// step 3e).

#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "models/diagnosis/diagnosis.h"
#include "models/diagnosis/joint_refinement.h"

namespace mb::diagnosis_detail {

// 3e. Backward check once the parameters are refined: a friction-law replacement (when other effects were found behind
// it) whose removal from the full set raises the held-out error by less than min_gain, or insignificantly, took what an
// effect found later explains better; of the other effects, the weakest whose removal costs less than min_gain was
// chosen on a parameter the refinement has since moved. They are dropped (a note each), the rest refined again
// (JointRefinement). Returns the number of law replacements left.
std::size_t PruneChosenEffects(const DiagnosisSignals& signals, const Eigen::MatrixXd& base_cols,
                               const DiagnosisOptions& options, std::size_t laws, Ranking* out,
                               std::vector<std::string>* notes);

}  // namespace mb::diagnosis_detail

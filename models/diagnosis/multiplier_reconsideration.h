#pragma once
// The chosen products' multipliers chosen again once the laws and the other effects are refit with each
// (multiplier_reconsideration.cc; DiagnoseMissingEffects, step 3d′).

#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "models/diagnosis/diagnosis.h"
#include "models/diagnosis/joint_refinement.h"

namespace mb::diagnosis_detail {

// 3d′. The forward selection chose each product of the grammar in what the effects before it left, the friction-law
// replacements first: a Stribeck law takes part of a quadratic drag's v·|v| near zero speed, and the drive force's
// ŷ·|ŷ| then fits what is left better than v·|v| does. For each chosen product (in the order chosen), every other
// product of the same modulator at its shape is screened with the laws and the other effects as they are; the best of
// them (the lowest BIC) is refit jointly with them (JointRefinement) and takes the chosen one's place where the whole
// set's fit, under the ranking's weights, is better by its likelihood: a lower BIC and Vuong's test (Vuong 1989,
// Econometrica 57(2)) on the two sets' in-sample losses significant at DiagnosisOptions::significance_t,
// family-wise — Bonferroni — over the products screened, named or searched alike (the sets differ in one term of about
// the same size: the held-out blocks settled that the effect is there, its likelihood says which multiplier it
// carries); a note says which was tried and why it was kept or replaced. `out` changes only where a product is
// replaced.
// Equation-error mode only (not where CatalogueOptions::loop is set). Throws nothing of its own: a product with no
// columns on this record (its regressors throw std::invalid_argument: ŷ in simulation mode) is not tried.
void ReconsiderMultipliers(const DiagnosisSignals& signals, const Eigen::MatrixXd& base_cols,
                           const DiagnosisOptions& options, std::size_t laws, Ranking* out,
                           std::vector<std::string>* notes);

}  // namespace mb::diagnosis_detail

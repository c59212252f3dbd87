#pragma once
// Robust weighting of the diagnosis' least-squares fits (robust_weighting.cc): Huber weights found by iteratively
// reweighted least squares, so that a few badly modelled samples do not drag the base refit (DiagnosisOptions::huber_k).

#include <vector>

#include <Eigen/Core>

namespace mb::diagnosis_detail {

// The q-quantile (0..1) of v by selection, without interpolation (the element at ⌊q·(n−1)⌋ in sorted order); 0 for an
// empty v.
double Percentile(std::vector<double> v, double q);

// The robust scale of e: σ = 1.4826·MAD, the median absolute deviation from the median (consistent with the standard
// deviation for Gaussian noise; Huber, Robust Statistics, 1981). 0 for an empty e.
double RobustScale(const Eigen::VectorXd& e);

// Iteratively reweighted least squares of r on the columns x (N × q, q may be 0) with Huber weights (at most 10
// iterations, until no weight moves by 1e-3): the weights, and in `residual` r minus the weighted fit. k <= 0: plain
// least squares, all weights 1.
Eigen::VectorXd RobustWeights(const Eigen::MatrixXd& x, const Eigen::VectorXd& r, double k, Eigen::VectorXd* residual);

}  // namespace mb::diagnosis_detail

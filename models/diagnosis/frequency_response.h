#pragma once
// The frequency response of a system estimated from its input and output records: Welch's H1 estimator with the
// magnitude-squared coherence, as MATLAB's `tfestimate` / `mscohere` (Bendat & Piersol, Random Data, 4th ed., §9.2):
// H1(f) = P_uy(f) / P_uu(f), γ²(f) = |P_uy(f)|² / (P_uu(f) P_yy(f)), the cross and auto spectra averaged over
// Hann-windowed segments with 50 % overlap, each segment's mean removed. γ² near 1: y is linear in u at f and the
// estimate is good; near 0: noise, a nonlinearity or another input dominates y there.

#include <Eigen/Core>

namespace mb {

struct FrequencyResponseEstimate {
  Eigen::VectorXd frequency_hz;  ///< K bins, 0 … 1/(2 Ts) [Hz]
  Eigen::VectorXcd response;     ///< H1, K values [y unit / u unit]
  Eigen::VectorXd coherence;     ///< γ², K values in [0, 1]
  int segments = 0;              ///< segments averaged (γ² of a single segment is 1 everywhere: meaningless)
};

/// H1 and coherence of `output` against `input` (N samples each, sample period Ts [s]) over segments of
/// `segment_length` samples (clamped to N; a power of two is fastest).
/// @throws std::invalid_argument for a length mismatch, Ts <= 0, segment_length < 8, N < 8 or a non-finite sample.
FrequencyResponseEstimate EstimateFrequencyResponse(const Eigen::Ref<const Eigen::VectorXd>& input,
                                                    const Eigen::Ref<const Eigen::VectorXd>& output,
                                                    double sample_period, Eigen::Index segment_length = 1024);

}  // namespace mb

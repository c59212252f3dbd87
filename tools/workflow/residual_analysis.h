#pragma once
// Residual analysis as MATLAB's `resid`, in a user's words: is what the model leaves white (no structure left in
// time), and is it independent of the input (nothing left that the input explains)? The correlations themselves are
// the diagnosis's (models/diagnosis/signal_processing.h: ResidualAutocorrelation with its Ljung–Box test,
// InputResidualCrossCorrelation); this layer counts the lags outside the band and says what that means.
//
// Source: L. Ljung, System Identification: Theory for the User, 2nd ed., Prentice Hall 1999, §16.6 "Residual
// analysis". With ε the residual and u the input (means removed), the normalised correlations are
//   ρ_ε(τ)  = Σ_t ε(t+τ) ε(t) / Σ_t ε(t)²,                 τ = 0 … M,
//   ρ_εu(τ) = Σ_t ε(t+τ) u(t) / (‖ε‖ ‖u‖),                 τ = −M … M (positive τ: the residual after the input).
// If ε is white (and, for the cross-correlation, independent of u), √N ρ(τ) is asymptotically N(0, 1) for every
// τ ≠ 0, so a lag falls outside ±2.58/√N with probability 1 % — the 99 % band `resid` draws. The cross-correlation's
// band assumes a white residual; a coloured residual widens its true spread, so with a residual that fails the
// whiteness test a cross-correlation outside the band is only a guide.

#include <cstddef>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace mb {

/// Lags shown by default: ±25 samples (MATLAB `resid`'s default M = 25).
inline constexpr int kResidDefaultLags = 25;
/// A residual is called white (or independent of the input) when at most this share of its lags (τ ≠ 0) falls
/// outside the band: a 99 % band leaves 1 % outside by chance; 5 % allows for the few lags a long record shows.
inline constexpr double kResidMaxShareOutside = 0.05;

/// One correlation function with its band.
struct ResidualCorrelation {
  std::vector<int> lags;        ///< τ in samples, increasing: 0 … M (auto) or −M … M (cross)
  std::vector<double> values;   ///< ρ(τ), dimensionless in [−1, 1], one per lag
  double band = 0.0;            ///< the 99 % band's half-width 2.58/√N (ρ outside ±band: correlated at that lag)
  std::size_t tested = 0;       ///< lags tested against the band (every lag but τ = 0 of an autocorrelation)
  std::size_t outside = 0;      ///< tested lags with |ρ(τ)| > band
  int strongest_lag = 0;        ///< the tested lag of largest |ρ|
  double strongest = 0.0;       ///< ρ at that lag
  double ljung_box_p = -1.0;    ///< autocorrelation: the Ljung–Box test's p-value over the lags (< 0: not computed)
  /// outside ≤ kResidMaxShareOutside · tested: white (autocorrelation) or independent of the input (cross).
  bool within_band() const;
};

/// ρ_ε(τ), τ = 0 … max_lag, of `residual` (N samples, any unit), scored against the band; `ljung_box_p` set.
/// @throws std::invalid_argument as the diagnosis's ResidualAutocorrelation: max_lag < 1, N ≤ max_lag + 1, a value
/// not finite, or a constant residual.
ResidualCorrelation ResidAutocorrelation(const Eigen::Ref<const Eigen::VectorXd>& residual,
                                         int max_lag = kResidDefaultLags);

/// ρ_εu(τ), τ = −max_lag … max_lag, of `residual` ε and `input` u (same length N), scored against the band.
/// @throws std::invalid_argument as the diagnosis's InputResidualCrossCorrelation: different lengths,
/// N ≤ max_lag + 1, or a constant input or residual.
ResidualCorrelation ResidCrossCorrelation(const Eigen::Ref<const Eigen::VectorXd>& input,
                                          const Eigen::Ref<const Eigen::VectorXd>& residual,
                                          int max_lag = kResidDefaultLags);

/// What the two tests say, in a user's words, e.g. "The residual is not white: 25 of 25 lags lie outside the 99 %
/// band ±0.016 (strongest ρ = 0.93 at lag 1 sample = 1 ms): the model leaves structure in time." `sample_time`
/// [s] converts the strongest lag to time (≤ 0: samples only); `input_name` names the input.
std::string DescribeWhiteness(const ResidualCorrelation& autocorrelation, double sample_time);
std::string DescribeIndependence(const ResidualCorrelation& cross_correlation, const std::string& input_name,
                                 double sample_time);

}  // namespace mb

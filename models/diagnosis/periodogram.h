// Floating-mean Lomb–Scargle periodogram of a residual against an abscissa: the position (cogging,
// screw-lead ripple: periodic in x) or the time (vibration: periodic in t).
//
// power(P) = 1 − χ²(P)/χ²_0, the share of the residual's variance explained by the least-squares fit
//   r ≈ c0 + a·cos(2πx/P) + b·sin(2πx/P)          (Zechmeister & Kürster 2009; VanderPlas 2018 eq. 44)
// where χ²_0 = Σ (r − mean r)². False-alarm probability of a peak: Baluev (2008) eq. 5 with the
// "standard" normalisation (as astropy's `fap_baluev`).
//
// How it is fast (N = 25k, thousands of periods in milliseconds): the residual is averaged into uniform
// bins of the abscissa of width h = P_min/8 (the bin mean keeps the sample count as weight); the
// weighted sums Σw·e^{iθ}, Σw·r·e^{iθ}, Σw·e^{2iθ} (θ = 2πx/P) on the uniform bin grid are DFTs, computed
// for all frequencies at once by one zero-padded FFT each (frequency step ≤ 1/(4·span), i.e. 4× finer
// than a peak's width; Press & Rybicki 1989 use extirpolation for the same purpose). The binning
// attenuates a sinusoid of period P by sinc(h/P) in amplitude, ≥ 0.97 at P_min (a uniformly sampled
// abscissa such as time is binned at its own step: no attenuation); the within-bin
// variance stays in χ²_0, so power is still a share of the raw residual's variance. The reported
// curve on the log grid of trial periods is the maximum of the fine FFT grid inside each log cell
// (peak-preserving); peaks are refined by golden-section search on the exact binned power.
#pragma once

#include <vector>

#include <Eigen/Core>

namespace mb {

struct PeriodogramOptions {
  // Trial periods [unit of the abscissa: m or s]. <= 0: automatic, P_min = 4 × median |Δx| between
  // consecutive samples, P_max = (max x − min x)/2.
  double min_period = 0.0;
  double max_period = 0.0;
  // Number of trial periods on the log grid of the reported curve (the search itself uses the finer
  // FFT grid). >= 16.
  Eigen::Index num_periods = 2000;
  // How many distinct peaks to report (strongest first).
  Eigen::Index max_peaks = 5;
  // A peak is significant when its false-alarm probability is below this.
  double false_alarm_level = 0.01;
  // Samples counted by the false-alarm probability; <= 0: N. Pass a smaller effective sample size when
  // the residual is strongly autocorrelated (the Baluev formula assumes independent noise).
  double effective_samples = 0.0;
  // Relative tolerance when calling one peak a harmonic of another: P_strong/P_weak within this of an
  // integer k in 2..8 (or the inverse ratio: a sub-harmonic).
  double harmonic_tolerance = 0.01;
};

struct PeriodogramPeak {
  double period = 0.0;                   // refined period [m or s]
  double power = 0.0;                    // share of variance explained by this one sinusoid, 0..1
  double amplitude = 0.0;                // sqrt(a² + b²) [unit of the residual]
  double false_alarm_probability = 1.0;  // Baluev 2008
  bool significant = false;              // false_alarm_probability < options.false_alarm_level
  // Index (into Periodogram::peaks) of a stronger peak that this one is a harmonic (period P/k) or
  // sub-harmonic (period k·P) of; −1 when it is independent.
  int harmonic_of = -1;
  int harmonic_order = 0;                // k (P_strong/P_this for a harmonic, negative for a sub-harmonic)
};

struct Periodogram {
  Eigen::VectorXd periods;                  // log grid, ascending [m or s]
  Eigen::VectorXd power;                    // share of variance explained, 0..1, at each trial period
  std::vector<PeriodogramPeak> peaks;       // strongest first; harmonics flagged, not removed
  double min_period = 0.0, max_period = 0.0;
  double bin_width = 0.0;                   // h [m or s]
  Eigen::Index samples = 0;                 // N
  // The strongest peak (peaks.front()); throws std::logic_error when there is none.
  const PeriodogramPeak& best() const;
};

// Periodogram of residual r against abscissa x (any order; x need not be sorted or uniform).
// Throws std::invalid_argument on a size mismatch, N < 16, non-finite values, a constant residual,
// a zero abscissa span, or a period range that is empty (min >= max) or below 2 bin widths.
Periodogram LombScarglePeriodogram(const Eigen::Ref<const Eigen::VectorXd>& abscissa,
                                   const Eigen::Ref<const Eigen::VectorXd>& residual,
                                   const PeriodogramOptions& options = {});

// Position-domain periodogram (abscissa = position [m]); periods in m.
inline Periodogram PositionPeriodogram(const Eigen::Ref<const Eigen::VectorXd>& position,
                                       const Eigen::Ref<const Eigen::VectorXd>& residual,
                                       const PeriodogramOptions& options = {}) {
  return LombScarglePeriodogram(position, residual, options);
}

// Time-domain periodogram (abscissa = time [s]); periods in s.
inline Periodogram TimePeriodogram(const Eigen::Ref<const Eigen::VectorXd>& time,
                                   const Eigen::Ref<const Eigen::VectorXd>& residual,
                                   const PeriodogramOptions& options = {}) {
  return LombScarglePeriodogram(time, residual, options);
}

// Exact (unbinned) floating-mean Lomb–Scargle power at one period, 0..1; O(N). The reference the
// binned periodogram is tested against. Same throws as LombScarglePeriodogram for the data.
double LombScarglePower(const Eigen::Ref<const Eigen::VectorXd>& abscissa,
                        const Eigen::Ref<const Eigen::VectorXd>& residual, double period);

// Baluev (2008) false-alarm probability of the highest peak reaching `power` (standard normalisation,
// floating mean: d_H = 1, d_K = 3) among frequencies up to 1/min_period, for N samples whose abscissa
// has variance abscissa_variance. Returns a value in [0, 1].
double BaluevFalseAlarmProbability(double power, double samples, double min_period,
                                   double abscissa_variance);

}  // namespace mb

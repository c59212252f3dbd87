// Signal processing for model-vs-measurement comparison: zero-phase filtering and differentiation of a
// measured position, goodness-of-fit figures (MATLAB System Identification Toolbox `compare`), residual
// whiteness and input–residual correlation (`resid`), and the Welch power spectrum.
// All vectors are Eigen column vectors of one signal, sample i at time t(i); SI units throughout.
#pragma once

#include <vector>

#include <Eigen/Core>

namespace mb {

// Zero-phase low-pass: a 2nd-order Butterworth (bilinear transform with pre-warping) run forward then
// backward (MATLAB/SciPy `filtfilt`), so the magnitude is |H|² (−6 dB at the cut-off) and the phase is
// zero. The ends are padded by odd reflection (3 time constants) and the filter starts in the steady
// state of the first padded sample, so a constant or a ramp passes unchanged.
// This is what the EMPS benchmark's IDIM-LS does to the position before differentiating.
// signal: N samples; sample_period Ts [s]; cutoff_hz in (0, 0.5/Ts).
// Throws std::invalid_argument when N < 3, Ts <= 0 or the cut-off is not below the Nyquist frequency.
Eigen::VectorXd ZeroPhaseLowPass(const Eigen::Ref<const Eigen::VectorXd>& signal, double sample_period,
                                 double cutoff_hz);

// ZeroPhaseLowPass on every column of `columns` (N × k, N >= 3), in place: the same values, bit for bit, four columns
// at a time (their recursions interleaved, which the processor overlaps: 8 columns of 25,000 samples in 0.76 ms
// against 1.54 ms one after another, tests/benchmarks BM_ZeroPhaseLowPassColumns).
// Throws as ZeroPhaseLowPass, before any column is changed.
void ZeroPhaseLowPassColumns(Eigen::Ref<Eigen::MatrixXd> columns, double sample_period, double cutoff_hz);

// Derivative dy/dt by central differences, second-order accurate also on a non-uniform time grid
// (three-point Lagrange formula); one-sided second-order formulas at both ends.
// time, values: N >= 3 samples, time strictly increasing. Throws std::invalid_argument otherwise.
Eigen::VectorXd CentralDifference(const Eigen::Ref<const Eigen::VectorXd>& time,
                                  const Eigen::Ref<const Eigen::VectorXd>& values);

// y(t − delay) on the samples' own time grid by linear interpolation, held at the first (last) value before (after)
// the record: a signal delayed (delay > 0) or advanced (delay < 0) by `delay` [s]. time: N >= 2 samples, strictly
// increasing (not checked); values: N. Throws nothing.
Eigen::VectorXd ShiftedInTime(const Eigen::Ref<const Eigen::VectorXd>& time,
                              const Eigen::Ref<const Eigen::VectorXd>& values, double delay);

// Position, velocity and acceleration derived from a measured position.
struct MotionDerivatives {
  Eigen::VectorXd position;      // zero-phase low-passed position [m]
  Eigen::VectorXd velocity;      // [m/s]
  Eigen::VectorXd acceleration;  // [m/s²]
};

// IDIM-LS style derivation: low-pass the position with ZeroPhaseLowPass (cutoff_hz, sample period =
// median time step), then velocity and acceleration by CentralDifference.
// Throws std::invalid_argument as ZeroPhaseLowPass and CentralDifference do, or when sizes differ.
MotionDerivatives DeriveMotion(const Eigen::Ref<const Eigen::VectorXd>& time,
                               const Eigen::Ref<const Eigen::VectorXd>& position, double cutoff_hz);

// The same per segment: rows [starts[k], starts[k+1]) (the last to N) are filtered and differentiated
// separately, never across the gap in time between two segments (MeasurementLog::segment_starts); segments of
// fewer than 3 samples pass unchanged (derivatives 0). starts empty or {0}: one segment. Throws as above, or
// std::invalid_argument when starts does not begin with 0 or does not increase within N.
Eigen::VectorXd ZeroPhaseLowPassBySegment(const Eigen::Ref<const Eigen::VectorXd>& signal, double sample_period,
                                          double cutoff_hz, const std::vector<Eigen::Index>& starts);
MotionDerivatives DeriveMotionBySegment(const Eigen::Ref<const Eigen::VectorXd>& time,
                                        const Eigen::Ref<const Eigen::VectorXd>& position, double cutoff_hz,
                                        const std::vector<Eigen::Index>& starts);

// A zero-order-held signal (a command logged at t_k and held over [t_k, t_k+1): a controller's force or current
// reference) at the sample instants as a motion derivative sees it: its mean over the sample period centred on t_k,
// (y[k−1] + y[k])/2 on a uniform grid — half a sample later than the raw samples (MATLAB iddata's InterSample
// 'zoh'). Central differences of the position see the held force so (for a double integrator the second difference
// x[k+1] − 2x[k] + x[k−1] is exactly h²·(u[k−1] + u[k])/2), whereas the raw sample leads the motion by half a
// period: a 0.5 ms lead at 1 kHz, taken for a shorter delay or a friction law by the diagnosis. Per segment (as
// ZeroPhaseLowPassBySegment); the first sample of each segment is kept. Throws std::invalid_argument on bad starts.
Eigen::VectorXd HeldSignalAtSampleInstants(const Eigen::Ref<const Eigen::VectorXd>& signal,
                                          const std::vector<Eigen::Index>& starts);

// Root-mean-square error sqrt(mean((y − ŷ)²)). Throws std::invalid_argument on a size mismatch or N = 0.
double Rmse(const Eigen::Ref<const Eigen::VectorXd>& measured,
            const Eigen::Ref<const Eigen::VectorXd>& model);

// How many samples at each end of a record of n samples a zero-phase low-pass at cutoff_hz, and the motion derived
// through it, still hold the filter's edge transient, where it reads its own padding (ZeroPhaseLowPass's odd
// reflection mirrors the signal, not the physics: a record that opens with a controller's kick leaves there a spike a
// hundred times the noise): two periods of the cut-off, at most 5 % of n. n in samples, sample_period [s], cutoff_hz
// [Hz]. 0 when sample_period or cutoff_hz is not positive. Throws nothing. Source: Gustafsson, "Determining the
// initial states in forward-backward filtering", IEEE Trans. Signal Processing 44(4), 1996 (filtfilt's edge
// transients).
Eigen::Index FilterEdgeSamples(Eigen::Index n, double sample_period, double cutoff_hz) noexcept;

// Rmse over the interior of every segment [starts[k], starts[k+1]) (the last to N; empty starts: one segment), its
// first and last FilterEdgeSamples(segment length, sample_period, cutoff_hz) samples left out; measured, model: N each,
// the result in their unit (the whole record's Rmse when no segment has an interior). Throws as Rmse, or
// std::invalid_argument on bad starts.
double InteriorRmse(const Eigen::Ref<const Eigen::VectorXd>& measured, const Eigen::Ref<const Eigen::VectorXd>& model,
                    const std::vector<Eigen::Index>& starts, double sample_period, double cutoff_hz);

// The interior of every segment as weights (n): 1, but 0 over each segment's first and last FilterEdgeSamples(segment
// length, sample_period, cutoff_hz) samples — what InteriorRmse scores and an equation-error refit weighs
// (tools/workflow/comparison.h, ModelComparison::FitWeights). sample_period [s], cutoff_hz [Hz]; all ones when either
// is not positive. Throws std::invalid_argument on bad starts (as InteriorRmse). Source: as FilterEdgeSamples.
Eigen::VectorXd InteriorWeights(Eigen::Index n, const std::vector<Eigen::Index>& starts, double sample_period,
                                double cutoff_hz);

// Fit [%] = 100·(1 − ‖y − ŷ‖/‖y − mean(y)‖) (NRMSE; MATLAB `compare`): 100 is perfect, 0 is no better
// than the mean, negative is worse. Throws std::invalid_argument on a size mismatch, N = 0 or a
// constant measurement (the normaliser is zero).
double FitPercent(const Eigen::Ref<const Eigen::VectorXd>& measured,
                  const Eigen::Ref<const Eigen::VectorXd>& model);

// Residual autocorrelation and whiteness test (MATLAB `resid`; Ljung & Box 1978).
struct AutocorrelationTest {
  Eigen::VectorXd autocorrelation;  // r(τ), τ = 0..max_lag; r(0) = 1
  double band99 = 0.0;              // 99 % band ±2.58/√N for a white residual
  double ljung_box_q = 0.0;         // Q = N(N+2) Σ_{τ=1..L} r(τ)²/(N−τ)
  double p_value = 1.0;             // P(χ²(L) > Q); small = not white
  bool white = true;                // p_value >= 0.01
};

// Autocorrelation of the (mean-removed) residual up to max_lag and the Ljung–Box test against χ²(max_lag)
// (Boost.Math). Throws std::invalid_argument when max_lag < 1 or N <= max_lag + 1, the residual is constant, holds a
// NaN or infinity (naming the sample) or overflows (its energy is not finite).
AutocorrelationTest ResidualAutocorrelation(const Eigen::Ref<const Eigen::VectorXd>& residual,
                                            Eigen::Index max_lag = 25);

// Input–residual cross-correlation r_eu(k) = Σ_t e(t)·u(t−k) / (N σ_e σ_u), k = −max_lag..max_lag.
// A significant peak at k > 0: the effect of u(t−k) on the output is not modelled (MATLAB `resid`).
struct CrossCorrelationTest {
  Eigen::VectorXi lags;             // −max_lag..max_lag [samples]
  Eigen::VectorXd correlation;      // r_eu(k)
  Eigen::Index peak_lag = 0;        // lag of max |r_eu| [samples]
  double peak_value = 0.0;          // r_eu at the peak
  double band99 = 0.0;              // ±2.58/√N
  bool significant = false;         // |peak_value| > band99
};

// Throws std::invalid_argument on a size mismatch, max_lag < 0, N <= max_lag + 1 or a constant signal.
CrossCorrelationTest InputResidualCrossCorrelation(const Eigen::Ref<const Eigen::VectorXd>& input,
                                                   const Eigen::Ref<const Eigen::VectorXd>& residual,
                                                   Eigen::Index max_lag = 25);

// One-sided power spectral density.
struct PowerSpectrum {
  Eigen::VectorXd frequency_hz;  // 0 .. 1/(2 Ts)
  Eigen::VectorXd density;       // [unit²/Hz]; Σ density·Δf ≈ variance of the (mean-removed) signal
};

// Welch's method (Welch 1967): Hann-windowed segments of segment_length samples (clamped to N; a power
// of two is fastest), 50 % overlap, segment mean removed, averaged periodograms, one-sided.
// Throws std::invalid_argument when Ts <= 0, segment_length < 8 or N < 8.
PowerSpectrum WelchPowerSpectrum(const Eigen::Ref<const Eigen::VectorXd>& signal, double sample_period,
                                 Eigen::Index segment_length = 1024);

// The record's noise floor: the RMS error that no model of the motion can go below (DIAGNOSIS.md, "The noise floor,
// and leaks"). The residual's density in a band above the motion's, taken as white and integrated over the band the
// compared signals carry: without parallel filtering (band_limit_hz <= 0) the upper half of the spectrum,
// [f_N/2, 0.95 f_N] (f_N the Nyquist frequency), integrated up to f_N; with it (the residual low-passed by
// ZeroPhaseLowPass at band_limit_hz = f_c) the band [f_c/4, f_c/2], each bin divided by the filter's power gain
// 1/(1 + (f/f_c)⁴)² there, integrated over the filter's noise bandwidth ∫|H|⁴ df = 3π/(8√2)·f_c. The level is each
// 256-sample segment's (128 below 2048 samples; Hann window, half overlap: WelchPowerSpectrum of the segment) median
// density over the band, made unbiased for white noise, and of those the quietest tenth (the 10th percentile over the
// segments): the band of a low-passed record holds the motion's own content too (a ripple at speed, a friction
// chattering while the axis dwells), local in time, which the quietest segments are free of. It is a lower estimate:
// on white noise 0.56 × its RMS in a low-passed band (7 bins per segment) to 0.7–1 × in the upper half of an
// unfiltered spectrum, so a step refused as fitting the noise
// (below 0.7 × this floor) lies well below the real one.
// The diagnosis adds the part that differentiating a quantized position puts into the band (quantization_floor.h):
// rms = √(white_rms² + quantization_rms²).
struct NoiseFloor {
  double rms = 0.0;                             // [unit of the residual]; 0 when the record is too short to tell
  double white_rms = 0.0;                       // the spectral estimate above [unit of the residual]
  double quantization_rms = 0.0;                // what the position's quantization adds [unit of the residual]
  double position_step = 0.0;                   // the lattice step of the logged position [m or rad]; 0 = none seen
  double band_low_hz = 0.0, band_high_hz = 0.0;  // the band its level was read in
};
// 0 when the record is shorter than 1024 samples. Throws std::invalid_argument when sample_period <= 0 or band_limit_hz
// is at or above the Nyquist frequency.
NoiseFloor EstimateNoiseFloor(const Eigen::Ref<const Eigen::VectorXd>& residual, double sample_period,
                              double band_limit_hz = 0.0);

// Median of the time steps t(i+1) − t(i) [s]. Throws std::invalid_argument when N < 2.
double MedianTimeStep(const Eigen::Ref<const Eigen::VectorXd>& time);

}  // namespace mb

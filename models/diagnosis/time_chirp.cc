#include "models/diagnosis/time_chirp.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <vector>

#include <fmt/format.h>

#include "models/diagnosis/effect_proposal.h"
#include "models/diagnosis/effect_regressors.h"
#include "models/diagnosis/fft.h"
#include "models/diagnosis/signal_processing.h"

namespace mb {
namespace {

constexpr int kWindowsPerRecord = 6;      // a window is about a sixth of the record; hop half a window
constexpr double kMinProminence = 8.0;    // a window's peak over its spectrum's median density
constexpr double kMinDriftBins = 3.0;     // the ridge's drift over the record, in a window's frequency bins
constexpr double kMaxRidgeScatter = 1.5;  // RMS of the ridge about its line, in a window's frequency bins
constexpr int kMinRidgeWindows = 5;

struct RidgePoint {
  double time = 0.0, frequency = 0.0, prominence = 0.0;
};

// The strongest peak of each window's Hann periodogram of `signal` above 4 bins (below: the motion's slow content and
// drift).
std::vector<RidgePoint> Ridge(const ProposalContext& c, const Eigen::VectorXd& signal, double* bin_hz) {
  // A sixth of the record, shortened to a length whose FFT is fast (FastFftLength: at most 10 % shorter).
  const Eigen::Index n = c.size(), length = FastFftLength(n / kWindowsPerRecord), hop = length / 2;
  const double ts = c.sample_period();
  std::vector<RidgePoint> ridge;
  *bin_hz = length > 0 ? 1.0 / (static_cast<double>(length) * ts) : 0.0;
  if (length < 64) return ridge;
  for (Eigen::Index start = 0; start + length <= n; start += hop) {
    const PowerSpectrum psd = WelchPowerSpectrum(signal.segment(start, length), ts, length);
    const Eigen::Index m = psd.density.size();
    if (m < 16) return ridge;
    Eigen::Index best = 4;
    for (Eigen::Index k = 4; k < m; ++k) {
      if (c.options().band_limit_hz > 0.0 && psd.frequency_hz(k) > c.options().band_limit_hz) break;
      if (psd.density(k) > psd.density(best)) best = k;
    }
    std::vector<double> sorted(psd.density.data(), psd.density.data() + m);
    std::nth_element(sorted.begin(), sorted.begin() + m / 2, sorted.end());
    const double median = sorted[static_cast<std::size_t>(m / 2)];
    RidgePoint p;
    p.time = c.signals().time(start + length / 2);
    p.frequency = psd.frequency_hz(best);
    if (best > 0 && best + 1 < m) {  // parabolic interpolation of the log density
      const double l0 = std::log(psd.density(best - 1)), l1 = std::log(psd.density(best)),
                   l2 = std::log(psd.density(best + 1));
      const double denom = l0 - 2.0 * l1 + l2;
      if (denom < 0.0) p.frequency += std::clamp(0.5 * (l0 - l2) / denom, -0.5, 0.5) * *bin_hz;
    }
    p.prominence = median > 0.0 ? psd.density(best) / median : 0.0;
    ridge.push_back(p);
  }
  return ridge;
}

// The height of the dechirped residual's spectrum, r(t)·exp(−iπḟ(t − t_m)²), over [f_lo, f_hi], and where it peaks.
struct Dechirped {
  double height = 0.0, frequency = 0.0;
};
Dechirped Dechirp(const Eigen::VectorXd& r, const Eigen::VectorXd& t, double t_mid, double rate, double f_lo,
                  double f_hi, double ts) {
  const Eigen::Index n = r.size();
  Eigen::Index padded = 1;
  while (padded < 4 * n) padded *= 2;
  std::vector<std::complex<double>> z(static_cast<std::size_t>(padded), 0.0), spectrum;
  const double mean = r.mean();
  for (Eigen::Index i = 0; i < n; ++i) {
    const double d = t(i) - t_mid;
    z[static_cast<std::size_t>(i)] = (r(i) - mean) * std::polar(1.0, -std::numbers::pi * rate * d * d);
  }
  Fft().Forward(z, &spectrum);
  const double df = 1.0 / (static_cast<double>(padded) * ts);
  Dechirped best;
  for (auto k = static_cast<Eigen::Index>(std::floor(f_lo / df)); k <= static_cast<Eigen::Index>(std::ceil(f_hi / df));
       ++k) {
    if (k < 1 || k >= padded / 2) continue;
    const double height = std::abs(spectrum[static_cast<std::size_t>(k)]);
    if (height > best.height) best = {height, static_cast<double>(k) * df};
  }
  return best;
}

}  // namespace

Eigen::VectorXd ChirpCycles(const Eigen::VectorXd& t, double f0, double rate) {
  return (f0 * t.array() + 0.5 * rate * t.array().square()).matrix();
}

std::vector<FactorParameters> ScanTimeChirp(ProposalContext& c, const Eigen::VectorXd& m, const std::string& pair) {
  const Eigen::VectorXd demodulated = (c.residual().array() * m.array()).matrix();
  double bin = 0.0;
  const std::vector<RidgePoint> ridge = Ridge(c, demodulated, &bin);
  std::vector<RidgePoint> strong;
  for (const RidgePoint& p : ridge) {
    if (p.prominence >= kMinProminence) strong.push_back(p);
  }
  if (static_cast<int>(strong.size()) < kMinRidgeWindows) return {};
  // The ridge's line f = a + b(t − t_m), least squares over the windows whose peak stands out.
  const Eigen::VectorXd& t = c.signals().time;
  const double t_mid = 0.5 * (t(0) + t(t.size() - 1)), duration = t(t.size() - 1) - t(0);
  Eigen::MatrixXd design(static_cast<Eigen::Index>(strong.size()), 2);
  Eigen::VectorXd f(design.rows());
  for (Eigen::Index i = 0; i < design.rows(); ++i) {
    design(i, 0) = 1.0;
    design(i, 1) = strong[static_cast<std::size_t>(i)].time - t_mid;
    f(i) = strong[static_cast<std::size_t>(i)].frequency;
  }
  const Eigen::Vector2d line = design.colPivHouseholderQr().solve(f);
  const double scatter = std::sqrt((design * line - f).squaredNorm() / static_cast<double>(f.size()));
  const double drift = std::abs(line(1)) * duration;
  if (drift < kMinDriftBins * bin) return {};  // one fixed frequency: the time_periodic modulator's
  if (scatter > kMaxRidgeScatter * bin) {
    c.Note(fmt::format("{} not proposed: the residual's short-time spectrum peaks along {} windows from {:.4g} to "
                       "{:.4g} Hz, but {:.3g} Hz about a straight line ({:.1f} of its {:.3g} Hz bins): not a frequency "
                       "drifting steadily in time (a periodic force of the position at a varying speed?)",
                       pair, strong.size(), f.minCoeff(), f.maxCoeff(), scatter, scatter / bin, bin));
    return {};
  }
  // Dechirping: the rate whose dechirped spectrum peaks highest, on steps of a quarter of the phase's coherence
  // (π·δḟ·(T/2)² = π/4 at the ends), within the ridge's rate ± its uncertainty (two bins over the record).
  const double ts = c.sample_period(), step = 0.25 / (0.25 * duration * duration);
  const double half_range = std::max(2.0 * bin / duration, 4.0 * step);
    double rate = line(1), f_mid = line(0), height = 0.0;
  constexpr int kMaxTrials = 400;  // at most, whatever the record's length (each trial is one FFT of 4N points)
  const int trials = std::min(kMaxTrials, static_cast<int>(std::ceil(2.0 * half_range / step)));
  for (int k = 0; k <= trials; ++k) {
    const double trial = line(1) - half_range + k * (2.0 * half_range / trials);
    const Dechirped d = Dechirp(demodulated, t, t_mid, trial, line(0) - 2.0 * bin, line(0) + 2.0 * bin, ts);
    if (d.height > height) {
      height = d.height;
      rate = trial;
      f_mid = d.frequency;
    }
  }
  // The joint fit with the base settles both to a fraction of the grid.
  const Eigen::MatrixXd base = c.BaseWithConstant();
  const JointFitResidual joint_fit(base, c.residual(), c.loop());
  auto columns = [&](double fm, double rt) {
    return PeriodicColumns(ChirpCycles(t, fm - rt * t_mid, rt), 1.0, 1, pair, &m).columns;
  };
  const double df = 1.0 / duration;
  // (Widths relative to the midpoints: a thousandth of the record's frequency resolution, of the dechirping's step.)
  auto sse_f = [&](double trial) { return joint_fit(columns(trial, rate)); };
  f_mid = GoldenSectionMinimum(sse_f, f_mid - df, f_mid + df, 1e-3 * df / f_mid);
  rate = GoldenSectionMinimum([&](double trial) { return joint_fit(columns(f_mid, trial)); }, rate - step, rate + step,
                              1e-3 * step / std::abs(rate));
  f_mid = GoldenSectionMinimum(sse_f, f_mid - 0.25 * df, f_mid + 0.25 * df, 1e-4 * df / f_mid);
  const double f0 = f_mid - rate * t_mid;
  if (!(std::min(f0 + rate * t(0), f0 + rate * t(t.size() - 1)) > 0.0)) {
    c.Note(fmt::format("{} not proposed: the line through the ridge ({:.4g} Hz at t = {:.4g} s, {:+.4g} Hz/s) reaches "
                       "0 Hz within the record", pair, f_mid, t_mid, rate));
    return {};
  }
  return {{{"frequency_hz", f0}, {"drift_rate", rate}, {"harmonics", 1.0}}};
}


}  // namespace mb

#include "models/diagnosis/periodogram.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <stdexcept>

#include <Eigen/Dense>
#include <fmt/format.h>
#include <tbb/parallel_invoke.h>

#include "models/diagnosis/fft.h"

namespace mb {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

// Least-squares fit of c0 + a cos θ + b sin θ to data from its weighted sums: W = Σw, C = Σw cos θ,
// S = Σw sin θ, C2 = Σw cos 2θ, S2 = Σw sin 2θ, Y = Σw y, YC = Σw y cos θ, YS = Σw y sin θ.
// Closed form: project cos and sin off the constant, solve the 2×2 system (Zechmeister & Kürster 2009).
// Returns the explained sum of squares Σw ŷ²; writes (c0, a, b) when asked.
double ExplainedSumOfSquares(double w, double c, double s, double c2, double s2, double y, double yc,
                             double ys, Eigen::Vector3d* coef = nullptr) {
  const double cc = 0.5 * (w + c2) - c * c / w;
  const double ss = 0.5 * (w - c2) - s * s / w;
  const double cs = 0.5 * s2 - c * s / w;
  const double yc_t = yc - y * c / w, ys_t = ys - y * s / w;
  const double det = cc * ss - cs * cs;
  double a = 0.0, b = 0.0, ess = y * y / w;
  if (det > 1e-12 * w * w) {
    a = (ss * yc_t - cs * ys_t) / det;
    b = (cc * ys_t - cs * yc_t) / det;
    ess += a * yc_t + b * ys_t;
  } else if (std::max(cc, ss) > 1e-12 * w) {  // cos and sin nearly collinear: fit the larger one
    if (cc >= ss) {
      a = yc_t / cc;
      ess += a * yc_t;
    } else {
      b = ys_t / ss;
      ess += b * ys_t;
    }
  }
  if (coef) *coef = Eigen::Vector3d((y - a * c - b * s) / w, a, b);
  return std::isfinite(ess) ? std::max(0.0, ess) : 0.0;
}

void CheckData(const Eigen::Ref<const Eigen::VectorXd>& x, const Eigen::Ref<const Eigen::VectorXd>& r,
               const char* what) {
  if (x.size() != r.size()) {
    throw std::invalid_argument(fmt::format("{}: abscissa has {} samples but the residual {}; pass equally "
                                            "long vectors", what, x.size(), r.size()));
  }
  if (x.size() < 16) {
    throw std::invalid_argument(fmt::format("{}: {} samples, at least 16 are needed", what, x.size()));
  }
  if (!x.allFinite() || !r.allFinite()) {
    throw std::invalid_argument(fmt::format("{}: the abscissa or the residual holds NaN or Inf", what));
  }
}

// Residual averaged into uniform bins x_j = x_min + j·h (nearest bin centre).
struct Bins {
  double h = 0.0;
  Eigen::VectorXd weight;  // sample count per bin
  Eigen::VectorXd mean;    // mean centred residual per bin (0 where empty)
};

Bins MakeBins(const Eigen::Ref<const Eigen::VectorXd>& x, const Eigen::VectorXd& r_centred, double x_min,
              double h, Eigen::Index m) {
  Bins b;
  b.h = h;
  b.weight = Eigen::VectorXd::Zero(m);
  b.mean = Eigen::VectorXd::Zero(m);
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    const auto j = std::clamp<Eigen::Index>(static_cast<Eigen::Index>(std::lround((x(i) - x_min) / h)), 0, m - 1);
    b.weight(j) += 1.0;
    b.mean(j) += r_centred(i);
  }
  for (Eigen::Index j = 0; j < m; ++j) {
    if (b.weight(j) > 0.0) b.mean(j) /= b.weight(j);
  }
  return b;
}

// The rotation sums Σw cos θ, Σw sin θ, Σw cos 2θ, Σw sin 2θ, Σwy cos θ, Σwy sin θ of a run of bins.
struct RotationSums {
  double c = 0.0, s = 0.0, c2 = 0.0, s2 = 0.0, yc = 0.0, ys = 0.0;
  void Add(const RotationSums& o) { c += o.c; s += o.s; c2 += o.c2; s2 += o.s2; yc += o.yc; ys += o.ys; }
};

// The rotation sums of bins [begin, begin + 4·quarter) at θ_j = j·phase_step by four independent chains, one per
// quarter, each started at its own phase: the chains' products overlap, where a single chain waits on its last
// product at every bin. An empty bin adds zeros (its weight and mean are 0).
RotationSums FourChainSums(const Bins& b, double phase_step, Eigen::Index begin, Eigen::Index quarter) {
  constexpr int kChains = 4;
  const std::complex<double> step = std::polar(1.0, phase_step);
  const double sr = step.real(), si = step.imag();
  const double* weight = b.weight.data() + begin;
  const double* mean = b.mean.data() + begin;
  double zr[kChains], zi[kChains], c[kChains] = {}, s[kChains] = {}, c2[kChains] = {}, s2[kChains] = {};
  double yc[kChains] = {}, ys[kChains] = {};
  for (int l = 0; l < kChains; ++l) {
    const std::complex<double> z0 = std::polar(1.0, phase_step * static_cast<double>(begin + l * quarter));
    zr[l] = z0.real();
    zi[l] = z0.imag();
  }
  for (Eigen::Index j = 0; j < quarter; ++j) {
    for (int l = 0; l < kChains; ++l) {
      const double wj = weight[l * quarter + j], wy = wj * mean[l * quarter + j];
      c[l] += wj * zr[l];
      s[l] += wj * zi[l];
      c2[l] += wj * (zr[l] * zr[l] - zi[l] * zi[l]);
      s2[l] += wj * (2.0 * zr[l] * zi[l]);
      yc[l] += wy * zr[l];
      ys[l] += wy * zi[l];
      const double next_r = zr[l] * sr - zi[l] * si;
      zi[l] = zr[l] * si + zi[l] * sr;
      zr[l] = next_r;
    }
    if ((j & 1023) == 1023) {  // keep |z| = 1 over long runs
      for (int l = 0; l < kChains; ++l) {
        const double norm = std::hypot(zr[l], zi[l]);
        zr[l] /= norm;
        zi[l] /= norm;
      }
    }
  }
  RotationSums out;
  for (int l = 0; l < kChains; ++l) out.Add({c[l], s[l], c2[l], s2[l], yc[l], ys[l]});
  return out;
}

// Exact weighted fit on the bins at frequency f (cycles per unit of x); O(M) by complex rotation: FourChainSums over
// the bins, in two concurrent halves of four chains from 2^16 bins on (the peaks' refinement is serial; the
// periodograms' other work often leaves a core idle), the last bins by a chain of their own. The sums differ from a
// single chain's in the last digits only; the split depends on M alone, so a result does not depend on the threads.
double BinnedExplained(const Bins& b, double f, Eigen::Vector3d* coef = nullptr) {
  const Eigen::Index m = b.weight.size();
  const int groups = m >= (Eigen::Index{1} << 16) ? 2 : 1;
  const Eigen::Index quarter = m / (4 * groups), covered = 4 * groups * quarter;
  const double phase_step = kTwoPi * f * b.h;
  RotationSums part[2];
  if (groups == 2) {
    tbb::parallel_invoke([&] { part[0] = FourChainSums(b, phase_step, 0, quarter); },
                         [&] { part[1] = FourChainSums(b, phase_step, 4 * quarter, quarter); });
  } else {
    part[0] = FourChainSums(b, phase_step, 0, quarter);
  }
  RotationSums t = part[0];
  if (groups == 2) t.Add(part[1]);
  const std::complex<double> step = std::polar(1.0, phase_step);
  std::complex<double> z = std::polar(1.0, phase_step * static_cast<double>(covered));
  double w = 0.0, y = 0.0;
  for (Eigen::Index j = covered; j < m; ++j) {
    const double wj = b.weight(j), wy = wj * b.mean(j);
    const std::complex<double> z2 = z * z;
    t.Add({wj * z.real(), wj * z.imag(), wj * z2.real(), wj * z2.imag(), wy * z.real(), wy * z.imag()});
    z *= step;
  }
  for (Eigen::Index j = 0; j < m; ++j) {  // the constant's sums, independent of f
    w += b.weight(j);
    y += b.weight(j) * b.mean(j);
  }
  return ExplainedSumOfSquares(w, t.c, t.s, t.c2, t.s2, y, t.yc, t.ys, coef);
}

// The forward FFT of real v zero-padded to K, its half spectrum k = 0..K/2 (the rest is its conjugate mirror), into
// `out`; `in` is the zero-padded input buffer, kept between calls (its tail beyond v stays zero).
void HalfSpectrum(Fft& fft, const Eigen::VectorXd& v, std::vector<double>* in,
                  std::vector<std::complex<double>>* out) {
  std::copy(v.data(), v.data() + v.size(), in->begin());
  fft.Forward(*in, out);
}

}  // namespace

const PeriodogramPeak& Periodogram::best() const {
  if (peaks.empty()) throw std::logic_error("Periodogram::best: the periodogram has no peak");
  return peaks.front();
}

double BaluevFalseAlarmProbability(double power, double samples, double min_period, double abscissa_variance) {
  const double z = std::clamp(power, 0.0, 1.0);
  const double nh = samples - 1.0, nk = samples - 3.0;
  if (nk <= 1.0 || !(min_period > 0.0) || !(abscissa_variance > 0.0)) return 1.0;
  if (z >= 1.0) return 0.0;
  const double log1mz = std::log1p(-z);
  const double fap_single = std::exp(0.5 * nk * log1mz);
  const double gamma = std::sqrt(2.0 / nh) * std::exp(std::lgamma(0.5 * nh) - std::lgamma(0.5 * (nh - 1.0)));
  const double w = (1.0 / min_period) * std::sqrt(4.0 * std::numbers::pi * abscissa_variance);
  const double tau = gamma * w * std::exp(0.5 * (nk - 1.0) * log1mz) * std::sqrt(0.5 * nh * z);
  return std::clamp(1.0 - (1.0 - fap_single) * std::exp(-tau), 0.0, 1.0);
}

double LombScarglePower(const Eigen::Ref<const Eigen::VectorXd>& abscissa,
                        const Eigen::Ref<const Eigen::VectorXd>& residual, double period) {
  CheckData(abscissa, residual, "LombScarglePower");
  if (!(period > 0.0)) throw std::invalid_argument("LombScarglePower: the period must be positive");
  const Eigen::VectorXd r = residual.array() - residual.mean();
  const double chi0 = r.squaredNorm();
  if (!(chi0 > 0.0)) throw std::invalid_argument("LombScarglePower: the residual is constant");
  double w = 0, c = 0, s = 0, c2 = 0, s2 = 0, y = 0, yc = 0, ys = 0;
  for (Eigen::Index i = 0; i < r.size(); ++i) {
    const double th = kTwoPi * abscissa(i) / period;
    w += 1.0;
    c += std::cos(th);
    s += std::sin(th);
    c2 += std::cos(2.0 * th);
    s2 += std::sin(2.0 * th);
    y += r(i);
    yc += r(i) * std::cos(th);
    ys += r(i) * std::sin(th);
  }
  return ExplainedSumOfSquares(w, c, s, c2, s2, y, yc, ys) / chi0;
}

namespace {

// P_min and P_max of `options`, or the automatic ones: 4 × the median |Δx|, half the span.
void SetPeriodRange(const Eigen::Ref<const Eigen::VectorXd>& abscissa, double span, const PeriodogramOptions& options,
                    Periodogram* out) {
  const Eigen::Index n = abscissa.size();
  out->min_period = options.min_period;
  if (out->min_period <= 0.0) {
    std::vector<double> steps(static_cast<std::size_t>(n - 1));
    for (Eigen::Index i = 1; i < n; ++i) steps[static_cast<std::size_t>(i - 1)] = std::abs(abscissa(i) - abscissa(i - 1));
    const auto mid = steps.begin() + static_cast<std::ptrdiff_t>(steps.size() / 2);
    std::nth_element(steps.begin(), mid, steps.end());
    out->min_period = 4.0 * *mid;
    if (!(out->min_period > 0.0)) out->min_period = 8.0 * span / static_cast<double>(n);
  }
  out->max_period = options.max_period > 0.0 ? options.max_period : 0.5 * span;
  if (!(out->min_period < out->max_period)) {
    throw std::invalid_argument(fmt::format(
        "LombScarglePeriodogram: the period range [{}, {}] is empty; the abscissa spans {} — choose "
        "min_period < max_period",
        out->min_period, out->max_period, span));
  }
}

// Bin width: P_min/8, but at most 2^21 bins. A uniformly sampled, increasing abscissa (time) is binned at its own
// step: every sample sits on a bin centre, binning changes nothing.
double BinWidth(const Eigen::Ref<const Eigen::VectorXd>& abscissa, double span, double min_period) {
  constexpr double kMaxBins = 2097152.0;
  double width = std::max(min_period / 8.0, span / (kMaxBins - 1.0));
  const Eigen::Index n = abscissa.size();
  const double step = span / static_cast<double>(n - 1);
  bool uniform = true;
  for (Eigen::Index i = 1; i < n && uniform; ++i) uniform = std::abs(abscissa(i) - abscissa(i - 1) - step) <= 1e-6 * step;
  if (uniform && step > width) width = step;
  return width;
}

// The fine frequency grid k·df, k in [k_lo, k_hi], of an FFT of the bins zero-padded to K: df = 1/(K h) ≤ 1/(4 span)
// (4 nodes per main lobe; peaks are refined afterwards). The DFT sums are exact at every index < K, which must
// include 2 f_max.
class FineGrid {
 public:
  FineGrid(const Bins& bins, const Periodogram& p) {
    const auto m = bins.weight.size();
    while (k_size_ < 4 * m) k_size_ *= 2;
    df_ = 1.0 / (static_cast<double>(k_size_) * bins.h);
    k_lo_ = std::max<Eigen::Index>(1, static_cast<Eigen::Index>(std::floor(1.0 / p.max_period / df_)));
    k_hi_ = static_cast<Eigen::Index>(std::ceil(1.0 / p.min_period / df_));
    if (2 * k_hi_ >= k_size_) {
      throw std::invalid_argument(fmt::format(
          "LombScarglePeriodogram: min_period {} is below 2 sample steps ({}) of a uniformly sampled abscissa "
          "(above the Nyquist frequency); raise min_period",
          p.min_period, 2.0 * bins.h));
    }
    in_.assign(static_cast<std::size_t>(k_size_), 0.0);
    HalfSpectrum(fft_, bins.weight, &in_, &weights_);
    w_total_ = bins.weight.sum();
  }
  double df() const { return df_; }
  Eigen::Index k_lo() const { return k_lo_; }
  Eigen::Index k_hi() const { return k_hi_; }
  // The explained sum of squares / chi_ref at each node for the bin means of `work`.
  Eigen::VectorXd Power(const Bins& work, double chi_ref) {
    const Eigen::VectorXd wy = work.weight.cwiseProduct(work.mean);
    HalfSpectrum(fft_, wy, &in_, &sums_);  // k_hi < K/2: every node's sum is in the half spectrum
    const double y = wy.sum();
    Eigen::VectorXd p(k_hi_ - k_lo_ + 1);
    for (Eigen::Index k = k_lo_; k <= k_hi_; ++k) {
      const auto ak = Weights(k), a2k = Weights(2 * k);
      const auto bk = std::conj(sums_[static_cast<std::size_t>(k)]);
      p(k - k_lo_) =
          ExplainedSumOfSquares(w_total_, ak.real(), ak.imag(), a2k.real(), a2k.imag(), y, bk.real(), bk.imag()) /
          chi_ref;
    }
    return p;
  }

 private:
  // Σ_j w_j e^{+2πi jk/K}: the conjugate of the forward FFT, whose upper half mirrors the lower (exactly: Eigen's
  // full spectrum is filled in as conj(F[K−k]) too).
  std::complex<double> Weights(Eigen::Index k) const {
    return k <= k_size_ / 2 ? std::conj(weights_[static_cast<std::size_t>(k)])
                            : weights_[static_cast<std::size_t>(k_size_ - k)];
  }

  Fft fft_{/*half_spectrum=*/true};
  Eigen::Index k_size_ = 1, k_lo_ = 0, k_hi_ = 0;
  double df_ = 0.0, w_total_ = 0.0;
  std::vector<double> in_;                     // the zero-padded input, reused by every transform
  std::vector<std::complex<double>> weights_;  // the forward FFT of the bin weights, k = 0..K/2
  std::vector<std::complex<double>> sums_;     // the forward FFT of the weighted bin means, k = 0..K/2
};

// The reported curve on the log grid of options.num_periods: the fine grid's maximum within each log cell, else
// interpolated between its nodes.
void ReportedCurve(const Eigen::VectorXd& fine, const FineGrid& grid, Eigen::Index num_periods, Periodogram* out) {
  out->periods = Eigen::VectorXd::LinSpaced(num_periods, std::log(out->min_period), std::log(out->max_period))
                     .array().exp().matrix();
  out->power.resize(num_periods);
  const double log_step = std::log(out->max_period / out->min_period) / static_cast<double>(num_periods - 1);
  const double df = grid.df();
  const Eigen::Index k_lo = grid.k_lo(), k_hi = grid.k_hi();
  for (Eigen::Index i = 0; i < num_periods; ++i) {
    const double f = 1.0 / out->periods(i);
    const double f_hi = f * std::exp(0.5 * log_step), f_lo = f * std::exp(-0.5 * log_step);
    const auto j_lo = std::max(k_lo, static_cast<Eigen::Index>(std::ceil(f_lo / df)));
    const auto j_hi = std::min(k_hi, static_cast<Eigen::Index>(std::floor(f_hi / df)));
    if (j_lo <= j_hi) {
      out->power(i) = fine.segment(j_lo - k_lo, j_hi - j_lo + 1).maxCoeff();
    } else {
      const double u = std::clamp(f / df, static_cast<double>(k_lo), static_cast<double>(k_hi));
      const auto j0 = std::min(k_hi - 1, static_cast<Eigen::Index>(std::floor(u)));
      const double t = u - static_cast<double>(j0);
      out->power(i) = (1.0 - t) * fine(j0 - k_lo) + t * fine(j0 + 1 - k_lo);
    }
  }
}

// The frequency of the maximum of the exact binned power on [lo, hi]: golden-section search, to 1e-9 relative (its
// termination tolerance: a change of the sums in their last digits may move the result within it, not beyond).
double RefinePeak(const Bins& work, double lo, double hi) {
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
  double e1 = BinnedExplained(work, x1), e2 = BinnedExplained(work, x2);
  for (int it = 0; it < 40 && hi - lo > 1e-9 * hi; ++it) {
    if (e1 > e2) {
      hi = x2; x2 = x1; e2 = e1; x1 = hi - g * (hi - lo); e1 = BinnedExplained(work, x1);
    } else {
      lo = x1; x1 = x2; e1 = e2; x2 = lo + g * (hi - lo); e2 = BinnedExplained(work, x2);
    }
  }
  return 0.5 * (lo + hi);
}

// Marks `peak` as a harmonic (or sub-harmonic) of the first stronger peak whose period it divides (or multiplies) by
// an integer k in 2..8, within `tolerance`.
void MarkHarmonic(const std::vector<PeriodogramPeak>& stronger, double tolerance, PeriodogramPeak* peak) {
  for (std::size_t i = 0; i < stronger.size() && peak->harmonic_of < 0; ++i) {
    const double ratio = stronger[i].period / peak->period;
    const double big = ratio >= 1.0 ? ratio : 1.0 / ratio;
    const double k = std::round(big);
    if (k >= 2.0 && k <= 8.0 && std::abs(big - k) <= tolerance * k) {
      peak->harmonic_of = static_cast<int>(i);
      peak->harmonic_order = ratio >= 1.0 ? static_cast<int>(k) : -static_cast<int>(k);
    }
  }
}

// Subtracts the sinusoid c0 + a cos(2πf x) + b sin(2πf x) from the bin means.
void Prewhiten(double f, const Eigen::Vector3d& coef, Bins* work) {
  const std::complex<double> step = std::polar(1.0, kTwoPi * f * work->h);
  std::complex<double> z(1.0, 0.0);
  for (Eigen::Index j = 0; j < work->mean.size(); ++j) {
    work->mean(j) -= coef(0) + coef(1) * z.real() + coef(2) * z.imag();
    z *= step;
    if ((j & 1023) == 1023) z /= std::abs(z);
  }
}

}  // namespace

Periodogram LombScarglePeriodogram(const Eigen::Ref<const Eigen::VectorXd>& abscissa,
                                   const Eigen::Ref<const Eigen::VectorXd>& residual,
                                   const PeriodogramOptions& options) {
  CheckData(abscissa, residual, "LombScarglePeriodogram");
  const Eigen::Index n = abscissa.size();
  if (options.num_periods < 16) {
    throw std::invalid_argument(fmt::format(
        "LombScarglePeriodogram: num_periods = {} is too small, use at least 16", options.num_periods));
  }
  const Eigen::VectorXd r = residual.array() - residual.mean();
  const double chi0 = r.squaredNorm();
  if (!(chi0 > 0.0)) throw std::invalid_argument("LombScarglePeriodogram: the residual is constant");
  const double x_min = abscissa.minCoeff(), x_max = abscissa.maxCoeff();
  const double span = x_max - x_min;
  if (!(span > 0.0)) throw std::invalid_argument("LombScarglePeriodogram: the abscissa does not vary");

  Periodogram out;
  out.samples = n;
  SetPeriodRange(abscissa, span, options, &out);
  out.bin_width = BinWidth(abscissa, span, out.min_period);
  const Eigen::Index m = static_cast<Eigen::Index>(std::ceil(span / out.bin_width)) + 1;
  const Bins bins = MakeBins(abscissa, r, x_min, out.bin_width, m);
  FineGrid grid(bins, out);
  const double f_min = 1.0 / out.max_period, f_max = 1.0 / out.min_period, df = grid.df();
  const double abscissa_variance = (abscissa.array() - abscissa.mean()).square().mean();
  const double n_eff = options.effective_samples > 0.0 ? options.effective_samples : static_cast<double>(n);
  Bins work = bins;
  const Eigen::VectorXd fine = grid.Power(work, chi0);
  ReportedCurve(fine, grid, options.num_periods, &out);

  // Peaks by iterative prewhitening: take the highest fine-grid node away from the accepted peaks, refine its
  // frequency on the exact binned power, subtract the fitted sinusoid from the bin means, repeat.
  double chi_left = chi0;
  std::vector<double> accepted_f;
  const double exclusion = 1.0 / span;  // a peak's half width in frequency
  for (Eigen::Index iter = 0; iter < options.max_peaks; ++iter) {
    const Eigen::VectorXd p = iter == 0 ? fine : grid.Power(work, chi_left);
    Eigen::Index best = -1;
    for (Eigen::Index j = 0; j < p.size(); ++j) {
      const double f = static_cast<double>(j + grid.k_lo()) * df;
      bool near = false;
      for (double fa : accepted_f) near = near || std::abs(f - fa) < exclusion;
      if (!near && (best < 0 || p(j) > p(best))) best = j;
    }
    if (best < 0 || !(p(best) > 0.0)) break;
    const double f_best = RefinePeak(work, std::max(f_min, static_cast<double>(best + grid.k_lo() - 1) * df),
                                     std::min(f_max, static_cast<double>(best + grid.k_lo() + 1) * df));
    Eigen::Vector3d coef;
    const double explained = BinnedExplained(work, f_best, &coef);
    PeriodogramPeak peak;
    peak.period = 1.0 / f_best;
    peak.power = explained / chi0;
    peak.amplitude = std::hypot(coef(1), coef(2));
    peak.false_alarm_probability =
        BaluevFalseAlarmProbability(explained / chi_left, n_eff, out.min_period, abscissa_variance);
    peak.significant = peak.false_alarm_probability < options.false_alarm_level;
    MarkHarmonic(out.peaks, options.harmonic_tolerance, &peak);
    out.peaks.push_back(peak);
    accepted_f.push_back(f_best);
    Prewhiten(f_best, coef, &work);
    chi_left -= explained;
    if (!(chi_left > 1e-12 * chi0)) break;
  }
  return out;
}

}  // namespace mb

#include "models/diagnosis/signal_processing.h"

#include <algorithm>
#include <cmath>
#include <complex>
#include <numbers>
#include <stdexcept>
#include <utility>
#include <vector>

#include <boost/math/distributions/chi_squared.hpp>
#include <fmt/format.h>

#include "models/diagnosis/fft.h"

namespace mb {
namespace {

void RequireSameSize(const Eigen::Ref<const Eigen::VectorXd>& a, const Eigen::Ref<const Eigen::VectorXd>& b,
                     const char* what) {
  if (a.size() != b.size()) {
    throw std::invalid_argument(
        fmt::format("{}: the two signals have {} and {} samples; pass equally long signals", what,
                    a.size(), b.size()));
  }
  if (a.size() == 0) throw std::invalid_argument(fmt::format("{}: the signals are empty", what));
}

// Direct-form II transposed biquad.
struct Biquad {
  double b0, b1, b2, a1, a2;
};

// The biquad run over L signals interleaved in x (sample i of signal l at x[i·L + l], `length` samples each), each
// from the steady state of its own first sample: forward (i = 0, 1, …) or backward (i = length − 1, …, 0), in place.
// The L recursions are independent, so they overlap in the processor's pipeline (one recursion waits on its own
// previous output every sample); each signal's arithmetic is the single-signal recursion's, operation for operation.
template <int L>
void RunInterleaved(const Biquad& f, double* x, Eigen::Index length, bool backward) {
  const Eigen::Index first = backward ? length - 1 : 0, step = backward ? -1 : 1;
  double z1[static_cast<std::size_t>(L)], z2[static_cast<std::size_t>(L)];
  for (int l = 0; l < L; ++l) {
    const double c = x[first * L + l];
    z2[l] = (f.b2 - f.a2) * c;
    z1[l] = (f.b1 - f.a1) * c + z2[l];
  }
  for (Eigen::Index k = 0, i = first; k < length; ++k, i += step) {
    double* s = x + i * L;
    for (int l = 0; l < L; ++l) {
      const double in = s[l];
      const double out = f.b0 * in + z1[l];
      z1[l] = f.b1 * in - f.a1 * out + z2[l];
      z2[l] = f.b2 * in - f.a2 * out;
      s[l] = out;
    }
  }
}

// The Butterworth section and the padding of ZeroPhaseLowPass for n samples, its arguments checked.
struct ZeroPhaseDesign {
  Biquad filter;
  Eigen::Index pad;
};

ZeroPhaseDesign DesignZeroPhase(Eigen::Index n, double sample_period, double cutoff_hz) {
  if (n < 3) throw std::invalid_argument("ZeroPhaseLowPass: the signal needs at least 3 samples");
  if (!(sample_period > 0.0)) {
    throw std::invalid_argument(
        fmt::format("ZeroPhaseLowPass: sample period {} s must be positive", sample_period));
  }
  const double nyquist = 0.5 / sample_period;
  if (!(cutoff_hz > 0.0 && cutoff_hz < nyquist)) {
    throw std::invalid_argument(fmt::format(
        "ZeroPhaseLowPass: cut-off {} Hz must lie in (0, {} Hz) (the Nyquist frequency); lower it",
        cutoff_hz, nyquist));
  }
  const double k = std::tan(std::numbers::pi * cutoff_hz * sample_period);
  const double sqrt2 = std::numbers::sqrt2;
  const double norm = 1.0 / (1.0 + sqrt2 * k + k * k);
  const Biquad f{k * k * norm, 2.0 * k * k * norm, k * k * norm, 2.0 * (k * k - 1.0) * norm,
                 (1.0 - sqrt2 * k + k * k) * norm};
  const Eigen::Index pad = std::min<Eigen::Index>(
      n - 1, std::max<Eigen::Index>(9, static_cast<Eigen::Index>(std::ceil(3.0 / (cutoff_hz * sample_period)))));
  return {f, pad};
}

// Columns [j, j + L) of `columns` filtered in place, zero phase (ZeroPhaseLowPass on each), through `buffer`.
template <int L>
void ZeroPhaseLanes(const ZeroPhaseDesign& d, Eigen::Ref<Eigen::MatrixXd> columns, Eigen::Index j,
                    std::vector<double>* buffer) {
  const Eigen::Index n = columns.rows(), pad = d.pad, length = n + 2 * pad;
  buffer->resize(static_cast<std::size_t>(length * L));
  double* x = buffer->data();
  for (int l = 0; l < L; ++l) {
    const auto signal = columns.col(j + l);
    const double first = signal(0), last = signal(n - 1);
    for (Eigen::Index i = 0; i < pad; ++i) {
      x[i * L + l] = 2.0 * first - signal(pad - i);
      x[(pad + n + i) * L + l] = 2.0 * last - signal(n - 2 - i);
    }
    for (Eigen::Index i = 0; i < n; ++i) x[(pad + i) * L + l] = signal(i);
  }
  RunInterleaved<L>(d.filter, x, length, false);
  RunInterleaved<L>(d.filter, x, length, true);
  for (int l = 0; l < L; ++l) {
    auto signal = columns.col(j + l);
    for (Eigen::Index i = 0; i < n; ++i) signal(i) = x[(pad + i) * L + l];
  }
}

}  // namespace

Eigen::VectorXd ZeroPhaseLowPass(const Eigen::Ref<const Eigen::VectorXd>& signal, double sample_period,
                                 double cutoff_hz) {
  const ZeroPhaseDesign d = DesignZeroPhase(signal.size(), sample_period, cutoff_hz);
  Eigen::MatrixXd out = signal;
  thread_local std::vector<double> buffer;  // as in ZeroPhaseLowPassColumns
  ZeroPhaseLanes<1>(d, out, 0, &buffer);
  return out.col(0);
}

void ZeroPhaseLowPassColumns(Eigen::Ref<Eigen::MatrixXd> columns, double sample_period, double cutoff_hz) {
  if (columns.cols() == 0) return;
  const ZeroPhaseDesign d = DesignZeroPhase(columns.rows(), sample_period, cutoff_hz);
  // One scratch per thread, kept between calls: the diagnosis filters every candidate's columns, thousands of times a
  // record, and a fresh buffer of four padded lanes (800 KB at 25k samples) was a fresh mapping each time under
  // AddressSanitizer (its allocator maps every block over 128 KiB anew): 7.5 % of the grammar test's page faults.
  thread_local std::vector<double> buffer;
  Eigen::Index j = 0;
  for (; j + 4 <= columns.cols(); j += 4) ZeroPhaseLanes<4>(d, columns, j, &buffer);
  switch (columns.cols() - j) {
    case 3: ZeroPhaseLanes<3>(d, columns, j, &buffer); break;
    case 2: ZeroPhaseLanes<2>(d, columns, j, &buffer); break;
    case 1: ZeroPhaseLanes<1>(d, columns, j, &buffer); break;
    default: break;
  }
}

Eigen::VectorXd ShiftedInTime(const Eigen::Ref<const Eigen::VectorXd>& time,
                              const Eigen::Ref<const Eigen::VectorXd>& values, double delay) {
  const Eigen::Index n = time.size();
  Eigen::VectorXd out(n);
  Eigen::Index j = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double tq = time(i) - delay;
    if (tq <= time(0)) { out(i) = values(0); continue; }
    if (tq >= time(n - 1)) { out(i) = values(n - 1); continue; }
    j = std::clamp<Eigen::Index>(j, 0, n - 2);
    while (j > 0 && time(j) > tq) --j;
    while (j + 1 < n - 1 && time(j + 1) < tq) ++j;
    const double w = (tq - time(j)) / (time(j + 1) - time(j));
    out(i) = (1.0 - w) * values(j) + w * values(j + 1);
  }
  return out;
}

Eigen::VectorXd CentralDifference(const Eigen::Ref<const Eigen::VectorXd>& time,
                                  const Eigen::Ref<const Eigen::VectorXd>& values) {
  RequireSameSize(time, values, "CentralDifference");
  const Eigen::Index n = time.size();
  if (n < 3) throw std::invalid_argument("CentralDifference: at least 3 samples are needed");
  for (Eigen::Index i = 1; i < n; ++i) {
    if (!(time(i) > time(i - 1))) {
      throw std::invalid_argument(fmt::format(
          "CentralDifference: time must increase strictly (sample {} has t = {} after t = {})", i,
          time(i), time(i - 1)));
    }
  }
  Eigen::VectorXd d(n);
  // Three-point Lagrange derivative at the middle node (non-uniform spacing h1, h2).
  for (Eigen::Index i = 1; i + 1 < n; ++i) {
    const double h1 = time(i) - time(i - 1), h2 = time(i + 1) - time(i);
    d(i) = (-h2 / (h1 * (h1 + h2))) * values(i - 1) + ((h2 - h1) / (h1 * h2)) * values(i) +
           (h1 / (h2 * (h1 + h2))) * values(i + 1);
  }
  {  // at the first node, from nodes 0, 1, 2
    const double h1 = time(1) - time(0), h2 = time(2) - time(1);
    d(0) = (-(2.0 * h1 + h2) / (h1 * (h1 + h2))) * values(0) + ((h1 + h2) / (h1 * h2)) * values(1) -
           (h1 / (h2 * (h1 + h2))) * values(2);
  }
  {  // at the last node, from nodes n-3, n-2, n-1
    const double h1 = time(n - 2) - time(n - 3), h2 = time(n - 1) - time(n - 2);
    d(n - 1) = (h2 / (h1 * (h1 + h2))) * values(n - 3) - ((h1 + h2) / (h1 * h2)) * values(n - 2) +
               ((h1 + 2.0 * h2) / (h2 * (h1 + h2))) * values(n - 1);
  }
  return d;
}

double MedianTimeStep(const Eigen::Ref<const Eigen::VectorXd>& time) {
  if (time.size() < 2) throw std::invalid_argument("MedianTimeStep: at least 2 samples are needed");
  std::vector<double> steps(static_cast<std::size_t>(time.size() - 1));
  for (Eigen::Index i = 1; i < time.size(); ++i) steps[static_cast<std::size_t>(i - 1)] = time(i) - time(i - 1);
  const auto mid = steps.begin() + static_cast<std::ptrdiff_t>(steps.size() / 2);
  std::nth_element(steps.begin(), mid, steps.end());
  return *mid;
}

MotionDerivatives DeriveMotion(const Eigen::Ref<const Eigen::VectorXd>& time,
                               const Eigen::Ref<const Eigen::VectorXd>& position, double cutoff_hz) {
  RequireSameSize(time, position, "DeriveMotion");
  MotionDerivatives m;
  m.position = ZeroPhaseLowPass(position, MedianTimeStep(time), cutoff_hz);
  m.velocity = CentralDifference(time, m.position);
  m.acceleration = CentralDifference(time, m.velocity);
  return m;
}

namespace {

// [begin, end) of each segment; throws unless starts begins with 0 and increases within n.
std::vector<std::pair<Eigen::Index, Eigen::Index>> Segments(const std::vector<Eigen::Index>& starts, Eigen::Index n) {
  std::vector<std::pair<Eigen::Index, Eigen::Index>> out;
  if (starts.empty()) return {{0, n}};
  for (std::size_t k = 0; k < starts.size(); ++k) {
    const Eigen::Index end = k + 1 < starts.size() ? starts[k + 1] : n;
    if ((k == 0 && starts[0] != 0) || !(end > starts[k]) || end > n) {
      throw std::invalid_argument(fmt::format(
          "segment starts must begin with 0 and increase strictly within the {} samples (segment {} starts at {})", n,
          k, starts[k]));
    }
    out.emplace_back(starts[k], end);
  }
  return out;
}

}  // namespace

Eigen::VectorXd ZeroPhaseLowPassBySegment(const Eigen::Ref<const Eigen::VectorXd>& signal, double sample_period,
                                          double cutoff_hz, const std::vector<Eigen::Index>& starts) {
  Eigen::VectorXd out = signal;
  for (const auto& [b, e] : Segments(starts, signal.size())) {
    if (e - b >= 3) out.segment(b, e - b) = ZeroPhaseLowPass(signal.segment(b, e - b), sample_period, cutoff_hz);
  }
  return out;
}

Eigen::VectorXd HeldSignalAtSampleInstants(const Eigen::Ref<const Eigen::VectorXd>& signal,
                                          const std::vector<Eigen::Index>& starts) {
  Eigen::VectorXd out = signal;
  for (const auto& [b, e] : Segments(starts, signal.size())) {
    for (Eigen::Index i = b + 1; i < e; ++i) out(i) = 0.5 * (signal(i - 1) + signal(i));
  }
  return out;
}

MotionDerivatives DeriveMotionBySegment(const Eigen::Ref<const Eigen::VectorXd>& time,
                                        const Eigen::Ref<const Eigen::VectorXd>& position, double cutoff_hz,
                                        const std::vector<Eigen::Index>& starts) {
  RequireSameSize(time, position, "DeriveMotionBySegment");
  MotionDerivatives m{position, Eigen::VectorXd::Zero(time.size()), Eigen::VectorXd::Zero(time.size())};
  const double ts = MedianTimeStep(time);
  for (const auto& [b, e] : Segments(starts, time.size())) {
    if (e - b < 3) continue;
    m.position.segment(b, e - b) = ZeroPhaseLowPass(position.segment(b, e - b), ts, cutoff_hz);
    m.velocity.segment(b, e - b) = CentralDifference(time.segment(b, e - b), m.position.segment(b, e - b));
    m.acceleration.segment(b, e - b) = CentralDifference(time.segment(b, e - b), m.velocity.segment(b, e - b));
  }
  return m;
}

double Rmse(const Eigen::Ref<const Eigen::VectorXd>& measured, const Eigen::Ref<const Eigen::VectorXd>& model) {
  RequireSameSize(measured, model, "Rmse");
  return std::sqrt((measured - model).squaredNorm() / static_cast<double>(measured.size()));
}

Eigen::Index FilterEdgeSamples(Eigen::Index n, double sample_period, double cutoff_hz) noexcept {
  if (!(cutoff_hz > 0.0) || !(sample_period > 0.0) || n <= 0) return 0;
  const double samples = std::ceil(2.0 / (cutoff_hz * sample_period));
  return static_cast<Eigen::Index>(std::min(samples, 0.05 * static_cast<double>(n)));
}

Eigen::VectorXd InteriorWeights(Eigen::Index n, const std::vector<Eigen::Index>& starts, double sample_period,
                                double cutoff_hz) {
  Eigen::VectorXd weight = Eigen::VectorXd::Ones(n);
  for (const auto& [b, e] : Segments(starts, n)) {
    const Eigen::Index edge = FilterEdgeSamples(e - b, sample_period, cutoff_hz);
    weight.segment(b, edge).setZero();
    weight.segment(e - edge, edge).setZero();
  }
  return weight;
}

double InteriorRmse(const Eigen::Ref<const Eigen::VectorXd>& measured, const Eigen::Ref<const Eigen::VectorXd>& model,
                    const std::vector<Eigen::Index>& starts, double sample_period, double cutoff_hz) {
  RequireSameSize(measured, model, "InteriorRmse");
  const Eigen::VectorXd weight = InteriorWeights(measured.size(), starts, sample_period, cutoff_hz);
  const double count = weight.sum();
  if (!(count > 0.0)) return Rmse(measured, model);
  return std::sqrt(weight.cwiseProduct(measured - model).squaredNorm() / count);
}

double FitPercent(const Eigen::Ref<const Eigen::VectorXd>& measured,
                  const Eigen::Ref<const Eigen::VectorXd>& model) {
  RequireSameSize(measured, model, "FitPercent");
  const double spread = (measured.array() - measured.mean()).matrix().norm();
  if (!(spread > 0.0)) {
    throw std::invalid_argument("FitPercent: the measured signal is constant, the fit is undefined");
  }
  return 100.0 * (1.0 - (measured - model).norm() / spread);
}

AutocorrelationTest ResidualAutocorrelation(const Eigen::Ref<const Eigen::VectorXd>& residual,
                                            Eigen::Index max_lag) {
  const Eigen::Index n = residual.size();
  if (max_lag < 1 || n <= max_lag + 1) {
    throw std::invalid_argument(fmt::format(
        "ResidualAutocorrelation: max_lag {} must be >= 1 and below N − 1 = {}", max_lag, n - 1));
  }
  for (Eigen::Index i = 0; i < n; ++i) {
    if (!std::isfinite(residual(i))) {
      throw std::invalid_argument(fmt::format(
          "the residual between the model and the measurement is {} at sample {} of {}: no whiteness test is "
          "possible. Check the measured column's values and unit and that the model's output is finite there",
          residual(i), i, n));
    }
  }
  const Eigen::VectorXd e = residual.array() - residual.mean();
  const double c0 = e.squaredNorm();
  if (!std::isfinite(c0)) {
    throw std::invalid_argument(fmt::format(
        "the residual between the model and the measurement overflows (its energy is {} over {} samples; largest "
        "|r| = {:.3g}): no whiteness test is possible. Check the measured column's unit and values (values near "
        "1e300 overflow)", c0, n, residual.cwiseAbs().maxCoeff()));
  }
  if (!(c0 > 0.0)) throw std::invalid_argument("ResidualAutocorrelation: the residual is constant");
  AutocorrelationTest out;
  out.autocorrelation.resize(max_lag + 1);
  const double nd = static_cast<double>(n);
  double q = 0.0;
  for (Eigen::Index k = 0; k <= max_lag; ++k) {
    const double r = e.head(n - k).dot(e.tail(n - k)) / c0;
    out.autocorrelation(k) = r;
    if (k > 0) q += r * r / (nd - static_cast<double>(k));
  }
  out.band99 = 2.58 / std::sqrt(nd);
  out.ljung_box_q = nd * (nd + 2.0) * q;
  const boost::math::chi_squared chi2(static_cast<double>(max_lag));
  out.p_value = boost::math::cdf(boost::math::complement(chi2, out.ljung_box_q));
  out.white = out.p_value >= 0.01;
  return out;
}

CrossCorrelationTest InputResidualCrossCorrelation(const Eigen::Ref<const Eigen::VectorXd>& input,
                                                   const Eigen::Ref<const Eigen::VectorXd>& residual,
                                                   Eigen::Index max_lag) {
  RequireSameSize(input, residual, "InputResidualCrossCorrelation");
  const Eigen::Index n = input.size();
  if (max_lag < 0 || n <= max_lag + 1) {
    throw std::invalid_argument(fmt::format(
        "InputResidualCrossCorrelation: max_lag {} must be >= 0 and below N − 1 = {}", max_lag, n - 1));
  }
  const Eigen::VectorXd u = input.array() - input.mean();
  const Eigen::VectorXd e = residual.array() - residual.mean();
  const double norm = u.norm() * e.norm();
  if (!(norm > 0.0)) {
    throw std::invalid_argument("InputResidualCrossCorrelation: the input or the residual is constant");
  }
  CrossCorrelationTest out;
  out.lags.resize(2 * max_lag + 1);
  out.correlation.resize(2 * max_lag + 1);
  for (Eigen::Index j = 0; j < 2 * max_lag + 1; ++j) {
    const Eigen::Index k = j - max_lag;
    const Eigen::Index m = n - std::abs(k);
    // e(t)·u(t − k): for k >= 0 pair e(k..) with u(0..), else e(0..) with u(−k..).
    const double s = k >= 0 ? e.tail(m).dot(u.head(m)) : e.head(m).dot(u.tail(m));
    out.lags(j) = static_cast<int>(k);
    out.correlation(j) = s / norm;
    if (std::abs(out.correlation(j)) > std::abs(out.peak_value)) {
      out.peak_value = out.correlation(j);
      out.peak_lag = k;
    }
  }
  out.band99 = 2.58 / std::sqrt(static_cast<double>(n));
  out.significant = std::abs(out.peak_value) > out.band99;
  return out;
}

PowerSpectrum WelchPowerSpectrum(const Eigen::Ref<const Eigen::VectorXd>& signal, double sample_period,
                                 Eigen::Index segment_length) {
  const Eigen::Index n = signal.size();
  if (!(sample_period > 0.0) || segment_length < 8 || n < 8) {
    throw std::invalid_argument(fmt::format(
        "WelchPowerSpectrum: needs a positive sample period (got {} s), segment_length >= 8 (got {}) "
        "and at least 8 samples (got {})",
        sample_period, segment_length, n));
  }
  const Eigen::Index m = std::min(segment_length, n);
  const Eigen::Index step = std::max<Eigen::Index>(1, m / 2);
  std::vector<double> window(static_cast<std::size_t>(m));
  double window_energy = 0.0;
  for (Eigen::Index i = 0; i < m; ++i) {
    const double w = 0.5 - 0.5 * std::cos(2.0 * std::numbers::pi * static_cast<double>(i) / static_cast<double>(m));
    window[static_cast<std::size_t>(i)] = w;
    window_energy += w * w;
  }
  const Eigen::Index bins = m / 2 + 1;
  PowerSpectrum out;
  out.density = Eigen::VectorXd::Zero(bins);
  out.frequency_hz = Eigen::VectorXd::LinSpaced(bins, 0.0, static_cast<double>(bins - 1) / (static_cast<double>(m) * sample_period));
  Fft fft;
  std::vector<double> segment(static_cast<std::size_t>(m));
  std::vector<std::complex<double>> spectrum;
  Eigen::Index segments = 0;
  for (Eigen::Index start = 0; start + m <= n; start += step) {
    const double mean = signal.segment(start, m).mean();
    for (Eigen::Index i = 0; i < m; ++i) {
      segment[static_cast<std::size_t>(i)] = (signal(start + i) - mean) * window[static_cast<std::size_t>(i)];
    }
    fft.Forward(segment, &spectrum);
    for (Eigen::Index k = 0; k < bins; ++k) out.density(k) += std::norm(spectrum[static_cast<std::size_t>(k)]);
    ++segments;
  }
  const double scale = sample_period / (window_energy * static_cast<double>(segments));
  out.density *= scale;
  // One-sided: double every bin but DC and (for even m) Nyquist.
  const Eigen::Index last_doubled = (m % 2 == 0) ? bins - 2 : bins - 1;
  if (last_doubled >= 1) out.density.segment(1, last_doubled).array() *= 2.0;
  return out;
}

NoiseFloor EstimateNoiseFloor(const Eigen::Ref<const Eigen::VectorXd>& residual, double sample_period,
                              double band_limit_hz) {
  const double nyquist = 0.5 / sample_period;
  if (!(sample_period > 0.0) || !(band_limit_hz < nyquist)) {
    throw std::invalid_argument(fmt::format("EstimateNoiseFloor: needs a positive sample period (got {} s) and a band "
                                            "limit below the Nyquist frequency {} Hz (got {} Hz)",
                                            sample_period, nyquist, band_limit_hz));
  }
  NoiseFloor out;
  const Eigen::Index n = residual.size();
  const Eigen::Index segment = n >= 2048 ? 256 : 128;
  if (n < 8 * segment) return out;
  const bool filtered = band_limit_hz > 0.0;
  out.band_low_hz = filtered ? 0.25 * band_limit_hz : 0.5 * nyquist;
  out.band_high_hz = filtered ? 0.5 * band_limit_hz : 0.95 * nyquist;
  // Each segment's median level over the band's bins (each divided by the filter's power gain there), made an unbiased
  // mean by the expected median of as many exponential variates (a white density's bins, χ²₂/2); the median over the
  // segments.
  std::vector<double> level, bins;
  for (Eigen::Index start = 0; start + segment <= n; start += segment / 2) {
    const PowerSpectrum spectrum = WelchPowerSpectrum(residual.segment(start, segment), sample_period, segment);
    bins.clear();
    for (Eigen::Index k = 0; k < spectrum.frequency_hz.size(); ++k) {
      const double f = spectrum.frequency_hz(k);
      if (f < out.band_low_hz || f > out.band_high_hz) continue;
      const double u4 = filtered ? std::pow(f / band_limit_hz, 4) : 0.0;
      bins.push_back(spectrum.density(k) * (1.0 + u4) * (1.0 + u4));
    }
    if (bins.size() < 3) continue;
    std::sort(bins.begin(), bins.end());
    // E[X_(j)] of k standard exponentials = Σ_{i=k−j+1..k} 1/i (Rényi); the median's j = (k + 1)/2, or the mean of the
    // two middle ones for an even k.
    const std::size_t k = bins.size();
    const auto expected = [k](std::size_t j) {
      double e = 0.0;
      for (std::size_t i = k - j + 1; i <= k; ++i) e += 1.0 / static_cast<double>(i);
      return e;
    };
    const double median = k % 2 == 1 ? bins[k / 2] : 0.5 * (bins[k / 2 - 1] + bins[k / 2]);
    const double scale = k % 2 == 1 ? expected(k / 2 + 1) : 0.5 * (expected(k / 2) + expected(k / 2 + 1));
    level.push_back(median / scale);
  }
  if (level.size() < 8) return out;
  // The quietest tenth of the segments: the axis at rest (no ripple in the band) or moving without a friction's chatter.
  const auto quiet = level.begin() + static_cast<std::ptrdiff_t>(level.size() / 10);
  std::nth_element(level.begin(), quiet, level.end());
  const double bandwidth = filtered ? 3.0 * std::numbers::pi / (8.0 * std::sqrt(2.0)) * band_limit_hz : nyquist;
  out.rms = out.white_rms = std::sqrt(*quiet * bandwidth);
  return out;
}

}  // namespace mb

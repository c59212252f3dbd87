#include "models/diagnosis/frequency_response.h"

#include <cmath>
#include <complex>
#include <numbers>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "models/diagnosis/fft.h"

namespace mb {

namespace {

// The Hann-windowed spectrum of signal[start, start + m) with its mean removed.
void WindowedSpectrum(const Eigen::Ref<const Eigen::VectorXd>& signal, Eigen::Index start,
                      const std::vector<double>& window, Fft* fft, std::vector<double>* segment,
                      std::vector<std::complex<double>>* spectrum) {
  const auto m = static_cast<Eigen::Index>(window.size());
  const double mean = signal.segment(start, m).mean();
  for (Eigen::Index i = 0; i < m; ++i) {
    (*segment)[static_cast<std::size_t>(i)] = (signal(start + i) - mean) * window[static_cast<std::size_t>(i)];
  }
  fft->Forward(*segment, spectrum);
}

}  // namespace

FrequencyResponseEstimate EstimateFrequencyResponse(const Eigen::Ref<const Eigen::VectorXd>& input,
                                                    const Eigen::Ref<const Eigen::VectorXd>& output,
                                                    double sample_period, Eigen::Index segment_length) {
  const Eigen::Index n = input.size();
  if (output.size() != n || !(sample_period > 0.0) || segment_length < 8 || n < 8 || !input.allFinite() ||
      !output.allFinite()) {
    throw std::invalid_argument(fmt::format(
        "EstimateFrequencyResponse: needs input and output of one length (got {} and {}), finite samples, a positive "
        "sample period (got {} s), segment_length >= 8 (got {}) and at least 8 samples",
        n, output.size(), sample_period, segment_length));
  }
  const Eigen::Index m = std::min(segment_length, n);
  std::vector<double> window(static_cast<std::size_t>(m));
  for (Eigen::Index i = 0; i < m; ++i) {
    window[static_cast<std::size_t>(i)] =
        0.5 - 0.5 * std::cos(2.0 * std::numbers::pi * static_cast<double>(i) / static_cast<double>(m));
  }
  const Eigen::Index bins = m / 2 + 1;
  Eigen::VectorXd puu = Eigen::VectorXd::Zero(bins), pyy = Eigen::VectorXd::Zero(bins);
  Eigen::VectorXcd puy = Eigen::VectorXcd::Zero(bins);
  Fft fft;
  std::vector<double> segment(static_cast<std::size_t>(m));
  std::vector<std::complex<double>> u_spectrum, y_spectrum;
  FrequencyResponseEstimate out;
  for (Eigen::Index start = 0; start + m <= n; start += std::max<Eigen::Index>(1, m / 2)) {
    WindowedSpectrum(input, start, window, &fft, &segment, &u_spectrum);
    WindowedSpectrum(output, start, window, &fft, &segment, &y_spectrum);
    for (Eigen::Index k = 0; k < bins; ++k) {
      const auto& u = u_spectrum[static_cast<std::size_t>(k)];
      const auto& y = y_spectrum[static_cast<std::size_t>(k)];
      puu(k) += std::norm(u);
      pyy(k) += std::norm(y);
      puy(k) += std::conj(u) * y;
    }
    ++out.segments;
  }
  // The window and one-sided scale factors are common to the three spectra and cancel in H1 and γ².
  out.frequency_hz =
      Eigen::VectorXd::LinSpaced(bins, 0.0, static_cast<double>(bins - 1) / (static_cast<double>(m) * sample_period));
  out.response.resize(bins);
  out.coherence.resize(bins);
  for (Eigen::Index k = 0; k < bins; ++k) {
    const bool excited = puu(k) > 0.0 && pyy(k) > 0.0;
    out.response(k) = puu(k) > 0.0 ? puy(k) / puu(k) : std::complex<double>(0.0, 0.0);
    out.coherence(k) = excited ? std::min(1.0, std::norm(puy(k)) / (puu(k) * pyy(k))) : 0.0;
  }
  return out;
}

}  // namespace mb

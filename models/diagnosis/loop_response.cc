#include "models/diagnosis/loop_response.h"

#include <algorithm>
#include <complex>
#include <numbers>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>

#include "models/diagnosis/fft.h"

namespace mb {

LoopResponse::LoopResponse(Eigen::VectorXd impulse_response, Eigen::Index samples)
    : h_(std::move(impulse_response)), samples_(samples) {
  if (h_.size() == 0 || !h_.allFinite() || !(h_.cwiseAbs().maxCoeff() > 0.0) || samples_ < 1) {
    throw std::invalid_argument(fmt::format(
        "LoopResponse: needs a finite, non-zero impulse response (got {} values) and a record of at least one sample "
        "(got {})",
        h_.size(), samples_));
  }
  if (h_.size() > samples_) h_.conservativeResize(samples_);  // what lies beyond the record never reaches it
  padded_ = 1;
  while (padded_ < samples_ + h_.size() - 1) padded_ *= 2;
  std::vector<double> padded(static_cast<std::size_t>(padded_), 0.0);
  for (Eigen::Index k = 0; k < h_.size(); ++k) padded[static_cast<std::size_t>(k)] = h_(k);
  Fft().Forward(padded, &h_spectrum_);
}

Eigen::MatrixXd LoopResponse::Simulate(const Eigen::Ref<const Eigen::MatrixXd>& columns) const {
  if (!simulator_) return Apply(columns);
  if (columns.rows() != samples_) {
    throw std::invalid_argument(
        fmt::format("LoopResponse::Simulate: columns of {} samples, the record has {}", columns.rows(), samples_));
  }
  Eigen::MatrixXd out = simulator_(columns);
  simulated_->columns += out.cols();
  for (Eigen::Index j = 0; j < out.cols(); ++j) {  // a response the simulation could not give: the linearised one
    if (out.col(j).allFinite()) continue;
    out.col(j) = Apply(columns.col(j));
    ++simulated_->linearised;
  }
  return out;
}

Eigen::MatrixXd LoopResponse::Apply(const Eigen::Ref<const Eigen::MatrixXd>& columns) const {
  if (columns.rows() != samples_) {
    throw std::invalid_argument(
        fmt::format("LoopResponse::Apply: columns of {} samples, the record has {}", columns.rows(), samples_));
  }
  Eigen::MatrixXd out(samples_, columns.cols());
  Fft fft;
  std::vector<double> padded(static_cast<std::size_t>(padded_));
  std::vector<std::complex<double>> spectrum;
  for (Eigen::Index j = 0; j < columns.cols(); ++j) {
    std::fill(padded.begin(), padded.end(), 0.0);
    for (Eigen::Index i = 0; i < samples_; ++i) padded[static_cast<std::size_t>(i)] = columns(i, j);
    fft.Forward(padded, &spectrum);
    for (std::size_t k = 0; k < spectrum.size(); ++k) spectrum[k] *= h_spectrum_[k];
    fft.Inverse(spectrum, &padded);
    for (Eigen::Index i = 0; i < samples_; ++i) out(i, j) = padded[static_cast<std::size_t>(i)];
  }
  return out;
}

Eigen::VectorXd LoopResponse::ForceOf(const Eigen::Ref<const Eigen::VectorXd>& output, double regularisation) const {
  if (output.size() != samples_) {
    throw std::invalid_argument(
        fmt::format("LoopResponse::ForceOf: an output of {} samples, the record has {}", output.size(), samples_));
  }
  double peak = 0.0;
  for (const auto& h : h_spectrum_) peak = std::max(peak, std::norm(h));
  const double lambda = regularisation * peak;
  Fft fft;
  std::vector<double> padded(static_cast<std::size_t>(padded_), 0.0);
  for (Eigen::Index i = 0; i < samples_; ++i) padded[static_cast<std::size_t>(i)] = output(i);
  std::vector<std::complex<double>> spectrum;
  fft.Forward(padded, &spectrum);
  for (std::size_t k = 0; k < spectrum.size(); ++k) {
    spectrum[k] *= std::conj(h_spectrum_[k]) / (std::norm(h_spectrum_[k]) + lambda);
  }
  fft.Inverse(spectrum, &padded);
  Eigen::VectorXd out(samples_);
  for (Eigen::Index i = 0; i < samples_; ++i) out(i) = padded[static_cast<std::size_t>(i)];
  return out;
}

double LoopResponse::GainAt(double frequency_hz, double sample_period) const {
  const double w = 2.0 * std::numbers::pi * frequency_hz * sample_period;
  std::complex<double> gain = 0.0;
  for (Eigen::Index k = 0; k < h_.size(); ++k) gain += h_(k) * std::polar(1.0, -w * static_cast<double>(k));
  return std::abs(gain);
}

}  // namespace mb

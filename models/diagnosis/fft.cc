#include "models/diagnosis/fft.h"

#include <algorithm>

#include <unsupported/Eigen/FFT>

namespace mb {

std::ptrdiff_t FastFftLength(std::ptrdiff_t n) {
  std::ptrdiff_t best = 1;
  for (std::ptrdiff_t p2 = 1; p2 <= n; p2 *= 2) {
    for (std::ptrdiff_t p3 = p2; p3 <= n; p3 *= 3) {
      for (std::ptrdiff_t p5 = p3; p5 <= n; p5 *= 5) best = std::max(best, p5);
    }
  }
  return best;
}

struct Fft::Impl {
  Eigen::FFT<double> fft;
};

Fft::Fft(bool half_spectrum) : impl_(std::make_unique<Impl>()) {
  if (half_spectrum) impl_->fft.SetFlag(Eigen::FFT<double>::HalfSpectrum);
}

Fft::~Fft() = default;

void Fft::Forward(const std::vector<double>& x, std::vector<std::complex<double>>* spectrum) {
  impl_->fft.fwd(*spectrum, x);
}

void Fft::Forward(const std::vector<std::complex<double>>& z, std::vector<std::complex<double>>* spectrum) {
  impl_->fft.fwd(*spectrum, z);
}

void Fft::Inverse(const std::vector<std::complex<double>>& spectrum, std::vector<double>* x) {
  impl_->fft.inv(*x, spectrum);
}

}  // namespace mb

#pragma once
// The diagnosis' discrete Fourier transforms behind one translation unit (fft.cc): Eigen's FFT module
// (unsupported/Eigen/FFT with its default kissfft backend). Under the sanitizers (MB_SANITIZE) that unit alone is
// compiled without AddressSanitizer (models/diagnosis/CMakeLists.txt): kissfft's butterflies are third-party
// arithmetic on buffers this class sizes, and even uninstrumented they are a tenth of a grammar draw's compare there.

#include <complex>
#include <cstddef>
#include <memory>
#include <vector>

namespace mb {

/// The largest length ≤ n (n ≥ 1) whose only prime factors are 2, 3 and 5: kissfft's own radices. Any other prime
/// factor p goes through its generic butterfly at O(p) per point — a window of 4166 = 2·2083 samples took a third of
/// a compare (Release). 1 for n < 1.
std::ptrdiff_t FastFftLength(std::ptrdiff_t n);

/// Forward and inverse DFT as Eigen::FFT computes them: X_k = Σ_j x_j e^{−2πijk/N}, unnormalised; the inverse
/// divides by N. A transform keeps its twiddle tables between calls of the same length. Not thread-safe: one per
/// thread. Any length N ≥ 1 (a power of two is fastest). Throws nothing beyond std::bad_alloc.
class Fft {
 public:
  /// half_spectrum: the forward transform of a real input holds k = 0..N/2 only (the rest is its conjugate mirror).
  explicit Fft(bool half_spectrum = false);
  ~Fft();
  Fft(const Fft&) = delete;
  Fft& operator=(const Fft&) = delete;

  /// Real x (N) → its spectrum (N, or N/2 + 1 with half_spectrum), resized.
  void Forward(const std::vector<double>& x, std::vector<std::complex<double>>* spectrum);
  /// Complex z (N) → its spectrum (N), resized.
  void Forward(const std::vector<std::complex<double>>& z, std::vector<std::complex<double>>* spectrum);
  /// The real signal (N, resized) of a full spectrum (N) of a real signal.
  void Inverse(const std::vector<std::complex<double>>& spectrum, std::vector<double>* x);

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace mb

#include "models/gpr/basis.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>
#include <utility>

#include "models/gpr/sincos.h"
#include "models/physics/fourier_series.h"

namespace mb {
namespace {

constexpr double kPi = std::numbers::pi;

void RequirePositive(double value, const char* what, const char* where) {
  if (!(value > 0.0) || !std::isfinite(value)) {
    throw std::invalid_argument(std::string(where) + ": " + what +
                                " must be finite and > 0, got " + std::to_string(value));
  }
}

void RequireTolerance(double tolerance, const char* where) {
  if (!(tolerance > 0.0 && tolerance < 1.0)) {
    throw std::invalid_argument(std::string(where) + ": tolerance must lie in (0, 1), got " +
                                std::to_string(tolerance));
  }
}

// Harmonics beyond which q_j² < 1e-300 (q_j² ≈ exp(−j²/(2z)) for large z, (z/2)^j/j! for small z).
int NegligibleHarmonic(double z) {
  return 50 + static_cast<int>(std::ceil(std::sqrt(1400.0 * z)));
}

// The harmonics of one bounded phase θ in [0, 2π] (models/physics/fourier_series.h): sin θ, cos θ by
// SinCosBounded, then four independent recurrence chains (fn(j, cos jθ, sin jθ, lane), lane = (j − 1) mod 4).
template <typename Fn>
inline void ForEachHarmonic(double theta, int n, Fn&& fn) noexcept {
  double s1 = 0.0;
  double c1 = 0.0;
  SinCosBounded(theta, &s1, &c1);
  mb::ForEachHarmonic<4>(c1, s1, n, std::forward<Fn>(fn));
}

// As ForEachHarmonic, sines only (fn(j, sin jθ, lane)): the Chebyshev recurrence of fourier_series.h.
template <typename Fn>
inline void ForEachSineHarmonic(double theta, int n, Fn&& fn) noexcept {
  double s1 = 0.0;
  double c1 = 0.0;
  SinCosBounded(theta, &s1, &c1);
  mb::ForEachSineHarmonic(c1, s1, n, std::forward<Fn>(fn));
}

// Phase ωx = 2π·frac(x/τ): reduces the argument before the trigonometric calls.
inline double PeriodicPhase(double x, double period) noexcept {
  const double t = x / period;
  return 2.0 * kPi * (t - std::floor(t));
}

inline bool InsideDomain(const HilbertDomain& d, double u) noexcept {
  return std::abs(u - d.center) <= d.half_width;
}

inline double HilbertPhase(const HilbertDomain& d, double u) noexcept {
  return kPi * (u - d.center + d.half_width) / (2.0 * d.half_width);
}

void HilbertWeights(const HilbertDomain& d, double signal_variance, double length_scale,
                    Eigen::Index offset, int variance_column, int length_column,
                    Eigen::VectorXd* s, Eigen::MatrixXd* dlog_s) {
  const double l2 = length_scale * length_scale;
  const double amplitude = signal_variance * std::sqrt(2.0 * kPi) * length_scale;
  for (int j = 1; j <= d.count; ++j) {
    const double omega = kPi * j / (2.0 * d.half_width);
    const Eigen::Index k = offset + j - 1;
    (*s)(k) = amplitude * std::exp(-0.5 * l2 * omega * omega);
    if (dlog_s != nullptr) {
      (*dlog_s)(k, variance_column) = 1.0;
      (*dlog_s)(k, length_column) = 1.0 - l2 * omega * omega;
    }
  }
}

int HilbertCountFor(double half_width, double length_scale, double tolerance) {
  const double omega_max = std::sqrt(2.0 * std::log(1.0 / tolerance)) / length_scale;
  return static_cast<int>(std::ceil(2.0 * half_width * omega_max / kPi));
}

}  // namespace

int GprPositionFeatureCount(const GprBasis& basis) noexcept {
  return basis.kernel == GprKernel::kPeriodicSe ? 2 * basis.harmonics + 1 : basis.x_domain.count;
}

int GprFeatureCount(const GprBasis& basis) noexcept {
  return GprPositionFeatureCount(basis) + basis.xdot_domain.count;
}

Eigen::VectorXd PeriodicSpectralWeights(double length_scale, int harmonics,
                                        Eigen::VectorXd* dlog_dlogl) {
  RequirePositive(length_scale, "length_scale_x", "PeriodicSpectralWeights");
  if (harmonics < 0) {
    throw std::invalid_argument("PeriodicSpectralWeights: harmonics must be >= 0, got " +
                                std::to_string(harmonics));
  }
  const double z = 1.0 / (length_scale * length_scale);
  const int m = std::max(harmonics, NegligibleHarmonic(z)) + 1;
  // ratio(j) = I_j(z)/I_{j−1}(z) by the backward recurrence I_{j−1} = (2j/z) I_j + I_{j+1}.
  Eigen::VectorXd ratio(m + 2);
  ratio(m + 1) = 0.0;
  for (int j = m; j >= 1; --j) ratio(j) = z / (2.0 * j + z * ratio(j + 1));
  // p_j = I_j/I_0; Σ q_j² = 1 ⇔ e^{−z} I_0 (1 + 2 Σ p_j) = 1 (the generating function at θ = 0).
  double p = 1.0;
  double sum = 1.0;
  Eigen::VectorXd ratios_to_zero(harmonics + 1);
  ratios_to_zero(0) = 1.0;
  for (int j = 1; j <= m; ++j) {
    p *= ratio(j);
    sum += 2.0 * p;
    if (j <= harmonics) ratios_to_zero(j) = p;
  }
  Eigen::VectorXd q2(harmonics + 1);
  q2(0) = 1.0 / sum;
  for (int j = 1; j <= harmonics; ++j) q2(j) = 2.0 * ratios_to_zero(j) / sum;
  if (dlog_dlogl != nullptr) {
    // d log(e^{−z} I_j)/dz = (I_{j−1} + I_{j+1})/(2 I_j) − 1, with I_{−1} = I_1; dz/dlog ℓ = −2z.
    dlog_dlogl->resize(harmonics + 1);
    (*dlog_dlogl)(0) = -2.0 * z * (ratio(1) - 1.0);
    for (int j = 1; j <= harmonics; ++j) {
      (*dlog_dlogl)(j) = -2.0 * z * (0.5 * (1.0 / ratio(j) + ratio(j + 1)) - 1.0);
    }
  }
  return q2;
}

int PeriodicHarmonicsForTolerance(double length_scale, double tolerance) {
  RequirePositive(length_scale, "length_scale_x", "PeriodicHarmonicsForTolerance");
  RequireTolerance(tolerance, "PeriodicHarmonicsForTolerance");
  const double z = 1.0 / (length_scale * length_scale);
  const Eigen::VectorXd q2 = PeriodicSpectralWeights(length_scale, NegligibleHarmonic(z));
  double tail = 0.0;
  int j = static_cast<int>(q2.size()) - 1;
  while (j > 0 && tail + q2(j) <= tolerance) {
    tail += q2(j);
    --j;
  }
  return j;
}

HilbertDomain HilbertDomainForTolerance(GprRange range, double length_scale, double tolerance) {
  RequirePositive(length_scale, "length scale", "HilbertDomainForTolerance");
  RequireTolerance(tolerance, "HilbertDomainForTolerance");
  if (!std::isfinite(range.min) || !std::isfinite(range.max) || range.max < range.min) {
    throw std::invalid_argument("HilbertDomainForTolerance: the range [" +
                                std::to_string(range.min) + ", " + std::to_string(range.max) +
                                "] is empty or not finite");
  }
  const double margin =
      length_scale * std::max(3.0, std::sqrt(0.5 * std::log(1.0 / tolerance)));
  HilbertDomain d;
  d.center = 0.5 * (range.min + range.max);
  d.half_width = 0.5 * (range.max - range.min) + margin;
  d.count = HilbertCountFor(d.half_width, length_scale, tolerance);
  return d;
}

GprBasis ChooseGprBasis(GprKernel kernel, const GprHyperparameters& hp, GprRange x_range,
                        GprRange xdot_range, double tolerance) {
  GprBasis basis;
  basis.kernel = kernel;
  basis.period = hp.period;
  if (kernel == GprKernel::kPeriodicSe) {
    RequirePositive(hp.period, "period", "ChooseGprBasis");
    basis.harmonics = PeriodicHarmonicsForTolerance(hp.length_scale_x, tolerance);
  } else {
    basis.x_domain = HilbertDomainForTolerance(x_range, hp.length_scale_x, tolerance);
  }
  basis.xdot_domain = HilbertDomainForTolerance(xdot_range, hp.length_scale_xdot, tolerance);
  if (GprFeatureCount(basis) > kMaxGprFeatures) {
    throw std::runtime_error(
        "ChooseGprBasis: the kernel at length_scale_x = " + std::to_string(hp.length_scale_x) +
        ", length_scale_xdot = " + std::to_string(hp.length_scale_xdot) + " needs " +
        std::to_string(GprFeatureCount(basis)) + " features (limit " +
        std::to_string(kMaxGprFeatures) +
        "): raise the lower bound of the length scale that is too short, or the tolerance");
  }
  return basis;
}

bool GprBasisSuffices(const GprBasis& basis, const GprHyperparameters& hp, GprRange x_range,
                      GprRange xdot_range, double tolerance) {
  const auto domain_ok = [&](const HilbertDomain& have, GprRange range, double length_scale) {
    const HilbertDomain need = HilbertDomainForTolerance(range, length_scale, tolerance);
    return have.center == need.center && have.half_width >= need.half_width &&
           have.count >= HilbertCountFor(have.half_width, length_scale, tolerance);
  };
  if (basis.kernel == GprKernel::kPeriodicSe) {
    if (basis.period != hp.period) return false;
    if (basis.harmonics < PeriodicHarmonicsForTolerance(hp.length_scale_x, tolerance)) {
      return false;
    }
  } else if (!domain_ok(basis.x_domain, x_range, hp.length_scale_x)) {
    return false;
  }
  return domain_ok(basis.xdot_domain, xdot_range, hp.length_scale_xdot);
}

void GprSpectralWeights(const GprBasis& basis, const GprHyperparameters& hp, Eigen::VectorXd* s,
                        Eigen::MatrixXd* dlog_s) {
  const Eigen::Index m = GprFeatureCount(basis);
  s->resize(m);
  if (dlog_s != nullptr) dlog_s->setZero(m, kGprParameterCount);
  Eigen::Index offset = 0;
  if (basis.kernel == GprKernel::kPeriodicSe) {
    if (hp.period != basis.period) {
      throw std::invalid_argument("GprSpectralWeights: the basis was built for period " +
                                  std::to_string(basis.period) + " m but the hyperparameters have " +
                                  std::to_string(hp.period) + " m: rebuild the basis");
    }
    Eigen::VectorXd dlog_q;
    const Eigen::VectorXd q2 = PeriodicSpectralWeights(hp.length_scale_x, basis.harmonics,
                                                       dlog_s != nullptr ? &dlog_q : nullptr);
    for (int j = 0; j <= basis.harmonics; ++j) {
      for (Eigen::Index k : {Eigen::Index{2 * j - 1}, Eigen::Index{2 * j}}) {
        if (k < 0) continue;
        (*s)(k) = hp.signal_variance_x * q2(j);
        if (dlog_s != nullptr) {
          (*dlog_s)(k, kLogSignalVarianceX) = 1.0;
          (*dlog_s)(k, kLogLengthScaleX) = dlog_q(j);
        }
      }
    }
    offset = 2 * basis.harmonics + 1;
  } else {
    HilbertWeights(basis.x_domain, hp.signal_variance_x, hp.length_scale_x, 0,
                   kLogSignalVarianceX, kLogLengthScaleX, s, dlog_s);
    offset = basis.x_domain.count;
  }
  HilbertWeights(basis.xdot_domain, hp.signal_variance_xdot, hp.length_scale_xdot, offset,
                 kLogSignalVarianceXdot, kLogLengthScaleXdot, s, dlog_s);
}

namespace {

// Writes the m Hilbert eigenfunctions of `d` at u (0 outside the domain).
inline void EvaluateHilbert(const HilbertDomain& d, double u, double* psi) noexcept {
  if (!InsideDomain(d, u)) {
    std::fill(psi, psi + d.count, 0.0);
    return;
  }
  const double scale = 1.0 / std::sqrt(d.half_width);
  ForEachSineHarmonic(HilbertPhase(d, u), d.count,
                      [&](int j, double s, int) { psi[j - 1] = scale * s; });
}

inline void EvaluateHilbertDerivative(const HilbertDomain& d, double u, double* dpsi) noexcept {
  if (!InsideDomain(d, u)) {
    std::fill(dpsi, dpsi + d.count, 0.0);
    return;
  }
  const double scale = 1.0 / std::sqrt(d.half_width);
  const double dtheta = kPi / (2.0 * d.half_width);
  ForEachHarmonic(HilbertPhase(d, u), d.count,
                  [&](int j, double c, double, int) { dpsi[j - 1] = scale * dtheta * j * c; });
}

inline double DotHilbert(const HilbertDomain& d, const double* beta, double u) noexcept {
  if (!InsideDomain(d, u)) return 0.0;
  double acc[4] = {0.0, 0.0, 0.0, 0.0};
  ForEachSineHarmonic(HilbertPhase(d, u), d.count,
                      [&](int j, double s, int lane) { acc[lane] += beta[j - 1] * s; });
  return ((acc[0] + acc[1]) + (acc[2] + acc[3])) / std::sqrt(d.half_width);
}

}  // namespace

void EvaluateGprBasis(const GprBasis& basis, double x, double xdot, double* psi) noexcept {
  if (basis.kernel == GprKernel::kPeriodicSe) {
    psi[0] = 1.0;
    ForEachHarmonic(PeriodicPhase(x, basis.period), basis.harmonics,
                    [&](int j, double c, double s, int) {
      psi[2 * j - 1] = c;
      psi[2 * j] = s;
    });
  } else {
    EvaluateHilbert(basis.x_domain, x, psi);
  }
  EvaluateHilbert(basis.xdot_domain, xdot, psi + GprPositionFeatureCount(basis));
}

void EvaluateGprBasisDerivatives(const GprBasis& basis, double x, double xdot, double* dpsi_dx,
                                 double* dpsi_dxdot) noexcept {
  const int p = GprPositionFeatureCount(basis);
  const int m = GprFeatureCount(basis);
  std::fill(dpsi_dx + p, dpsi_dx + m, 0.0);
  std::fill(dpsi_dxdot, dpsi_dxdot + p, 0.0);
  if (basis.kernel == GprKernel::kPeriodicSe) {
    const double omega = 2.0 * kPi / basis.period;
    dpsi_dx[0] = 0.0;
    ForEachHarmonic(PeriodicPhase(x, basis.period), basis.harmonics,
                    [&](int j, double c, double s, int) {
      dpsi_dx[2 * j - 1] = -j * omega * s;
      dpsi_dx[2 * j] = j * omega * c;
    });
  } else {
    EvaluateHilbertDerivative(basis.x_domain, x, dpsi_dx);
  }
  EvaluateHilbertDerivative(basis.xdot_domain, xdot, dpsi_dxdot + p);
}

void EvaluateGprBasisPeriodDerivative(const GprBasis& basis, double x, double* dpsi_dtau) noexcept {
  std::fill(dpsi_dtau, dpsi_dtau + GprFeatureCount(basis), 0.0);
  if (basis.kernel != GprKernel::kPeriodicSe) return;
  const double omega_x_over_tau = 2.0 * kPi * x / (basis.period * basis.period);
  ForEachHarmonic(PeriodicPhase(x, basis.period), basis.harmonics,
                  [&](int j, double c, double s, int) {
    dpsi_dtau[2 * j - 1] = j * omega_x_over_tau * s;
    dpsi_dtau[2 * j] = -j * omega_x_over_tau * c;
  });
}

void GprBasisFrequencies(const GprBasis& basis, double* frequency) noexcept {
  const auto hilbert = [](const HilbertDomain& d, double* f) {
    for (int j = 1; j <= d.count; ++j) f[j - 1] = kPi * j / (2.0 * d.half_width);
  };
  if (basis.kernel == GprKernel::kPeriodicSe) {
    const double omega = 2.0 * kPi / basis.period;
    frequency[0] = 0.0;
    for (int j = 1; j <= basis.harmonics; ++j) {
      frequency[2 * j - 1] = j * omega;
      frequency[2 * j] = j * omega;
    }
  } else {
    hilbert(basis.x_domain, frequency);
  }
  hilbert(basis.xdot_domain, frequency + GprPositionFeatureCount(basis));
}

double DotGprBasis(const GprBasis& basis, const double* beta, double x, double xdot) noexcept {
  double position = 0.0;
  if (basis.kernel == GprKernel::kPeriodicSe) {
    double acc[4] = {beta[0], 0.0, 0.0, 0.0};
    ForEachHarmonic(PeriodicPhase(x, basis.period), basis.harmonics,
                    [&](int j, double c, double s, int lane) {
                      acc[lane] += beta[2 * j - 1] * c + beta[2 * j] * s;
                    });
    position = (acc[0] + acc[1]) + (acc[2] + acc[3]);
  } else {
    position = DotHilbert(basis.x_domain, beta, x);
  }
  return position + DotHilbert(basis.xdot_domain, beta + GprPositionFeatureCount(basis), xdot);
}

}  // namespace mb

#pragma once
// Synthetic DOB-like disturbance data for the GPR tests and benchmarks: constant-velocity scans of
// a linear motor, d(x, ẋ) = cogging(x)·(1 + 0.2 ẋ/0.5) + offset(ẋ) + noise, the structure of the
// paper's eq. 13 (position-periodic part whose amplitude varies with velocity, velocity-dependent
// offset, residual). Header-only; used by tests/gpr and tests/benchmarks/gpr_benchmark.cc.

#include <cmath>
#include <cstdint>
#include <numbers>
#include <random>
#include <vector>

#include <Eigen/Core>

namespace mb::testing {

inline constexpr double kPolePitch = 0.0225;  // τ [m], the paper's magnet spacing

struct DisturbanceSamples {
  Eigen::VectorXd x;     // [m]
  Eigen::VectorXd xdot;  // [m/s]
  Eigen::VectorXd d;     // [N]
};

/// Cogging force [N] with spatial period `period`: fundamental plus a second harmonic.
inline double Cogging(double x, double period = kPolePitch) {
  const double w = 2.0 * std::numbers::pi / period;
  return 0.5 * std::sin(w * x) + 0.15 * std::sin(2.0 * w * x + 0.5);
}

/// Velocity-dependent offset [N]: smooth Coulomb-like + viscous friction and a bias (the mean
/// that eq. 14 removes).
inline double Offset(double xdot) { return 0.3 * std::tanh(xdot / 0.1) + 0.5 * xdot + 1.0; }

/// Noise-free disturbance d(x, ẋ).
inline double TrueDisturbance(double x, double xdot, double period = kPolePitch) {
  return Cogging(x, period) * (1.0 + 0.2 * xdot / 0.5) + Offset(xdot);
}

/// The ten scan velocities 0.05, 0.10, …, 0.50 m/s.
inline std::vector<double> ScanVelocities() {
  std::vector<double> v;
  for (int i = 1; i <= 10; ++i) v.push_back(0.05 * i);
  return v;
}

/// `per_velocity` samples per scan velocity, positions uniform in [x_lo, x_hi] (a downsampled
/// constant-velocity log), Gaussian noise of standard deviation `noise_std`.
inline DisturbanceSamples ConstantVelocityScans(double x_lo, double x_hi, int per_velocity,
                                                double noise_std, std::uint64_t seed,
                                                double period = kPolePitch) {
  const std::vector<double> velocities = ScanVelocities();
  const Eigen::Index n = static_cast<Eigen::Index>(velocities.size()) * per_velocity;
  DisturbanceSamples s{Eigen::VectorXd(n), Eigen::VectorXd(n), Eigen::VectorXd(n)};
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> position(x_lo, x_hi);
  std::normal_distribution<double> noise(0.0, noise_std);
  Eigen::Index k = 0;
  for (double v : velocities) {
    for (int i = 0; i < per_velocity; ++i, ++k) {
      s.x(k) = position(rng);
      s.xdot(k) = v;
      s.d(k) = TrueDisturbance(s.x(k), v, period) + noise(rng);
    }
  }
  return s;
}

}  // namespace mb::testing

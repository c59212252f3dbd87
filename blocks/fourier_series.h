#pragma once
// Shared by the Fourier-series effect blocks (position_periodic, velocity_dependent_ripple, time_periodic):
//   y = Σ_{h=1..H} a_h cos(hθ) + b_h sin(hθ).

#include <cmath>
#include <stdexcept>
#include <string>

#include <Eigen/Core>

#include "engine/parameters.h"

namespace mb {

/// The coefficient vector parameter `name`: H entries, or [] for zeros.
/// @throws std::invalid_argument naming the parameter if it has another length.
inline Eigen::VectorXd FourierCoefficients(const Parameters& p, const std::string& name, int harmonics) {
  Eigen::VectorXd c = p.Vector(name);
  if (c.size() == 0) return Eigen::VectorXd::Zero(harmonics);
  if (c.size() != harmonics) {
    throw std::invalid_argument(name + " has " + std::to_string(c.size()) + " entries; give one per harmonic (" +
                                std::to_string(harmonics) + ") or []");
  }
  return c;
}

/// Σ_h a_h cos(hθ) + b_h sin(hθ), a and b of equal length H: one cos/sin pair, then the angle-addition
/// recurrence over h (rounding error grows like H·eps). Allocation-free.
inline double FourierSeries(const Eigen::VectorXd& a, const Eigen::VectorXd& b, double theta) noexcept {
  const double c1 = std::cos(theta), s1 = std::sin(theta);
  double ch = c1, sh = s1, y = 0.0;
  for (Eigen::Index h = 0; h < a.size(); ++h) {
    y += a(h) * ch + b(h) * sh;
    const double next_c = ch * c1 - sh * s1;
    sh = sh * c1 + ch * s1;
    ch = next_c;
  }
  return y;
}

}  // namespace mb

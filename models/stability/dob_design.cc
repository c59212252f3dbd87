#include "models/stability/dob_design.h"

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <string>

namespace mb {

namespace {

void CheckCutoff(double cutoff_hz, const char* what) {
  if (!(cutoff_hz > 0.0) || !std::isfinite(cutoff_hz)) {
    throw std::invalid_argument(std::string(what) + ": cutoff_hz must be a positive frequency in Hz, got " +
                                std::to_string(cutoff_hz));
  }
}

// (s + ω)^n in descending powers (binomial coefficients).
Eigen::VectorXd BinomialPolynomial(double omega, int n) {
  Eigen::VectorXd p = Eigen::VectorXd::Ones(1);
  for (int k = 0; k < n; ++k) {
    Eigen::VectorXd q = Eigen::VectorXd::Zero(p.size() + 1);
    q.head(p.size()) += p;
    q.tail(p.size()) += omega * p;
    p = q;
  }
  return p;
}

}  // namespace

ContinuousTf BinomialLowPass(double cutoff_hz, int order) {
  CheckCutoff(cutoff_hz, "binomial low-pass");
  if (order < 1 || order > 8) {
    throw std::invalid_argument("binomial low-pass: the order (relative degree) must be 1…8, got " +
                                std::to_string(order));
  }
  const double w = 2.0 * std::numbers::pi * cutoff_hz;
  return {Eigen::VectorXd::Constant(1, std::pow(w, order)), BinomialPolynomial(w, order)};
}

ContinuousTf QNominalInverse(double cutoff_hz, int relative_degree, double nominal_mass, double nominal_damping) {
  if (relative_degree < 2) {
    throw std::invalid_argument("Q∘P_n⁻¹: relative_degree must be ≥ 2 (the relative degree of P_n) for a proper "
                                "filter, got " + std::to_string(relative_degree));
  }
  if (!(nominal_mass > 0.0) || !(nominal_damping >= 0.0)) {
    throw std::invalid_argument("Q∘P_n⁻¹: nominal_mass must be > 0 kg and nominal_damping ≥ 0 N·s/m");
  }
  ContinuousTf q = BinomialLowPass(cutoff_hz, relative_degree);
  const double gain = q.num(0);
  q.num = Eigen::Vector3d(gain * nominal_mass, gain * nominal_damping, 0.0);
  return q;
}

ContinuousTf RigidBodyPlant(double mass, double damping) {
  if (!(mass > 0.0) || !(damping >= 0.0)) {
    throw std::invalid_argument("rigid body: mass must be > 0 kg and damping ≥ 0 N·s/m");
  }
  return {Eigen::VectorXd::Ones(1), Eigen::Vector3d(mass, damping, 0.0)};
}

DiscreteTf VelocityEstimatorFilter(double cutoff_hz, double sample_time) {
  CheckCutoff(cutoff_hz, "velocity estimator");
  if (!(sample_time > 0.0)) throw std::invalid_argument("velocity estimator: the sample time must be > 0 s");
  const double a = std::exp(-2.0 * std::numbers::pi * cutoff_hz * sample_time);
  const double g = (1.0 - a) / sample_time;
  return {Eigen::Vector2d(g, -g), Eigen::Vector2d(1.0, -a), sample_time};
}

ContinuousTf VelocityEstimatorFilterContinuous(double cutoff_hz) {
  CheckCutoff(cutoff_hz, "velocity estimator");
  const double w = 2.0 * std::numbers::pi * cutoff_hz;
  return {Eigen::Vector2d(w, 0.0), Eigen::Vector2d(1.0, w)};
}

DiscreteTf PdFilter(double kp, double kd, double derivative_cutoff_hz, double sample_time) {
  if (!(kp >= 0.0) || !(kd >= 0.0)) throw std::invalid_argument("PD: kp and kd must be ≥ 0");
  DiscreteTf f = VelocityEstimatorFilter(derivative_cutoff_hz, sample_time);
  // K_p (1 − a z⁻¹)/(1 − a z⁻¹) + K_d F(z).
  f.b = kd * f.b + kp * f.a;
  return f;
}

ContinuousTf PdFilterContinuous(double kp, double kd, double derivative_cutoff_hz) {
  if (!(kp >= 0.0) || !(kd >= 0.0)) throw std::invalid_argument("PD: kp and kd must be ≥ 0");
  const ContinuousTf f = VelocityEstimatorFilterContinuous(derivative_cutoff_hz);
  const double w = f.den(1);
  return {Eigen::Vector2d(kp + kd * w, kp * w), f.den};
}

}  // namespace mb

#include "models/diagnosis/quantization_floor.h"

#include <algorithm>
#include <cmath>
#include <vector>

#include <Eigen/Dense>

#include "models/diagnosis/signal_processing.h"

namespace mb {

double QuantizationStep(const Eigen::Ref<const Eigen::VectorXd>& signal) {
  std::vector<double> values(signal.data(), signal.data() + signal.size());
  std::sort(values.begin(), values.end());
  values.erase(std::unique(values.begin(), values.end()), values.end());
  double step = 0.0;
  for (std::size_t i = 1; i < values.size(); ++i) {
    const double gap = values[i] - values[i - 1];
    if (step == 0.0 || gap < step) step = gap;
  }
  return step;
}

namespace {

// The quantization noise of the motion derived from a smooth position put on the lattice of step q at `offsets`
// offsets q·(k + ½)/offsets: visit(δv, δa) for each, the differences from the smooth position's own derivatives (both
// by DeriveMotion at cutoff_hz).
template <class Visit>
void ForEachRequantization(const Eigen::VectorXd& time, const Eigen::VectorXd& smooth_position, double q,
                           double cutoff_hz, int offsets, Visit visit) {
  const MotionDerivatives smooth = DeriveMotion(time, smooth_position, cutoff_hz);
  for (int k = 0; k < offsets; ++k) {
    const double offset = q * (k + 0.5) / offsets;
    const Eigen::VectorXd lattice = ((smooth_position.array() + offset) / q).floor() * q - offset;
    const MotionDerivatives quantized = DeriveMotion(time, lattice, cutoff_hz);
    visit(quantized.velocity - smooth.velocity, quantized.acceleration - smooth.acceleration);
  }
}

double Rms(const Eigen::VectorXd& x) { return std::sqrt(x.squaredNorm() / static_cast<double>(x.size())); }

}  // namespace

QuantizationFloor EstimateQuantizationFloor(const DiagnosisSignals& signals, double cutoff_hz) {
  QuantizationFloor out;
  const Eigen::Index n = signals.size();
  if (!(cutoff_hz > 0.0) || signals.model_output.size() != n || n < 8) return out;
  out.step = QuantizationStep(signals.position);
  if (!(out.step > 0.0)) return out;
  // The model's sensitivities: ŷ regressed on the motion (a rigid body's mass, its viscous damping, a Coulomb level and
  // an offset, so that the friction law does not bend the other two).
  Eigen::MatrixXd x(n, 4);
  x.col(0) = signals.acceleration;
  x.col(1) = signals.velocity;
  x.col(2) = signals.velocity.array().sign().matrix();
  x.col(3).setOnes();
  const Eigen::VectorXd beta = x.colPivHouseholderQr().solve(signals.model_output);
  out.mass = beta(0);
  out.damping = beta(1);
  // The smooth motion: the logged position low-passed, differentiated as the log's was.
  const Eigen::VectorXd position = DeriveMotion(signals.time, signals.position, cutoff_hz).position;
  constexpr int kOffsets = 4;
  double sum = 0.0;
  ForEachRequantization(signals.time, position, out.step, cutoff_hz, kOffsets,
                        [&](const Eigen::VectorXd& dv, const Eigen::VectorXd& da) {
                          sum += (out.mass * da + out.damping * dv).squaredNorm() / static_cast<double>(n);
                        });
  out.rms = std::sqrt(sum / kOffsets);
  return out;
}

double QuantizationShareOfAcceleration(const Eigen::VectorXd& time, const Eigen::VectorXd& position, double cutoff_hz) {
  const double q = QuantizationStep(position);
  if (!(q > 0.0) || position.size() < 8) return 0.0;
  const MotionDerivatives logged = DeriveMotion(time, position, cutoff_hz);
  const double signal = Rms(logged.acceleration);
  if (!(signal > 0.0)) return 0.0;
  constexpr int kOffsets = 2;
  double sum = 0.0;
  ForEachRequantization(time, logged.position, q, cutoff_hz, kOffsets,
                        [&](const Eigen::VectorXd&, const Eigen::VectorXd& da) { sum += std::pow(Rms(da), 2); });
  return std::sqrt(sum / kOffsets) / signal;
}

double QuantizationLimitedCutoff(const Eigen::VectorXd& time, const Eigen::VectorXd& position, double cutoff_hz,
                                 double* share) {
  double f = cutoff_hz;
  for (int k = 0;; ++k) {
    f = cutoff_hz * std::pow(2.0, -0.5 * k);
    const double rho = QuantizationShareOfAcceleration(time, position, f);
    if (share != nullptr) *share = rho;
    if (rho <= kMaxQuantizationShare || k == kCutoffHalvings * 2) return f;
  }
}

void AddQuantizationFloor(const DiagnosisSignals& signals, double cutoff_hz, NoiseFloor* floor) {
  const QuantizationFloor q = EstimateQuantizationFloor(signals, cutoff_hz);
  floor->position_step = q.step;
  floor->quantization_rms = q.rms;
  floor->rms = std::hypot(floor->white_rms, q.rms);
}

}  // namespace mb

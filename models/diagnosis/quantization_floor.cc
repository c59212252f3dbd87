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
  // The smooth motion: the logged position low-passed, and its derivatives as the log's were taken.
  const Eigen::VectorXd position = DeriveMotion(signals.time, signals.position, cutoff_hz).position;
  const MotionDerivatives smooth = DeriveMotion(signals.time, position, cutoff_hz);
  const double q = out.step;
  constexpr int kOffsets = 4;
  double sum = 0.0;
  for (int k = 0; k < kOffsets; ++k) {
    const double offset = q * (k + 0.5) / kOffsets;
    const Eigen::VectorXd lattice = ((position.array() + offset) / q).floor() * q - offset;
    const MotionDerivatives quantized = DeriveMotion(signals.time, lattice, cutoff_hz);
    const Eigen::VectorXd part = out.mass * (quantized.acceleration - smooth.acceleration) +
                                 out.damping * (quantized.velocity - smooth.velocity);
    sum += part.squaredNorm() / static_cast<double>(n);
  }
  out.rms = std::sqrt(sum / kOffsets);
  return out;
}

void AddQuantizationFloor(const DiagnosisSignals& signals, double cutoff_hz, NoiseFloor* floor) {
  const QuantizationFloor q = EstimateQuantizationFloor(signals, cutoff_hz);
  floor->position_step = q.step;
  floor->quantization_rms = q.rms;
  floor->rms = std::hypot(floor->white_rms, q.rms);
}

}  // namespace mb

#include "models/diagnosis/quantization_floor.h"

#include <cmath>
#include <numbers>
#include <random>

#include <gtest/gtest.h>

#include "models/diagnosis/signal_processing.h"

namespace mb {
namespace {

TEST(QuantizationStep, IsTheLatticeStepOfAnEncoderAndNegligibleForAContinuousSignal) {
  constexpr double kStep = 2.0 * std::numbers::pi / 65536.0;
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> uniform(-1.0, 1.0);
  Eigen::VectorXd counts(2000), continuous(2000);
  for (Eigen::Index i = 0; i < counts.size(); ++i) {
    counts(i) = std::floor((0.3 + 0.5 * std::sin(0.01 * static_cast<double>(i))) / kStep) * kStep;
    continuous(i) = uniform(rng);
  }
  EXPECT_NEAR(QuantizationStep(counts), kStep, 1e-9 * kStep);
  EXPECT_LT(QuantizationStep(continuous), 1e-4);  // 2000 uniform values on [−1, 1]: gaps of order 1e-6
  EXPECT_EQ(QuantizationStep(Eigen::VectorXd::Constant(10, 0.25)), 0.0);
}

// A rotary axis with a 2¹⁶-count encoder at 1 kHz, moved smoothly; the model a rigid body (J·a + B·v). The truth is the
// model on the encoder's motion minus the model on the true motion, both differentiated as a log is.
struct QuantizedRecord {
  DiagnosisSignals signals;
  double truth_rms = 0.0;
};

QuantizedRecord MakeRecord(double step) {
  constexpr double kRate = 1000.0, kCutoff = 100.0, kInertia = 0.05, kDamping = 0.02;
  const Eigen::Index n = 8000;
  Eigen::VectorXd time(n), truth(n), counts(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    const double t = static_cast<double>(i) / kRate;
    time(i) = t;
    truth(i) = 0.8 * std::sin(2.0 * std::numbers::pi * 0.7 * t) + 0.3 * std::sin(2.0 * std::numbers::pi * 1.9 * t + 1.0);
    counts(i) = std::floor(truth(i) / step) * step;
  }
  const MotionDerivatives measured = DeriveMotion(time, counts, kCutoff);
  const MotionDerivatives exact = DeriveMotion(time, truth, kCutoff);
  QuantizedRecord r;
  r.signals.time = time;
  r.signals.position = counts;
  r.signals.velocity = measured.velocity;
  r.signals.acceleration = measured.acceleration;
  r.signals.model_output = kInertia * measured.acceleration + kDamping * measured.velocity;
  r.signals.residual = Eigen::VectorXd::Zero(n);
  const Eigen::VectorXd error = r.signals.model_output - (kInertia * exact.acceleration + kDamping * exact.velocity);
  r.truth_rms = std::sqrt(error.squaredNorm() / static_cast<double>(n));
  return r;
}

TEST(EstimateQuantizationFloor, MatchesWhatTheEncoderPutsIntoTheModelsOutput) {
  const QuantizedRecord coarse = MakeRecord(2.0 * std::numbers::pi / 65536.0);
  const QuantizationFloor q = EstimateQuantizationFloor(coarse.signals, 100.0);
  EXPECT_NEAR(q.step, 2.0 * std::numbers::pi / 65536.0, 1e-12);
  EXPECT_NEAR(q.mass, 0.05, 0.005);
  ASSERT_GT(coarse.truth_rms, 0.0);
  EXPECT_GT(q.rms, 0.7 * coarse.truth_rms);
  EXPECT_LT(q.rms, 1.3 * coarse.truth_rms);

  // Sixteen times finer: the part falls with the step.
  const QuantizedRecord fine = MakeRecord(2.0 * std::numbers::pi / (16.0 * 65536.0));
  const QuantizationFloor f = EstimateQuantizationFloor(fine.signals, 100.0);
  EXPECT_LT(f.rms, 0.2 * q.rms);
  EXPECT_GT(f.rms, 0.7 * fine.truth_rms);
  EXPECT_LT(f.rms, 1.3 * fine.truth_rms);

  // Simulation mode (no parallel filter): the position is compared itself, nothing is added.
  EXPECT_EQ(EstimateQuantizationFloor(coarse.signals, 0.0).rms, 0.0);
}

TEST(AddQuantizationFloor, AddsThePartsInQuadrature) {
  const QuantizedRecord coarse = MakeRecord(2.0 * std::numbers::pi / 65536.0);
  NoiseFloor floor;
  floor.rms = floor.white_rms = 0.001;
  AddQuantizationFloor(coarse.signals, 100.0, &floor);
  EXPECT_GT(floor.quantization_rms, 0.0);
  EXPECT_NEAR(floor.rms, std::hypot(0.001, floor.quantization_rms), 1e-15);
  EXPECT_GT(floor.position_step, 0.0);
}

// The share falls as the cut-off comes down (the quantization's acceleration grows as f_c^2.5, the motion's does not
// above its band), and the limited cut-off is the highest of the grid where it is at most a tenth.
TEST(QuantizationLimitedCutoff, ComesDownToWhereTheMotionDominatesTheEncoder) {
  const QuantizedRecord coarse = MakeRecord(2.0 * std::numbers::pi / 4096.0);  // 12 bits per revolution: coarse
  const Eigen::VectorXd& t = coarse.signals.time;
  const Eigen::VectorXd& x = coarse.signals.position;
  const double at_100 = QuantizationShareOfAcceleration(t, x, 100.0), at_25 = QuantizationShareOfAcceleration(t, x, 25.0);
  EXPECT_GT(at_100, kMaxQuantizationShare);
  EXPECT_LT(at_25, at_100);
  double share = 0.0;
  const double cutoff = QuantizationLimitedCutoff(t, x, 100.0, &share);
  EXPECT_LT(cutoff, 100.0);
  EXPECT_LE(share, kMaxQuantizationShare);
  EXPECT_GT(QuantizationShareOfAcceleration(t, x, cutoff * std::sqrt(2.0)), kMaxQuantizationShare)
      << "the next cut-off up on the grid must fail, else it would have been chosen";

  const QuantizedRecord fine = MakeRecord(2.0 * std::numbers::pi / std::pow(2.0, 24));
  EXPECT_EQ(QuantizationLimitedCutoff(fine.signals.time, fine.signals.position, 100.0), 100.0);
}

}  // namespace
}  // namespace mb

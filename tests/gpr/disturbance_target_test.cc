// The smoothed inverse-model disturbance estimate (models/gpr/disturbance_target.h): no phase lag where the DOB's
// Q-filter lags, the scans of a table estimated separately, errors that say what to fix.
#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "models/gpr/disturbance_target.h"
#include "models/stability/dob_design.h"
#include "tests/error_message.h"

namespace mb {
namespace {

using testing::ErrorOf;
constexpr double kMass = 0.2621, kDamping = 3.0, kTs = 1e-3;
constexpr double kF = 15.6;  // [Hz], the twin's cogging fundamental at 350 mm/s

// A stroke at 0.35 m/s with a 15.6 Hz, 0.5 N disturbance d = 0.5 sin(ωt + φ) that the force does not cancel: the
// position x(t) = v t + a sin(ωt) is analytic, and u = M_n ẍ + B_n ẋ − d is sampled (not held) at t_k.
struct Stroke {
  Eigen::VectorXd t, x, u, d;
};
Stroke MakeStroke(int n, double phase) {
  Stroke s{Eigen::VectorXd(n), Eigen::VectorXd(n), Eigen::VectorXd(n), Eigen::VectorXd(n)};
  const double w = 2.0 * std::numbers::pi * kF, a = 2e-6;
  for (int k = 0; k < n; ++k) {
    const double t = k * kTs;
    s.t[k] = t;
    s.x[k] = 0.35 * t + a * std::sin(w * t);
    s.d[k] = 0.5 * std::sin(w * t + phase);
    s.u[k] = kMass * (-a * w * w * std::sin(w * t)) + kDamping * (0.35 + a * w * std::cos(w * t)) - s.d[k];
  }
  return s;
}

// Phase [rad] of y relative to the sinusoid at kF with phase `phase`, by least squares over the middle half.
double PhaseError(const Eigen::VectorXd& t, const Eigen::VectorXd& y, double phase) {
  double sc = 0.0, ss = 0.0;
  const Eigen::Index n = y.size();
  const double w = 2.0 * std::numbers::pi * kF;
  for (Eigen::Index k = n / 4; k < 3 * n / 4; ++k) {
    ss += (y[k] - y.segment(n / 4, n / 2).mean()) * std::sin(w * t[k] + phase);
    sc += (y[k] - y.segment(n / 4, n / 2).mean()) * std::cos(w * t[k] + phase);
  }
  return std::atan2(sc, ss);
}

// The DOB of eq. 51 on the same samples: Q∘P_n⁻¹{x} (Tustin) − Q{u} (ZOH), as blocks/dob.cc.
Eigen::VectorXd DobEstimate(const Stroke& s) {
  const DiscreteTf qp = Discretize(QNominalInverse(30.0, 2, kMass, kDamping), kTs, Discretization::kTustin);
  const DiscreteTf q = Discretize(BinomialLowPass(30.0, 2), kTs, Discretization::kZeroOrderHold);
  std::vector<double> sqp(static_cast<std::size_t>(qp.order()), 0.0), sq(static_cast<std::size_t>(q.order()), 0.0);
  FilterSteadyState(qp, s.x[0], sqp.data());
  FilterSteadyState(q, s.u[0], sq.data());
  Eigen::VectorXd d(s.t.size());
  for (Eigen::Index k = 0; k < s.t.size(); ++k) {
    d[k] = FilterOutput(qp, s.x[k], sqp.data()) - FilterOutput(q, 0.0, sq.data());
    FilterUpdate(qp, s.x[k], sqp.data());
    FilterUpdate(q, s.u[k], sq.data());
  }
  return d;
}

TEST(SmoothedDisturbanceEstimateTest, HasNoPhaseLagWhereTheDobLags) {
  const double phase = 0.7;
  const Stroke s = MakeStroke(2000, phase);
  SmoothedDisturbanceOptions o;
  o.nominal_mass = kMass;
  o.nominal_damping = kDamping;
  o.force_held = false;
  const Eigen::VectorXd smoothed = SmoothedDisturbanceEstimate(s.t, s.x, s.u, o);
  const double smoothed_error = PhaseError(s.t, smoothed, phase);
  const double dob_error = PhaseError(s.t, DobEstimate(s), phase);
  // Q = ω²/(s + ω)² at 30 Hz lags by 2·atan(15.6/30) = 55° at 15.6 Hz (plus the sample delay of Q{u}).
  EXPECT_LT(dob_error, -50.0 * std::numbers::pi / 180.0);
  EXPECT_LT(std::abs(smoothed_error), 0.5 * std::numbers::pi / 180.0);
  // The amplitude: |H|² of the 200 Hz zero-phase Butterworth and the [1 2 1]/4 kernel of the two differences.
  const Eigen::Index n = s.t.size();
  const double rms = std::sqrt(smoothed.segment(n / 4, n / 2).array().square().mean());
  EXPECT_NEAR(rms, 0.5 / std::sqrt(2.0), 0.02);
}

TEST(SmoothedDisturbanceEstimateTest, EstimatesEachScanOfATableSeparately) {
  const Stroke s = MakeStroke(400, 0.0);
  SmoothedDisturbanceOptions o;
  o.nominal_mass = kMass;
  o.nominal_damping = kDamping;
  const Eigen::VectorXd one = SmoothedDisturbanceEstimate(s.t, s.x, s.u, o);
  // Two scans one after another, each restarting at t = 0, the second shifted in position.
  Eigen::VectorXd t(800), x(800), u(800);
  t << s.t, s.t;
  x << s.x, s.x.array() + 0.1;
  u << s.u, s.u;
  Table table({"time_s", "x", "u"}, {t, x, u}, "two_scans.csv");
  AddSmoothedDisturbanceColumn(table, "time_s", "x", "u", o, "d");
  const Eigen::VectorXd& d = table.column("d");
  EXPECT_LT((d.head(400) - one).cwiseAbs().maxCoeff(), 1e-9);
  EXPECT_LT((d.tail(400) - one).cwiseAbs().maxCoeff(), 1e-6);
}

TEST(SmoothedDisturbanceEstimateTest, Errors) {
  const Stroke s = MakeStroke(10, 0.0);
  SmoothedDisturbanceOptions o;
  o.nominal_mass = kMass;
  EXPECT_EQ(ErrorOf([&] { SmoothedDisturbanceEstimate(s.t, s.x, s.u.head(9), o); }),
            "smoothed disturbance estimate: time, position and force must have the same length, got 10, 10 and 9 "
            "samples");
  EXPECT_EQ(ErrorOf([&] { SmoothedDisturbanceEstimate(s.t.head(2), s.x.head(2), s.u.head(2), o); }),
            "smoothed disturbance estimate: needs at least 3 samples, got 2");
  Eigen::VectorXd t = s.t;
  t[5] = t[4];
  EXPECT_EQ(ErrorOf([&] { SmoothedDisturbanceEstimate(t, s.x, s.u, o); }),
            "smoothed disturbance estimate: time must increase, but t[5] = 0.004 s follows t[4] = 0.004 s (estimate "
            "each scan separately)");
  SmoothedDisturbanceOptions bad = o;
  bad.nominal_mass = 0.0;
  EXPECT_EQ(ErrorOf([&] { SmoothedDisturbanceEstimate(s.t, s.x, s.u, bad); }),
            "smoothed disturbance estimate: nominal mass must be positive and finite [kg], got 0");
  bad = o;
  bad.nominal_damping = -1.0;
  EXPECT_EQ(ErrorOf([&] { SmoothedDisturbanceEstimate(s.t, s.x, s.u, bad); }),
            "smoothed disturbance estimate: nominal damping must be >= 0 and finite [N*s/m], got -1");
  Table table({"time_s", "x", "u"}, {s.t, s.x, s.u}, "log.csv");
  EXPECT_EQ(ErrorOf([&] { AddSmoothedDisturbanceColumn(table, "time_s", "x", "u", o, "u"); }),
            "log.csv: already has a column 'u': rename it or choose another name");
  Eigen::VectorXd t2(5);
  t2 << 0.0, 0.001, 0.002, 0.0, 0.001;
  Table short_scan({"time_s", "x", "u"}, {t2, t2, t2}, "short.csv");
  EXPECT_EQ(ErrorOf([&] { AddSmoothedDisturbanceColumn(short_scan, "time_s", "x", "u", o, "d"); }),
            "short.csv: the scan at rows 4..5 (time_s) has fewer than 3 samples: the smoothed estimate needs a time "
            "series per scan");
}

}  // namespace
}  // namespace mb

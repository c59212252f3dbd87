#include "models/diagnosis/viscous_drift.h"

#include <cmath>
#include <limits>

namespace mb {
namespace {

constexpr int kStepGrid = 41;
constexpr double kStepTrim = 0.1;        // of the record's duration left out at each end of the step scan
constexpr int kWarmUpGrid = 25;          // log grid of T over [duration/kWarmUpRange, duration]
constexpr double kWarmUpRange = 100.0;
constexpr double kEdge = 1.1;            // T within this factor of the range's ends: at the edge

}  // namespace

Eigen::VectorXd RampedVelocity(const Eigen::VectorXd& time, const Eigen::VectorXd& velocity, double start,
                               double end) {
  return velocity.cwiseProduct(((time.array() - start) / (end - start)).min(1.0).max(0.0).matrix());
}

Eigen::VectorXd WarmingVelocity(const Eigen::VectorXd& time, const Eigen::VectorXd& velocity, double start,
                                double time_constant) {
  const Eigen::ArrayXd elapsed = (time.array() - start).max(0.0);
  return velocity.cwiseProduct((1.0 - (-elapsed / time_constant).exp()).matrix());
}

ViscousDriftScan ScanViscousDrift(const ProposalContext& c) {
  const DiagnosisSignals& s = c.signals();
  constexpr double kInf = std::numeric_limits<double>::infinity();
  ViscousDriftScan scan{.ramp_sse = kInf, .step_sse = kInf, .warm_up_sse = kInf};
  if (c.size() < 2 || !(s.velocity.cwiseAbs().maxCoeff() > 0.0)) return scan;
  scan.start = s.time(0);
  scan.end = s.time(c.size() - 1);
  const double duration = scan.end - scan.start;
  if (!(duration > 0.0)) return scan;
  const Eigen::MatrixXd base = c.BaseWithConstant();  // JointFitResidual keeps a reference
  const JointFitResidual fit(base, c.residual(), c.loop());
  scan.ramp_sse = fit(RampedVelocity(s.time, s.velocity, scan.start, scan.end));
  for (int i = 0; i < kStepGrid; ++i) {
    const double t = scan.start + duration * (kStepTrim + (1.0 - 2.0 * kStepTrim) * i / (kStepGrid - 1));
    const double e = fit((s.time.array() >= t).select(s.velocity, 0.0));
    if (e < scan.step_sse) { scan.step_sse = e; scan.step_time = t; }
  }
  const double lo = duration / kWarmUpRange, hi = duration;
  const auto warm_up_sse = [&](double time_constant) {  // thread-safe: fit is const, the column its own
    return fit(WarmingVelocity(s.time, s.velocity, scan.start, time_constant));
  };
  scan.time_constant = MinimiseOnLogGrid(lo, hi, kWarmUpGrid, 20, warm_up_sse, /*parallel_grid=*/true);
  scan.warm_up_sse = warm_up_sse(scan.time_constant);
  scan.warm_up_inside = scan.time_constant > kEdge * lo && scan.time_constant < hi / kEdge;
  return scan;
}

}  // namespace mb

// time_delay: the measurement lags the model by a pure delay d (measured = ŷ(t − d)). Regressor ŷ(t − d) − ŷ(t)
// (linear interpolation; ≈ −d·dŷ/dt for small d) {delay d [s]}; it is the error itself, so it must enter with a
// coefficient near 1. Proposal: a first guess from the fit of r on dŷ/dt, refined by a scan and a golden-section
// search of the joint fit with the base. Block: transport_delay "delay" before the output, its delay free.
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <Eigen/Dense>
#include <fmt/format.h>

#include "models/diagnosis/effect_proposal.h"
#include "models/diagnosis/effect_registry.h"
#include "models/diagnosis/effect_regressors.h"
#include "models/diagnosis/signal_processing.h"

namespace mb {
namespace {

constexpr const char* kName = "time_delay";

// ŷ(t − d) by linear interpolation on the time grid, held constant beyond the ends.
Eigen::VectorXd Shifted(const Eigen::VectorXd& t, const Eigen::VectorXd& y, double delay) {
  const Eigen::Index n = t.size();
  Eigen::VectorXd out(n);
  Eigen::Index j = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double tq = t(i) - delay;
    if (tq <= t(0)) { out(i) = y(0); continue; }
    if (tq >= t(n - 1)) { out(i) = y(n - 1); continue; }
    j = std::clamp<Eigen::Index>(j, 0, n - 2);
    while (j > 0 && t(j) > tq) --j;
    while (j + 1 < n - 1 && t(j + 1) < tq) ++j;
    const double w = (tq - t(j)) / (t(j + 1) - t(j));
    out(i) = (1.0 - w) * y(j) + w * y(j + 1);
  }
  return out;
}

// The delay d: a first guess d0 = −c from the least-squares fit of r on [1, dŷ/dt] (without the base: the base's
// a, v columns would absorb part of dŷ/dt), then a log-grid scan of |d| over [|d0|/8, 8|d0|] and a golden-section
// refinement of the joint fit of r on [base, 1, ŷ(t − d) − ŷ(t)].
void Propose(ProposalContext& c) {
  const DiagnosisSignals& s = c.signals();
  const Eigen::Index n = c.size();
  if (s.model_output.size() != n) return;
  const Eigen::VectorXd& y = s.model_output;
  const Eigen::VectorXd& r = c.residual();
  const double ts = c.sample_period();
  const Eigen::MatrixXd base = c.BaseWithConstant();
  const Eigen::VectorXd dy = CentralDifference(s.time, y);
  Eigen::MatrixXd x(n, 2);
  x << Eigen::VectorXd::Ones(n), dy;
  const Eigen::Vector2d beta = x.colPivHouseholderQr().solve(r);
  const double d0 = -beta(1);
  if (!std::isfinite(d0) || !(std::abs(d0) > 1e-3 * ts)) return;
  const double sign = d0 > 0.0 ? 1.0 : -1.0;
  auto sse = [&](double magnitude) { return ResidualSumOfSquares(base, Shifted(s.time, y, sign * magnitude) - y, r); };
  constexpr int kGrid = 25;
  const double lo_grid = std::abs(d0) / 8.0, ratio = std::pow(64.0, 1.0 / (kGrid - 1));
  int best = 0;
  double best_sse = std::numeric_limits<double>::infinity();
  for (int i = 0; i < kGrid; ++i) {
    const double e = sse(lo_grid * std::pow(ratio, i));
    if (e < best_sse) { best_sse = e; best = i; }
  }
  double lo = lo_grid * std::pow(ratio, best - 1), hi = lo_grid * std::pow(ratio, best + 1);
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
  double e1 = sse(x1), e2 = sse(x2);
  for (int it = 0; it < 30 && hi - lo > 1e-4 * lo; ++it) {
    if (e1 < e2) {
      hi = x2; x2 = x1; e2 = e1; x1 = hi - g * (hi - lo); e1 = sse(x1);
    } else {
      lo = x1; x1 = x2; e1 = e2; x2 = lo + g * (hi - lo); e2 = sse(x2);
    }
  }
  // A delay far below the sample period is not resolved by the data: what it "explains" is a free multiple of
  // dŷ/dt (on EMPS, −0.04 ms at 1 ms sampling), not a lag.
  const double delay = sign * 0.5 * (lo + hi);
  if (std::abs(delay) >= c.options().min_delay_samples * ts) c.Propose(kName, {{"delay", delay}});
}

EffectType TimeDelay() {
  EffectType t;
  t.name = kName;
  t.catalogue_order = 110;
  t.physics = "the measurement lags the model by a pure delay; add a delay block (transport or sampling delay)";
  t.regressor_formula = "ŷ(t − d) − ŷ(t) (linear interpolation; ≈ −d·dŷ/dt for small d)";
  t.parameters = {{"delay", "s", "d: how long the measurement lags the model"}};
  t.traits.regressor_is_error = true;
  t.traits.regressor_in_output_band = true;
  t.traits.refined_parameter = "delay";
  t.traits.refinement_range = 4.0;
  t.regressors = [](const EffectInstance& e, const DiagnosisSignals& s) {
    const Eigen::VectorXd& y = NeedModelOutput(e, s);
    return SingleColumn(e.name, Shifted(s.time, y, RequiredParameter(e, "delay")) - y);
  };
  t.propose = Propose;
  return t;
}

}  // namespace
}  // namespace mb

MB_REGISTER_EFFECT(time_delay, mb::TimeDelay())

// quantization: the measured output is quantized with step q. Regressor q·round(ŷ/q) − ŷ {step q [unit of the
// output]}; it is the error itself, so it must enter with a coefficient near 1. Proposal: the measured output's
// (ŷ + r) smallest level difference when ≥ 95 % of its changes are multiples of it, else the strongest
// significant peak of the residual's periodogram against ŷ. Block: quantizer "output_quantizer" before the output;
// its step is not free (the least-squares cost is piecewise constant in it).
#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "models/diagnosis/effect_proposal.h"
#include "models/diagnosis/effect_registry.h"
#include "models/diagnosis/effect_regressors.h"

namespace mb {
namespace {

constexpr const char* kName = "quantization";

// The smallest step of the measured output when ≥ 95 % of its changes (at least 32) are integer multiples of it.
double StepOfLevels(const Eigen::VectorXd& measured) {
  std::vector<double> steps;
  for (Eigen::Index i = 1; i < measured.size(); ++i) {
    const double d = std::abs(measured(i) - measured(i - 1));
    if (d > 1e-12 * (1.0 + std::abs(measured(i)))) steps.push_back(d);
  }
  if (steps.size() < 32) return 0.0;
  const double q = *std::min_element(steps.begin(), steps.end());
  std::size_t on_grid = 0;
  for (double d : steps) on_grid += std::abs(d / q - std::round(d / q)) < 0.02 ? 1u : 0u;
  return static_cast<double>(on_grid) >= 0.95 * static_cast<double>(steps.size()) ? q : 0.0;
}

void Propose(ProposalContext& c) {
  const Eigen::Index n = c.size();
  if (c.signals().model_output.size() != n) return;
  const Eigen::VectorXd& y = c.signals().model_output;
  const Eigen::VectorXd& r = c.residual();
  const double q = StepOfLevels(y + r);
  if (q > 0.0) {
    c.Propose(kName, {{"step", q}});
    return;
  }
  // Not on levels (noise after the quantizer, or the output low-passed in parallel as `compare` does): the
  // quantization error q·round(ŷ/q) − ŷ is a sawtooth periodic in ŷ with period q, so the step is the strongest
  // significant independent peak of the residual's periodogram against ŷ (at least min_quantization_levels
  // periods in ŷ's range). Filtering in time smooths the sawtooth's corners where ŷ crosses levels fast but keeps
  // its period.
  const double y_span = y.maxCoeff() - y.minCoeff();
  if (!(y_span > 0.0)) return;
  PeriodogramOptions qo = c.options().output_periodogram;
  if (qo.max_period <= 0.0) qo.max_period = y_span / c.options().min_quantization_levels;
  try {
    const Periodogram pg = LombScarglePeriodogram(y, r, qo);
    for (const auto& peak : pg.peaks) {
      if (peak.harmonic_of >= 0) continue;
      if (peak.significant && peak.power >= c.options().min_quantization_power) c.Propose(kName, {{"step", peak.period}});
      break;
    }
  } catch (const std::invalid_argument&) {
    // ŷ too smooth or too short for the period range (min ≥ max): no quantization to see.
  }
}

EffectType Quantization() {
  EffectType t;
  t.name = kName;
  t.catalogue_order = 120;
  t.physics = "the measured output is quantized; model the sensor or converter resolution";
  t.regressor_formula = "q·round(ŷ/q) − ŷ";
  t.parameters = {{"step", "unit of the output", "q: the resolution of the sensor or converter"}};
  t.traits.regressor_is_error = true;
  t.regressors = [](const EffectInstance& e, const DiagnosisSignals& s) {
    const Eigen::VectorXd& y = NeedModelOutput(e, s);
    const double q = PositiveParameter(e, "step");
    return SingleColumn(e.name, y.unaryExpr([q](double v) { return q * std::round(v / q) - v; }));
  };
  t.propose = Propose;
  // The quantizer goes last, on the signal the output connector reads. Its step stays fixed (not free): the
  // least-squares cost is piecewise constant in q, so a Jacobian by finite differences carries no information about
  // it; the diagnosis finds q from the levels or the residual's periodicity in ŷ instead.
  return t;
}

}  // namespace
}  // namespace mb

MB_REGISTER_EFFECT(quantization, mb::Quantization())

// position_dependent_force: a smooth force of position — a spring, a cable carrier, a magnet's attraction, a
// hardening suspension (Duffing's cubic stiffness k₁(x − x₀) + k₃(x − x₀)³). Regressors ξ, ξ², ξ³ with
// ξ = (x − center)/half_range over the record's travel {center [m], half_range [m], degree (3)}. Proposed when the
// position moves over more than 100 of its lattice steps (QuantizationStep) and the residual holds no position period of 16 cycles or more
// with 2 % of its variance. Block: position_dependent_force "position_force" on the position
// input, its coefficients free.
#include <cmath>

#include <fmt/format.h>

#include "models/diagnosis/effect_proposal.h"
#include "models/diagnosis/effect_registry.h"
#include "models/diagnosis/effect_regressors.h"
#include "models/diagnosis/factors.h"
#include "models/diagnosis/quantization_floor.h"

namespace mb {
namespace {

constexpr const char* kName = "position_dependent_force";
constexpr int kDefaultDegree = 3;
// A ripple keeps the polynomial out (RippleASmoothFunctionWouldBlur: 16 cycles, 2 % of the variance): on EMPS the screw
// lead's 2.5 mm holds 8.3 % (4.3 % on the pulses record); on an electronic Duffing oscillator in volts a 0.5 % peak of
// 20 cycles (the cubic stiffness seen through the periodogram's window) kept the polynomial out while it was 97 % of
// the residual.

// The travel in steps of the position's lattice (an encoder's count, an ADC's least significant bit), at least: a
// record at rest spans a few counts of noise. Scale-free and independent of the sample rate — the median
// sample-to-sample step it replaced was a large part of the travel on a fast oscillation sampled at a few times its
// frequency (an electronic Duffing oscillator), which was skipped without a note.
constexpr double kMinSteps = 100.0;

int Degree(const EffectInstance& e) {
  const auto it = e.parameters.find("degree");
  if (it == e.parameters.end()) return kDefaultDegree;
  const double d = it->second;
  if (!(d >= 1.0 && d <= 9.0) || d != std::round(d)) {
    throw std::invalid_argument("effect 'position_dependent_force': parameter 'degree' must be an integer in 1..9");
  }
  return static_cast<int>(d);
}

EffectRegressors Columns(const EffectInstance& e, const DiagnosisSignals& s) {
  return PowerColumns(s.position, RequiredParameter(e, "center"), PositiveParameter(e, "half_range"), Degree(e),
                      e.name);
}

EffectType PositionDependentForce() {
  EffectType t;
  t.name = kName;
  t.catalogue_order = 65;
  t.multiplier = "one";  // the grammar's pair it is (factors.h)
  t.modulator = "position_smooth";
  t.physics = "a smooth force of position (spring, cable carrier, magnet attraction, hardening suspension); add a "
              "position_dependent_force block (polynomial in x)";
  t.regressor_formula = "ξ^j, ξ = (x − x₀)/h, j = 1..J";
  t.parameters = {{"center", "m", "x₀: the middle of the record's travel"},
                  {"half_range", "m", "h: half the record's travel"},
                  {"degree", "", "J, 3 when absent"}};
  t.regressors = Columns;
  t.propose = [](ProposalContext& c) {
    // Only when the residual holds no position period of 16 cycles or more in the travel: on EMPS (DATA_EMPS,
    // the rigid body) the polynomial takes 18.6 % of the held-out residual and the held-out ranking names it before the
    // screw lead's ripple (80 cycles). A "period" of a few cycles in the travel is what a smooth force of position looks
    // like to the periodogram (a hardening spring over 0.18 m: 18.7 mm, 9.6 cycles): it does not stop the polynomial.
    // The position must move over many of its own lattice steps (in the record's unit: metres, radians or volts
    // alike): a record at rest spans a few counts of noise.
    if (const double step = QuantizationStep(c.signals().position); !(c.position_span() > kMinSteps * step)) {
      c.Note(fmt::format("position_dependent_force not proposed: the position spans {:.3g} of its steps ({:.3g}), "
                         "fewer than {:g}: a record at rest, or one that moves too little to tell a force of the "
                         "position",
                         step > 0.0 ? c.position_span() / step : 0.0, step, kMinSteps));
      return;
    }
    if (const auto p = RippleASmoothFunctionWouldBlur(c)) {
      c.Note(fmt::format("position_dependent_force not proposed: the residual holds a position period of {:.3g} "
                         "cycles in the travel ({:.4g}, {:.1f} % of its variance), a ripple the polynomial would "
                         "only blur",
                         c.position_span() / p->period, p->period, 100.0 * p->power));
      return;
    }
    const Eigen::VectorXd& x = c.signals().position;
    c.Propose(kName, {{"center", 0.5 * (x.maxCoeff() + x.minCoeff())},
                      {"half_range", 0.5 * c.position_span()},
                      {"degree", kDefaultDegree}});
  };
  return t;
}

}  // namespace
}  // namespace mb

MB_REGISTER_EFFECT(position_dependent_force, mb::PositionDependentForce())

// mass_change: the moving mass changes during the record — a payload picked up or set down, a tool change. The
// residual is then structured in time, not in the state: after the change the model misses Δm·a. Regressor
// a·H(t − t_c) {change_time t_c [s]}, its coefficient Δm (the mass picked up, in the unit of the force per unit of
// acceleration): the grammar's pair a × step(t) under the catalogue's name. Proposal: the step modulator's own shape
// scan (factors.h, ModulatorRow::scan of "time_step": Andrews' sup-F scan of the joint fit over the break time in the
// middle 80 % of the record, then refined; the derived motion's edge transients left out, a note when the best break
// is at the scan's edge), so that this pair finds its time as every other step does; not proposed when a slow drift
// of the mass, a·(t − t₀)/T, fits better than a step (a note says so). Its significance is the forward selection's
// held-out test on contiguous blocks. Block: switched_gain "payload_change" on the acceleration input, its gain free
// (blocks/switched_gain.cc). Sources: Chow (1960), Econometrica 28(3); Andrews (1993), Econometrica 61(4);
// DIAGNOSIS.md, "Parameters that change".
#include <fmt/format.h>

#include "models/diagnosis/effect_proposal.h"
#include "models/diagnosis/effect_registry.h"
#include "models/diagnosis/effect_regressors.h"
#include "models/diagnosis/factors.h"

namespace mb {
namespace {

constexpr const char* kName = "mass_change";

Eigen::VectorXd Column(const DiagnosisSignals& s, double change_time) {
  return (s.time.array() >= change_time).select(s.acceleration, 0.0);
}

void Propose(ProposalContext& c) {
  const DiagnosisSignals& s = c.signals();
  if (!(s.acceleration.cwiseAbs().maxCoeff() > 0.0)) return;
  const std::vector<FactorParameters> found = FindModulator("time_step")->scan(c, s.acceleration, nullptr, kName);
  if (found.empty()) return;  // the scan said why
  const double change_time = found.front().at("change_time");
  const double t0 = s.time(0), duration = s.time(c.size() - 1) - t0;
  const Eigen::MatrixXd base = c.BaseWithConstant();
  const JointFitResidual fit(base, c.residual(), c.loop());
  const Eigen::VectorXd drift = s.acceleration.cwiseProduct(((s.time.array() - t0) / duration).matrix());
  if (fit(drift) <= fit(Column(s, change_time))) {
    c.Note(fmt::format("mass_change not proposed: a slow drift of the mass over the record fits the residual at least "
                       "as well as a step (best step at {:.3g} s): a drift (temperature, wear), not a payload change",
                       change_time));
    return;
  }
  c.Propose(kName, {{"change_time", change_time}});
}

EffectType MassChange() {
  EffectType t;
  t.name = kName;
  t.catalogue_order = 61;
  t.multiplier = "acceleration";  // the grammar's pair it is (factors.h)
  t.modulator = "time_step";
  t.physics = "the moving mass changes during the record (a payload picked up, a tool change): the mass steps at the "
              "change time; add a switched gain on the acceleration";
  t.regressor_formula = "a·H(t − t_c)";
  t.parameters = {{"change_time", "s", "t_c: when the mass changes"}};
  t.traits.coefficient_parameter = "change";  // Δm, the mass picked up (negative: set down)
  t.regressors = [](const EffectInstance& e, const DiagnosisSignals& s) {
    return SingleColumn(e.name, Column(s, RequiredParameter(e, "change_time")));
  };
  t.propose = Propose;
  return t;
}

}  // namespace
}  // namespace mb

MB_REGISTER_EFFECT(mass_change, mb::MassChange())

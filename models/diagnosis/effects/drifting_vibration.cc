// drifting_vibration: a vibration whose frequency drifts linearly in time (a pump or a fan speeding up, a neighbouring
// machine changing speed) — the grammar's pair one × time_chirp (models/diagnosis/time_chirp.h), written here so that
// it is proposed by default like time_periodic: f(t) = f₀ + ḟ·t, regressors cos kφ, sin kφ, φ = 2π(f₀t + ½ḟt²)
// {frequency_hz f₀ [Hz] at t = 0, drift_rate ḟ [Hz/s], harmonics K}. Proposal: the modulator's scan (ScanTimeChirp,
// the ridge of the residual's short-time spectrum, dechirping, the joint fit). Block: time_periodic with its
// frequency_rate, its frequency, rate and coefficients free.
#include "models/diagnosis/effect_proposal.h"
#include "models/diagnosis/effect_registry.h"
#include "models/diagnosis/effect_regressors.h"
#include "models/diagnosis/factors.h"
#include "models/diagnosis/time_chirp.h"

namespace mb {
namespace {

constexpr const char* kName = "drifting_vibration";

EffectType DriftingVibration() {
  const ModulatorRow& chirp = *FindModulator("time_chirp");
  EffectType t;
  t.name = kName;
  t.catalogue_order = 91;
  t.multiplier = "one";  // the grammar's pair it is (factors.h)
  t.modulator = chirp.id;
  t.physics = "a vibration whose frequency drifts in time (a pump or fan speeding up, a neighbouring machine changing "
              "speed); add a time_periodic block with its frequency_rate";
  t.regressor_formula = chirp.formula;
  t.parameters = chirp.parameters;
  t.traits.periodicity = Periodicity::kTime;
  t.regressors = [shape = chirp.shape](const EffectInstance& e, const DiagnosisSignals& s) {
    return shape(e.parameters, s, e.name, nullptr);
  };
  t.propose = [](ProposalContext& c) {
    const Eigen::VectorXd ones = Eigen::VectorXd::Ones(c.size());
    for (FactorParameters parameters : ScanTimeChirp(c, ones, kName)) c.Propose(kName, std::move(parameters));
  };
  return t;
}

}  // namespace
}  // namespace mb

MB_REGISTER_EFFECT(drifting_vibration, mb::DriftingVibration())

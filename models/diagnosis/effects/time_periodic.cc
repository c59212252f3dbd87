// time_periodic: a vibration periodic in time, independent of position. Regressors cos(2πkft), sin(2πkft),
// k = 1..K {frequency_hz f [Hz], harmonics K}. Proposal: the strongest peak of the residual's time periodogram
// that is not locked to the motion's own repetition (there, every state-dependent effect is time-periodic too).
// Block: time_periodic "vibration", its frequency and Fourier coefficients free.
#include <fmt/format.h>

#include "models/diagnosis/effect_proposal.h"
#include "models/diagnosis/effect_registry.h"
#include "models/diagnosis/effect_regressors.h"
#include "models/diagnosis/factors.h"

namespace mb {
namespace {

constexpr const char* kName = "time_periodic";

void Propose(ProposalContext& c) {
  const CandidateSearch& search = c.search();
  for (std::size_t i = 0; i < search.time_periodogram.peaks.size(); ++i) {
    const PeriodogramPeak& peak = search.time_periodogram.peaks[i];
    if (peak.harmonic_of >= 0) continue;
    const double f = 1.0 / peak.period;
    if (const int k = MotionHarmonic(c, f); k > 0) {
      c.Note(fmt::format(
          "the residual's time period {:.4g} s ({:.1f} % of its variance) repeats with the motion ({} × its "
          "frequency {:.4g} Hz): it depends on the motion state (x, v, a), not on time; not proposed as {}",
          peak.period, 100.0 * peak.power, k, search.motion_frequency_hz, kName));
      continue;
    }
    c.Propose(kName, {{"frequency_hz", f},
                      {"harmonics", HarmonicCount(search.time_periodogram, i, c.options().max_harmonics)}});
    break;
  }
}

EffectType TimePeriodic() {
  EffectType t;
  t.name = kName;
  t.catalogue_order = 90;
  t.multiplier = "one";  // the grammar's pair it is (factors.h)
  t.modulator = "time_periodic";
  t.physics = "a vibration periodic in time, independent of position (external vibration, ripple of a supply)";
  t.regressor_formula = "cos(2πkft), sin(2πkft), k = 1..K";
  t.parameters = {{"frequency_hz", "Hz", "f: the vibration's fundamental"}, {"harmonics", "", "K, 1 when absent"}};
  t.traits.periodicity = Periodicity::kTime;
  t.regressors = [](const EffectInstance& e, const DiagnosisSignals& s) {
    return PeriodicColumns(s.time, 1.0 / PositiveParameter(e, "frequency_hz"), HarmonicsParameter(e), e.name);
  };
  t.propose = Propose;
  // The frequency is free too: over a long record a small frequency error turns into a large phase error.
  return t;
}

}  // namespace
}  // namespace mb

MB_REGISTER_EFFECT(time_periodic, mb::TimePeriodic())

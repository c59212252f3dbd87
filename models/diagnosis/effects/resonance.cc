// resonance: a lightly damped structural mode excited by the drive. Regressors g and ġ/ω_r, g = the excitation
// (input u, else the acceleration a) through ω_r²/(s² + 2ζω_r s + ω_r²) (bilinear, pre-warped at f_r); with a: a
// load m on a spring–damper behind the motor adds m·g + 2ζm·ġ/ω_r to the force (two-mass model,
// blocks/flexible_load.h) {frequency_hz f_r [Hz], damping_ratio ζ}. Proposal: the most prominent peak of the
// residual's Welch spectrum, refined by golden-section searches of the joint fit with the base. Block:
// flexible_load on the acceleration input, its mass, frequency and damping free.
#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <utility>
#include <vector>

#include <fmt/format.h>

#include "models/diagnosis/effect_proposal.h"
#include "models/diagnosis/effect_registry.h"
#include "models/diagnosis/effect_regressors.h"
#include "models/diagnosis/signal_processing.h"

namespace mb {
namespace {

constexpr const char* kName = "resonance";
// A mode found by the scan (no prominent spectral peak) must be lightly damped: structural modes have ζ of a few per
// cent; the twin's closed loop with nothing missing gives a best scan at ζ = 0.15 that explains a broad shape of the
// spectrum (HiddenEffect.NothingMissingSaysSoAndInventsNothing).
constexpr double kMaxScannedDamping = 0.1;
constexpr double kTwoPi = 2.0 * std::numbers::pi;

// Resonant low-pass ω²/(s² + 2ζωs + ω²), bilinear transform pre-warped at ω, zero initial state.
Eigen::VectorXd ResonantFilter(const Eigen::VectorXd& u, double ts, double f_hz, double zeta) {
  const double w = kTwoPi * f_hz;
  const double k = w / std::tan(0.5 * w * ts);
  const double a0 = k * k + 2.0 * zeta * w * k + w * w;
  const double a1 = (2.0 * w * w - 2.0 * k * k) / a0, a2 = (k * k - 2.0 * zeta * w * k + w * w) / a0;
  const double b0 = w * w / a0, b1 = 2.0 * b0, b2 = b0;
  Eigen::VectorXd y(u.size());
  double z1 = 0.0, z2 = 0.0;
  for (Eigen::Index i = 0; i < u.size(); ++i) {
    const double out = b0 * u(i) + z1;
    z1 = b1 * u(i) - a1 * out + z2;
    z2 = b2 * u(i) - a2 * out;
    y(i) = out;
  }
  return y;
}

// The regressors: g = the excitation through ω²/(s² + 2ζωs + ω²) and ġ/ω (N × 2). The excitation is the input u
// when given, else the acceleration: with the encoder on the motor, a load on a spring–damper (two-mass model,
// blocks/flexible_load.h) adds m·(2ζωs + ω²)/(s² + 2ζωs + ω²)·a = m·g + 2ζm·ġ/ω to the force. (Not ŷ: the model
// force holds friction steps that the structure never feels as an acceleration.)
Eigen::MatrixXd ResonanceColumns(const DiagnosisSignals& s, double ts, double f_hz, double zeta) {
  const Eigen::VectorXd& u = s.input.size() ? s.input : s.acceleration;
  Eigen::MatrixXd columns(s.size(), 2);
  columns.col(0) = ResonantFilter(u.array() - u.mean(), ts, f_hz, zeta);
  columns.col(1) = CentralDifference(s.time, columns.col(0)) / (kTwoPi * f_hz);
  return columns;
}

// The most prominent local maximum of the spectrum: its density over the median density of the bins within
// ±50 % of its frequency (at least ±10 bins; the 2 bins either side, its own main lobe, left out). Local, because
// the residual is often low-passed (parallel filtering): against the whole spectrum's median, mostly stop band,
// any pass-band noise would be "prominent". Peaks below 4 frequency resolutions are drift, not a mode.
// Peaks above max_hz (> 0: the band limit of low-passed data, CatalogueOptions::band_limit_hz) are left out.
// Returns the bin (−1 if none) and its prominence.
std::pair<Eigen::Index, double> MostProminentPeak(const PowerSpectrum& psd, double max_hz) {
  const Eigen::Index m = psd.density.size();
  Eigen::Index k_best = -1;
  double best_prominence = 0.0;
  std::vector<double> window;
  for (Eigen::Index k = 4; k < m - 1; ++k) {
    if (!(psd.density(k) > psd.density(k - 1) && psd.density(k) >= psd.density(k + 1))) continue;
    if (max_hz > 0.0 && psd.frequency_hz(k) > max_hz) break;
    const Eigen::Index half = std::max<Eigen::Index>(k / 2, 10);
    window.clear();
    for (Eigen::Index j = std::max<Eigen::Index>(1, k - half); j <= std::min(m - 1, k + half); ++j) {
      if (std::abs(j - k) > 2) window.push_back(psd.density(j));
    }
    if (window.size() < 8) continue;
    const auto mid = window.begin() + static_cast<std::ptrdiff_t>(window.size() / 2);
    std::nth_element(window.begin(), mid, window.end());
    const double prominence = *mid > 0.0 ? psd.density(k) / *mid : 0.0;
    if (prominence > best_prominence) {
      best_prominence = prominence;
      k_best = k;
    }
  }
  return {k_best, best_prominence};
}

// The peak's frequency to a fraction of a Welch bin (parabolic interpolation of the log density around bin k).
double PeakFrequency(const PowerSpectrum& psd, Eigen::Index k) {
  const double l0 = std::log(psd.density(k - 1)), l1 = std::log(psd.density(k)), l2 = std::log(psd.density(k + 1));
  const double denom = l0 - 2.0 * l1 + l2;
  const double shift = denom < 0.0 ? std::clamp(0.5 * (l0 - l2) / denom, -0.5, 0.5) : 0.0;
  return psd.frequency_hz(k) + shift * (psd.frequency_hz(1) - psd.frequency_hz(0));
}

// From f (the peak's frequency, or the scan's), with a Welch bin of `bin` [Hz]:
// golden-section searches of the joint least-squares fit of r on [base, 1, g, ġ/ω_r] refine f_r (over f_0 ± 2
// bins), ζ (log scale, 0.002–0.3, from resonance_damping_ratio) and f_r again: a bin is ~1 Hz, a few per cent of
// a low mode, and the spectrum alone says little about ζ.
void ProposeAt(ProposalContext& c, double f, double bin, bool scanned = false) {
  const double ts = c.sample_period();
  double zeta = c.options().resonance_damping_ratio;
  if (f > 2.0 * bin && f + 2.0 * bin < 0.5 / ts) {
    const Eigen::MatrixXd base = c.BaseWithConstant();
    const DiagnosisSignals& s = c.signals();
    const Eigen::VectorXd& r = c.residual();
    const JointFitResidual joint_fit(base, r, c.loop());  // the base's Gram and moment once, not per trial
    auto sse_f = [&](double trial) { return joint_fit(ResonanceColumns(s, ts, trial, zeta)); };
    auto sse_log_zeta = [&](double log_zeta) { return joint_fit(ResonanceColumns(s, ts, f, std::exp(log_zeta))); };
    // (The scan refined f already: ζ alone, to 1 %, keeps the scan's cost within compare's budget.)
    if (!scanned) f = GoldenSectionMinimum(sse_f, f - 2.0 * bin, f + 2.0 * bin, 1e-5);
    zeta = std::exp(GoldenSectionMinimum(sse_log_zeta, std::log(0.002), std::log(0.3), scanned ? 1e-2 : 1e-3));
    f = GoldenSectionMinimum(sse_f, f - bin, f + bin, scanned ? 1e-4 : 1e-5);
  }
  if (scanned && zeta > kMaxScannedDamping) {  // the scan's best is a broad shape of the spectrum, not a mode
    c.Note(fmt::format("{} not proposed: the scan of the joint fit found {:.4g} Hz with damping ratio {:.2g} (> {}: "
                       "not a lightly damped mode)", kName, f, zeta, kMaxScannedDamping));
    return;
  }
  c.Propose(kName, {{"frequency_hz", f}, {"damping_ratio", zeta}});
}

void Propose(ProposalContext& c) {
  const PowerSpectrum psd =
      WelchPowerSpectrum(c.residual(), c.sample_period(), std::min(c.options().welch_segment, c.size()));
  const auto [k_best, prominence] = MostProminentPeak(psd, c.options().band_limit_hz);
  if (k_best <= 0) return;
  const double bin = psd.frequency_hz(1) - psd.frequency_hz(0);
  const double threshold = c.options().resonance_prominence;
  c.Note(fmt::format(
      "the residual spectrum's most prominent peak: {:.4g} Hz, {:.3g} × the median density around it ({}: a "
      "{} is proposed above {:.3g} ×)",
      psd.frequency_hz(k_best), prominence, prominence > threshold ? "proposed" : "not proposed", kName, threshold));
  if (prominence > threshold) {
    ProposeAt(c, PeakFrequency(psd, k_best), bin);
    return;
  }
  // A mode that the closed loop damps shows no prominent peak in the residual: scan the joint fit over 4 bins … half
  // the band limit (or an eighth of the sample rate) instead — near the parallel filter's cut-off the regressors are
  // distorted; a best fit with ζ > kMaxScannedDamping is a broad shape, not a mode; the ranking's significance test
  // judges the rest.
  const double ts = c.sample_period();
  const double hi = c.options().band_limit_hz > 0.0 ? 0.5 * c.options().band_limit_hz : 0.125 / ts;
  const double zeta = c.options().resonance_damping_ratio;
  const double f = ScanJointFit(c, 4.0 * bin, hi, 20,
                                [&](double trial) { return ResonanceColumns(c.signals(), ts, trial, zeta); });
  if (f > 0.0) ProposeAt(c, f, bin, true);
}

EffectType Resonance() {
  EffectType t;
  t.name = kName;
  t.catalogue_order = 100;
  t.physics = "a lightly damped structural mode excited by the drive; add a two-mass or resonance block";
  t.regressor_formula = "g and ġ/ω_r, g = the excitation (u, else a) through ω_r²/(s² + 2ζω_r s + ω_r²)";
  t.parameters = {{"frequency_hz", "Hz", "f_r: the mode's natural frequency"},
                  {"damping_ratio", "", "ζ: the mode's damping ratio"}};
  t.regressors = [](const EffectInstance& e, const DiagnosisSignals& s) {
    const double f = PositiveParameter(e, "frequency_hz");
    const double zeta = PositiveParameter(e, "damping_ratio");
    const double ts = MedianTimeStep(s.time);
    if (!(f < 0.5 / ts)) {
      throw std::invalid_argument(fmt::format(
          "effect '{}': frequency_hz = {} must be below the Nyquist frequency {} Hz", e.name, f, 0.5 / ts));
    }
    EffectRegressors out;
    out.columns = ResonanceColumns(s, ts, f, zeta);
    out.column_names = {e.name + ".response", e.name + ".rate"};
    return out;
  };
  t.propose = Propose;
  // The two-mass model seen from the motor (blocks/flexible_load.h): the regressors g and ġ/ω_r are its terms,
  // the coefficient of g its load mass. Mass, frequency and damping are refit: the frequency from the spectrum is
  // good to a fraction of a Welch bin, not of the mode's bandwidth.
  return t;
}

}  // namespace
}  // namespace mb

MB_REGISTER_EFFECT(resonance, mb::Resonance())

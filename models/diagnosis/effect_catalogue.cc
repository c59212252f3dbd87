#include "models/diagnosis/effect_catalogue.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include <Eigen/Dense>
#include <fmt/format.h>

#include "models/diagnosis/signal_processing.h"

namespace mb {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;

void CheckLength(const Eigen::VectorXd& v, Eigen::Index n, const char* name, bool optional) {
  if (optional && v.size() == 0) return;
  if (v.size() != n) {
    throw std::invalid_argument(fmt::format(
        "DiagnosisSignals: '{}' has {} samples but 'time' has {}; all signals must be equally long{}", name,
        v.size(), n, optional ? " (or empty when absent)" : ""));
  }
  if (!v.allFinite()) {
    Eigen::Index i = 0;
    while (i < v.size() && std::isfinite(v(i))) ++i;
    throw std::invalid_argument(
        fmt::format("DiagnosisSignals: '{}' holds NaN or Inf at sample {}; clean the data first", name, i));
  }
}

double Param(const EffectInstance& e, const char* key) {
  const auto it = e.parameters.find(key);
  if (it == e.parameters.end() || !std::isfinite(it->second)) {
    throw std::invalid_argument(fmt::format(
        "effect '{}': parameter '{}' is missing or not finite; set it (SI units)", e.name, key));
  }
  return it->second;
}

double PositiveParam(const EffectInstance& e, const char* key) {
  const double v = Param(e, key);
  if (!(v > 0.0)) {
    throw std::invalid_argument(fmt::format("effect '{}': parameter '{}' = {} must be positive", e.name, key, v));
  }
  return v;
}

int HarmonicsParam(const EffectInstance& e) {
  const auto it = e.parameters.find("harmonics");
  if (it == e.parameters.end()) return 1;
  const double h = it->second;
  if (!(h >= 1.0 && h <= 50.0) || h != std::round(h)) {
    throw std::invalid_argument(fmt::format(
        "effect '{}': parameter 'harmonics' = {} must be an integer in 1..50", e.name, h));
  }
  return static_cast<int>(h);
}

const Eigen::VectorXd& NeedModelOutput(const EffectInstance& e, const DiagnosisSignals& s) {
  if (s.model_output.size() == 0) {
    throw std::invalid_argument(fmt::format(
        "effect '{}' needs the model output ŷ (DiagnosisSignals::model_output), which is absent", e.name));
  }
  return s.model_output;
}

Eigen::VectorXd SignDeadBand(const Eigen::VectorXd& v, double dead_band) {
  return v.unaryExpr([dead_band](double x) { return std::abs(x) <= dead_band ? 0.0 : (x > 0.0 ? 1.0 : -1.0); });
}

// Columns cos(2πk·z/period), sin(2πk·z/period), k = 1..harmonics, optionally scaled by `scale`.
void FillPeriodic(const Eigen::VectorXd& z, double period, int harmonics, const std::string& prefix,
                  EffectRegressors* out, const Eigen::VectorXd* scale = nullptr) {
  const Eigen::Index n = z.size();
  out->columns.resize(n, 2 * harmonics);
  for (int k = 1; k <= harmonics; ++k) {
    for (Eigen::Index i = 0; i < n; ++i) {
      const double th = kTwoPi * static_cast<double>(k) * z(i) / period;
      const double g = scale ? (*scale)(i) : 1.0;
      out->columns(i, 2 * (k - 1)) = g * std::cos(th);
      out->columns(i, 2 * (k - 1) + 1) = g * std::sin(th);
    }
    out->column_names.push_back(fmt::format("{}.cos{}", prefix, k));
    out->column_names.push_back(fmt::format("{}.sin{}", prefix, k));
  }
}

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

// The resonance regressors: g = the excitation through ω²/(s² + 2ζωs + ω²) and ġ/ω (N × 2). The excitation is
// the input u when given, else the acceleration: with the encoder on the motor, a load on a spring–damper
// (two-mass model, blocks/flexible_load.h) adds m·(2ζωs + ω²)/(s² + 2ζωs + ω²)·a = m·g + 2ζm·ġ/ω to the force.
// (Not ŷ: the model force holds friction steps that the structure never feels as an acceleration.)
Eigen::MatrixXd ResonanceColumns(const DiagnosisSignals& s, double ts, double f_hz, double zeta) {
  const Eigen::VectorXd& u = s.input.size() ? s.input : s.acceleration;
  Eigen::MatrixXd columns(s.size(), 2);
  columns.col(0) = ResonantFilter(u.array() - u.mean(), ts, f_hz, zeta);
  columns.col(1) = CentralDifference(s.time, columns.col(0)) / (kTwoPi * f_hz);
  return columns;
}

// Golden-section search for the minimum of `cost` on [lo, hi] (assumed unimodal there), to a relative width of
// `tolerance`; returns the midpoint of the last bracket.
template <class Cost>
double GoldenSectionMinimum(const Cost& cost, double lo, double hi, double tolerance) {
  const double g = 0.5 * (std::sqrt(5.0) - 1.0);
  double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo);
  double e1 = cost(x1), e2 = cost(x2);
  for (int it = 0; it < 60 && hi - lo > tolerance * std::abs(lo + hi) * 0.5; ++it) {
    if (e1 < e2) {
      hi = x2; x2 = x1; e2 = e1; x1 = hi - g * (hi - lo); e1 = cost(x1);
    } else {
      lo = x1; x1 = x2; e1 = e2; x2 = lo + g * (hi - lo); e2 = cost(x2);
    }
  }
  return 0.5 * (lo + hi);
}

// Least-squares residual sum of squares of r on [base, extra] (normal equations, small ridge).
double ResidualSumOfSquares(const Eigen::MatrixXd& base, const Eigen::Ref<const Eigen::MatrixXd>& extra,
                            const Eigen::VectorXd& r) {
  Eigen::MatrixXd x(r.size(), base.cols() + extra.cols());
  x << base, extra;
  const Eigen::VectorXd scale = (x.colwise().norm().array() + 1e-300).inverse();
  x = x * scale.asDiagonal();
  Eigen::MatrixXd g = x.transpose() * x;
  g.diagonal().array() += 1e-10;
  const Eigen::VectorXd beta = g.ldlt().solve(x.transpose() * r);
  return (r - x * beta).squaredNorm();
}

// Harmonics of a periodogram peak: 1 + the highest positive harmonic order flagged against it.
int HarmonicCount(const Periodogram& pg, std::size_t index, int max_harmonics) {
  int h = 1;
  for (const auto& p : pg.peaks) {
    if (p.harmonic_of == static_cast<int>(index) && p.harmonic_order > 0) h = std::max(h, p.harmonic_order);
  }
  return std::min(h, max_harmonics);
}

}  // namespace

void DiagnosisSignals::Validate() const {
  const Eigen::Index n = time.size();
  if (n < 64) {
    throw std::invalid_argument(fmt::format("DiagnosisSignals: {} samples, at least 64 are needed", n));
  }
  CheckLength(time, n, "time", false);
  CheckLength(position, n, "position", false);
  CheckLength(velocity, n, "velocity", false);
  CheckLength(acceleration, n, "acceleration", false);
  CheckLength(residual, n, "residual", false);
  CheckLength(model_output, n, "model_output", true);
  CheckLength(input, n, "input", true);
  for (Eigen::Index i = 1; i < n; ++i) {
    if (!(time(i) > time(i - 1))) {
      throw std::invalid_argument(fmt::format(
          "DiagnosisSignals: time does not increase at sample {} (t = {} after {})", i, time(i), time(i - 1)));
    }
  }
}

const std::vector<std::string>& EffectNames() {
  static const std::vector<std::string> kNames{
      "position_periodic", "velocity_dependent_ripple", "viscous_friction", "coulomb_friction",
      "stribeck_friction", "asymmetric_friction",       "mass_mismatch",    "time_delay",
      "resonance",         "time_periodic",             "quantization",     "constant_offset"};
  return kNames;
}

std::string EffectPhysics(std::string_view name) {
  if (name == "position_periodic")
    return "a force periodic in position (cogging, screw-lead or gear ripple); add a cogging/ripple block "
           "with this period and its harmonics";
  if (name == "velocity_dependent_ripple")
    return "a position-periodic ripple whose amplitude grows with speed; add a ripple term scaled by |v|";
  if (name == "viscous_friction") return "a force proportional to velocity; add or refit viscous friction";
  if (name == "coulomb_friction")
    return "a constant force opposing motion; add or refit Coulomb friction (friction mode, not sign(v))";
  if (name == "stribeck_friction")
    return "extra friction at low speed decaying with the Stribeck velocity; add a Stribeck term";
  if (name == "asymmetric_friction")
    return "friction that differs between the two directions of motion; use direction-dependent levels";
  if (name == "mass_mismatch") return "a force proportional to acceleration; refit the moving mass (payload)";
  if (name == "time_delay")
    return "the measurement lags the model by a pure delay; add a delay block (transport or sampling delay)";
  if (name == "resonance")
    return "a lightly damped structural mode excited by the drive; add a two-mass or resonance block";
  if (name == "time_periodic")
    return "a vibration periodic in time, independent of position (external vibration, ripple of a supply)";
  if (name == "quantization") return "the measured output is quantized; model the sensor or converter resolution";
  if (name == "constant_offset") return "a constant bias (sensor offset, gravity on an incline, amplifier offset)";
  throw std::invalid_argument(fmt::format("unknown effect '{}'", name));
}

EffectRegressors BuildEffectRegressors(const EffectInstance& effect, const DiagnosisSignals& s) {
  const Eigen::Index n = s.size();
  const std::string& name = effect.name;
  EffectRegressors out;
  auto single = [&](Eigen::VectorXd col) {
    out.columns = std::move(col);
    out.column_names = {name};
  };
  if (name == "constant_offset") {
    single(Eigen::VectorXd::Ones(n));
  } else if (name == "viscous_friction") {
    single(s.velocity);
  } else if (name == "coulomb_friction") {
    single(SignDeadBand(s.velocity, Param(effect, "dead_band")));
  } else if (name == "stribeck_friction") {
    const double vs = PositiveParam(effect, "stribeck_velocity");
    const Eigen::VectorXd sg = SignDeadBand(s.velocity, Param(effect, "dead_band"));
    single((-(s.velocity.array() / vs).square()).exp() * sg.array());
  } else if (name == "asymmetric_friction") {
    const double db = Param(effect, "dead_band");
    single(s.velocity.unaryExpr([db](double v) { return v > db ? 1.0 : 0.0; }));
  } else if (name == "mass_mismatch") {
    single(s.acceleration);
  } else if (name == "position_periodic") {
    FillPeriodic(s.position, PositiveParam(effect, "period"), HarmonicsParam(effect), name, &out);
  } else if (name == "velocity_dependent_ripple") {
    const Eigen::VectorXd speed = s.velocity.cwiseAbs();
    FillPeriodic(s.position, PositiveParam(effect, "period"), 1, name, &out, &speed);
  } else if (name == "time_periodic") {
    FillPeriodic(s.time, 1.0 / PositiveParam(effect, "frequency_hz"), HarmonicsParam(effect), name, &out);
  } else if (name == "resonance") {
    const double f = PositiveParam(effect, "frequency_hz");
    const double zeta = PositiveParam(effect, "damping_ratio");
    const double ts = MedianTimeStep(s.time);
    if (!(f < 0.5 / ts)) {
      throw std::invalid_argument(fmt::format(
          "effect 'resonance': frequency_hz = {} must be below the Nyquist frequency {} Hz", f, 0.5 / ts));
    }
    out.columns = ResonanceColumns(s, ts, f, zeta);
    out.column_names = {"resonance.response", "resonance.rate"};
  } else if (name == "time_delay") {
    const Eigen::VectorXd& y = NeedModelOutput(effect, s);
    single(Shifted(s.time, y, Param(effect, "delay")) - y);
  } else if (name == "quantization") {
    const Eigen::VectorXd& y = NeedModelOutput(effect, s);
    const double q = PositiveParam(effect, "step");
    single(y.unaryExpr([q](double v) { return q * std::round(v / q) - v; }));
  } else {
    std::string known;
    for (const auto& k : EffectNames()) known += (known.empty() ? "" : ", ") + k;
    throw std::invalid_argument(fmt::format("unknown effect '{}'; the catalogue has: {}", name, known));
  }
  return out;
}

CandidateSearch ProposeCandidateEffects(const DiagnosisSignals& s, const Eigen::Ref<const Eigen::VectorXd>& residual,
                                        const Eigen::Ref<const Eigen::MatrixXd>& base_columns,
                                        const CatalogueOptions& options) {
  s.Validate();
  const Eigen::Index n = s.size();
  if (residual.size() != n || base_columns.rows() != n) {
    throw std::invalid_argument(fmt::format(
        "ProposeCandidateEffects: residual has {} and base_columns {} rows, the signals {}", residual.size(),
        base_columns.rows(), n));
  }
  const Eigen::VectorXd r = residual;
  CandidateSearch out;
  auto add = [&](std::string name, std::map<std::string, double> p = {}) {
    out.candidates.push_back({std::move(name), std::move(p)});
  };
  const double v_max = s.velocity.cwiseAbs().maxCoeff();
  const double dead_band = options.dead_band_fraction * v_max;

  add("constant_offset");
  if (v_max > 0.0) {
    add("viscous_friction");
    add("coulomb_friction", {{"dead_band", dead_band}});
    add("asymmetric_friction", {{"dead_band", dead_band}});
    // Stribeck velocity: the trial value whose regressor correlates best with the residual.
    double best_vs = 0.0, best_corr = -1.0;
    const Eigen::VectorXd sg = SignDeadBand(s.velocity, dead_band);
    const Eigen::VectorXd rc = r.array() - r.mean();
    for (double frac : options.stribeck_fractions) {
      const double vs = frac * v_max;
      Eigen::VectorXd col = (-(s.velocity.array() / vs).square()).exp() * sg.array();
      col.array() -= col.mean();
      const double denom = col.norm() * rc.norm();
      const double corr = denom > 0.0 ? std::abs(col.dot(rc)) / denom : 0.0;
      if (corr > best_corr) { best_corr = corr; best_vs = vs; }
    }
    if (best_vs > 0.0) add("stribeck_friction", {{"stribeck_velocity", best_vs}, {"dead_band", dead_band}});
  }
  if (s.acceleration.cwiseAbs().maxCoeff() > 0.0) add("mass_mismatch");

  // Position-periodic effects from the position periodogram.
  const double x_span = s.position.maxCoeff() - s.position.minCoeff();
  if (x_span > 0.0) {
    PeriodogramOptions po = options.position_periodogram;
    if (po.max_period <= 0.0) po.max_period = x_span / options.min_position_cycles;
    out.position_periodogram = PositionPeriodogram(s.position, r, po);
    const auto& pg = out.position_periodogram;
    int proposed = 0;
    for (std::size_t i = 0; i < pg.peaks.size() && proposed < options.max_position_periods; ++i) {
      if (pg.peaks[i].harmonic_of >= 0) continue;
      int sub = 1;  // a weaker peak at k·P (sub-harmonic) means the true period is k·P
      for (const auto& p : pg.peaks) {
        if (p.harmonic_of == static_cast<int>(i) && p.harmonic_order < 0) sub = std::max(sub, -p.harmonic_order);
      }
      const double period = pg.peaks[i].period * sub;
      if (period > pg.max_period) continue;
      const int harmonics = std::min(options.max_harmonics, sub * HarmonicCount(pg, i, options.max_harmonics));
      add("position_periodic", {{"period", period}, {"harmonics", harmonics}});
      if (proposed == 0 && v_max > 0.0) add("velocity_dependent_ripple", {{"period", period}});
      ++proposed;
    }
  }

  // Time-periodic vibration from the time periodogram: the strongest peak that is not locked to the
  // motion's own repetition (there, every state-dependent effect is time-periodic too).
  out.time_periodogram = TimePeriodogram(s.time, r, options.time_periodogram);
  if (x_span > 0.0) {
    out.motion_frequency_hz = 1.0 / TimePeriodogram(s.time, s.position, options.time_periodogram).best().period;
  }
  for (std::size_t i = 0; i < out.time_periodogram.peaks.size(); ++i) {
    const PeriodogramPeak& peak = out.time_periodogram.peaks[i];
    if (peak.harmonic_of >= 0) continue;
    const double f = 1.0 / peak.period;
    const double k = out.motion_frequency_hz > 0.0 ? std::round(f / out.motion_frequency_hz) : 0.0;
    if (k >= 1.0 && k <= options.motion_harmonics &&
        std::abs(f - k * out.motion_frequency_hz) <= 0.01 * f) {
      out.notes.push_back(fmt::format(
          "the residual's time period {:.4g} s ({:.1f} % of its variance) repeats with the motion ({} × its "
          "frequency {:.4g} Hz): it depends on the motion state (x, v, a), not on time; not proposed as "
          "time_periodic",
          peak.period, 100.0 * peak.power, static_cast<int>(k), out.motion_frequency_hz));
      continue;
    }
    add("time_periodic", {{"frequency_hz", f},
                          {"harmonics", HarmonicCount(out.time_periodogram, i, options.max_harmonics)}});
    break;
  }

  // Resonance: the most prominent local maximum of the residual's Welch spectrum — its density over the median
  // density of the bins within ±50 % of its frequency (at least ±10 bins; the 2 bins either side, its own main
  // lobe, left out) — gives f_0 (to a fraction of a Welch bin). Local, because the residual is often low-passed
  // (parallel filtering): against the whole spectrum's median, mostly stop band, any pass-band noise would be
  // "prominent". Then golden-section searches of the joint least-squares fit of r on [base, 1, g, ġ/ω_r] refine
  // f_r (over f_0 ± 2 bins), ζ (log scale, 0.002–0.3, from resonance_damping_ratio) and f_r again: a bin is
  // ~1 Hz, a few per cent of a low mode, and the spectrum alone says little about ζ.
  const double ts = MedianTimeStep(s.time);
  {
    const PowerSpectrum psd = WelchPowerSpectrum(r, ts, std::min(options.welch_segment, n));
    const Eigen::Index m = psd.density.size();
    Eigen::Index k_best = -1;
    double best_prominence = 0.0;
    std::vector<double> window;
    for (Eigen::Index k = 4; k < m - 1; ++k) {
      if (!(psd.density(k) > psd.density(k - 1) && psd.density(k) >= psd.density(k + 1))) continue;
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
    if (k_best > 0) {
      out.notes.push_back(fmt::format(
          "the residual spectrum's most prominent peak: {:.4g} Hz, {:.3g} × the median density around it ({}: a "
          "resonance is proposed above {:.3g} ×)",
          psd.frequency_hz(k_best), best_prominence,
          best_prominence > options.resonance_prominence ? "proposed" : "not proposed", options.resonance_prominence));
    }
    if (k_best > 0 && best_prominence > options.resonance_prominence) {
      // Parabolic interpolation of the log density around the peak bin.
      const double l0 = std::log(psd.density(k_best - 1)), l1 = std::log(psd.density(k_best)),
                   l2 = std::log(psd.density(k_best + 1));
      const double denom = l0 - 2.0 * l1 + l2;
      const double shift = denom < 0.0 ? std::clamp(0.5 * (l0 - l2) / denom, -0.5, 0.5) : 0.0;
      const double bin = psd.frequency_hz(1) - psd.frequency_hz(0);
      double f = psd.frequency_hz(k_best) + shift * bin;
      double zeta = options.resonance_damping_ratio;
      const double nyquist = 0.5 / ts;
      if (f > 2.0 * bin && f + 2.0 * bin < nyquist) {
        Eigen::MatrixXd base(n, base_columns.cols() + 1);
        base << base_columns, Eigen::VectorXd::Ones(n);
        auto sse_f = [&](double trial) { return ResidualSumOfSquares(base, ResonanceColumns(s, ts, trial, zeta), r); };
        auto sse_log_zeta = [&](double log_zeta) {
          return ResidualSumOfSquares(base, ResonanceColumns(s, ts, f, std::exp(log_zeta)), r);
        };
        f = GoldenSectionMinimum(sse_f, f - 2.0 * bin, f + 2.0 * bin, 1e-5);
        zeta = std::exp(GoldenSectionMinimum(sse_log_zeta, std::log(0.002), std::log(0.3), 1e-3));
        f = GoldenSectionMinimum(sse_f, f - bin, f + bin, 1e-5);
      }
      add("resonance", {{"frequency_hz", f}, {"damping_ratio", zeta}});
    }
  }

  // Time delay d (measured = ŷ(t − d)): a first guess d0 = −c from the least-squares fit of r on
  // [1, dŷ/dt] (without the base: the base's a, v columns would absorb part of dŷ/dt), then a log-grid
  // scan of |d| over [|d0|/8, 8|d0|] and a golden-section refinement of the joint fit of r on
  // [base, 1, ŷ(t − d) − ŷ(t)].
  if (s.model_output.size() == n) {
    const Eigen::VectorXd& y = s.model_output;
    Eigen::MatrixXd base(n, base_columns.cols() + 1);
    base << base_columns, Eigen::VectorXd::Ones(n);
    const Eigen::VectorXd dy = CentralDifference(s.time, y);
    Eigen::MatrixXd x(n, 2);
    x << Eigen::VectorXd::Ones(n), dy;
    const Eigen::Vector2d beta = x.colPivHouseholderQr().solve(r);
    const double d0 = -beta(1);
    if (std::isfinite(d0) && std::abs(d0) > 1e-3 * ts) {
      const double sign = d0 > 0.0 ? 1.0 : -1.0;
      auto sse = [&](double magnitude) {
        return ResidualSumOfSquares(base, Shifted(s.time, y, sign * magnitude) - y, r);
      };
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
      // A delay far below the sample period is not resolved by the data: what it "explains" is a free multiple
      // of dŷ/dt (on EMPS, −0.04 ms at 1 ms sampling), not a lag.
      const double delay = sign * 0.5 * (lo + hi);
      if (std::abs(delay) >= options.min_delay_samples * ts) add("time_delay", {{"delay", delay}});
    }
    // Quantization: the measured output y + r changes in integer multiples of its smallest step.
    const Eigen::VectorXd measured = y + r;
    std::vector<double> steps;
    for (Eigen::Index i = 1; i < n; ++i) {
      const double d = std::abs(measured(i) - measured(i - 1));
      if (d > 1e-12 * (1.0 + std::abs(measured(i)))) steps.push_back(d);
    }
    bool on_levels = false;
    if (steps.size() >= 32) {
      const double q = *std::min_element(steps.begin(), steps.end());
      std::size_t on_grid = 0;
      for (double d : steps) on_grid += std::abs(d / q - std::round(d / q)) < 0.02 ? 1u : 0u;
      if (static_cast<double>(on_grid) >= 0.95 * static_cast<double>(steps.size())) {
        add("quantization", {{"step", q}});
        on_levels = true;
      }
    }
    // Not on levels (noise after the quantizer, or the output low-passed in parallel as `compare` does): the
    // quantization error q·round(ŷ/q) − ŷ is a sawtooth periodic in ŷ with period q, so the step is the
    // strongest significant independent peak of the residual's periodogram against ŷ (at least
    // min_quantization_levels periods in ŷ's range). Filtering in time smooths the sawtooth's corners where ŷ
    // crosses levels fast but keeps its period.
    const double y_span = y.maxCoeff() - y.minCoeff();
    if (!on_levels && y_span > 0.0) {
      PeriodogramOptions qo = options.output_periodogram;
      if (qo.max_period <= 0.0) qo.max_period = y_span / options.min_quantization_levels;
      try {
        const Periodogram pg = LombScarglePeriodogram(y, r, qo);
        for (const auto& peak : pg.peaks) {
          if (peak.harmonic_of >= 0) continue;
          if (peak.significant && peak.power >= options.min_quantization_power) add("quantization", {{"step", peak.period}});
          break;
        }
      } catch (const std::invalid_argument&) {
        // ŷ too smooth or too short for the period range (min ≥ max): no quantization to see.
      }
    }
  }
  return out;
}

}  // namespace mb

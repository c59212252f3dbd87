// The diagnosis in words (DiagnoseMissingEffects, steps 5 and 7): each chosen effect's description — its share of the
// held-out residual energy, its parameters with units (periods in mm for metres, else in the position's unit and per
// revolution on a rotary axis; delays and lags in ms), its coefficients, where its fitted contribution is largest —
// and the summary for users with its evidence: the residual's whiteness (Ljung–Box), the strongest position-periodogram
// peak and its false-alarm probability, the robust refit's mean weight. Source: DIAGNOSIS.md, "Naming the missing
// effect", steps 4 and 6 (shares said of what; "no missing effect" said, nothing invented); docs/diagnosis.md.
#include "models/diagnosis/diagnosis_text.h"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <map>
#include <vector>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "engine/units.h"
#include "models/diagnosis/amplitude_factor.h"
#include "models/diagnosis/effect_registry.h"
#include "models/diagnosis/factors.h"
#include "models/diagnosis/parameter_text.h"
#include "models/diagnosis/robust_weighting.h"
#include "models/diagnosis/signal_processing.h"

namespace mb::diagnosis_detail {
namespace {

// A position in the diagnosis' position unit: mm for metres, else the unit itself.
std::string FormatPosition(double x, const std::string& unit) {
  if (unit == "m") return fmt::format("{:.4g} mm", x * 1e3);
  return fmt::format("{:.4g} {}", x, unit);
}

// `log_column`: the name of the unread log column a "column" parameter indexes ("" when none): named, not numbered.
std::string FormatParameters(const std::string& effect, const std::map<std::string, double>& p,
                             const std::string& position_unit, const std::string& log_column = "") {
  std::string out;
  for (const auto& [k, v] : p) {
    if (k.starts_with("amplitude_")) continue;  // a third factor: in its own words (AmplitudeWords)
    std::string item;
    if (k == "period") {
      item = "period " + FormatPosition(v, position_unit);
      if (const double rev = RevolutionIn(position_unit); rev > 0.0) {
        item += fmt::format(" ({:.3f} per revolution)", rev / v);
      }
    }
    else if (k == "delay") item = fmt::format("delay {:.4g} ms (the measurement lags the model)", v * 1e3);
    else if (k == "lag") item = fmt::format("lag {:.4g} ms (the logged command acts later)", v * 1e3);
    else if (k == "change_time") item = fmt::format("from t = {:.4g} s on", v);
    else if (k == "start_time" || k == "end_time") item = fmt::format("{} {:.4g} s", k.substr(0, k.find('_')), v);
    else if (k == "upper_limit" || k == "lower_limit") item = fmt::format("{} limit {:.4g}", k.substr(0, 5), v);
    else if (k == "frequency_hz") item = fmt::format("frequency {:.4g} Hz", v);
    else if (k == "harmonics") item = fmt::format("{} harmonic(s)", static_cast<int>(v));
    else if (k == "amplitude") item = fmt::format("amplitude {:.3g}", v);
    else if (k == "column" && !log_column.empty()) item = fmt::format("column '{}'", log_column);
    else item = fmt::format("{} {}", k, FormatParameterValue(v, EffectParameterUnit(effect, k), position_unit));
    out += (out.empty() ? "" : ", ") + item;
  }
  return out;
}

}  // namespace

DiagnosedEffect DescribeEffect(const Candidate& c, double score, double cumulative, const Eigen::VectorXd& coefficients,
                               const Eigen::VectorXd& coefficient_std, const DiagnosisSignals& signals,
                               const std::string& position_unit, bool friction_law) {
  const Eigen::Index n = signals.size();
  DiagnosedEffect d;
  d.effect = c.effect.name;
  d.multiplier = c.type->multiplier;
  d.modulator = c.type->modulator;
  d.score = score;
  d.cumulative_share = cumulative;
  d.parameters = c.effect.parameters;
  d.column_names = c.reg.column_names;
  d.coefficients = coefficients;
  d.coefficient_std = coefficient_std;
  // The amplitude of the first harmonic for every effect whose first columns are Fourier columns (PeriodicColumns:
  // the periodic effects, gravity's m·g·l).
  const bool fourier = d.column_names.size() >= 2 && d.column_names[0].ends_with(".cos1") &&
                       d.column_names[1].ends_with(".sin1");
  if (c.type->traits.periodicity != Periodicity::kNone || fourier) {
    d.parameters["amplitude"] = std::hypot(d.coefficients(0), d.coefficients(1));
  }
  if (!c.type->traits.coefficient_parameter.empty() && d.coefficients.size() == 1) {
    d.parameters[c.type->traits.coefficient_parameter] = d.coefficients(0);
  }
  if (c.type->derived_parameters) {
    for (const auto& [key, value] : c.type->derived_parameters(c.effect, d.coefficients)) d.parameters[key] = value;
  }
  // A third factor (amplitude_factor.h): the amplitude's change per unit of its source, and the column's name.
  if (const auto with = d.parameters.find(kAmplitudeWith); with != d.parameters.end()) {
    d.parameters[kAmplitudeSlope] = AmplitudeChange(c.reg.columns, d.coefficients, AmplitudeWeights(d.parameters)) /
                                   d.parameters.at(kAmplitudeScale);
    if (with->second >= 0.0 && with->second < static_cast<double>(signals.extra_names.size())) {
      d.amplitude_column = signals.extra_names[static_cast<std::size_t>(with->second)];
    }
  }
  const Eigen::VectorXd contribution = c.reg.columns * d.coefficients;
  d.contribution_rms = std::sqrt(contribution.squaredNorm() / static_cast<double>(n));
  const Eigen::VectorXd magnitude = contribution.cwiseAbs();
  const double threshold = Percentile(std::vector<double>(magnitude.data(), magnitude.data() + n), 0.9);
  std::vector<double> ts, xs, vs;
  for (Eigen::Index j = 0; j < n; ++j) {
    if (std::abs(contribution(j)) >= threshold) {
      ts.push_back(signals.time(j));
      xs.push_back(signals.position(j));
      vs.push_back(signals.velocity(j));
    }
  }
  d.time_range[0] = Percentile(ts, 0.05); d.time_range[1] = Percentile(ts, 0.95);
  d.position_range[0] = Percentile(xs, 0.05); d.position_range[1] = Percentile(xs, 0.95);
  d.velocity_range[0] = Percentile(vs, 0.05); d.velocity_range[1] = Percentile(vs, 0.95);
  // A factor of a log column (logged_column) names the column.
  if (const auto column = d.parameters.find("column"); column != d.parameters.end() && column->second >= 0.0 &&
                                                        column->second < static_cast<double>(signals.extra_names.size())) {
    d.log_column = signals.extra_names[static_cast<std::size_t>(column->second)];
  }
  d.description = fmt::format(
      "{}{}{}: explains {:.1f} % of the held-out residual energy left before it was added ({:.1f} % "
      "cumulative); RMS contribution {:.3g}; largest for t in [{:.3g}, {:.3g}] s, x in [{}, {}], "
      "v in [{:.3g}, {:.3g}] {}/s. {}",
      friction_law ? "the friction law near zero velocity is wrong: " : "", d.effect,
      d.parameters.empty() ? "" : " (" + FormatParameters(d.effect, d.parameters, position_unit, d.log_column) + ")", 100.0 * d.score, 100.0 * d.cumulative_share, d.contribution_rms, d.time_range[0], d.time_range[1],
      FormatPosition(d.position_range[0], position_unit), FormatPosition(d.position_range[1], position_unit),
      d.velocity_range[0], d.velocity_range[1], position_unit, c.type->physics);
  if (!d.log_column.empty()) {
    d.description += fmt::format(" The residual follows the log column '{}' (coupling from another axis, or what that "
                                 "column measures acting on this one).", d.log_column);
  }
  // A pair of the grammar in its rows' words, with its figures (issue 45): "the Coulomb friction level follows
  // 'normal_force_N': +0.031 per unit of it".
  const MultiplierRow* multiplier = FindMultiplier(d.multiplier);
  const ModulatorRow* modulator = FindModulator(d.modulator);
  if (multiplier != nullptr && modulator != nullptr && modulator->words) {
    // The coefficient of the shape's one column (named as the effect), beside its level's (MultiplierRow::own_level).
    double single = 0.0, level = 0.0;
    bool has_level = false;
    for (std::size_t k = 0; k < d.column_names.size(); ++k) {
      const double value = d.coefficients(static_cast<Eigen::Index>(k));
      if (d.column_names[k] == d.effect) single = value;
      if (d.column_names[k] == d.effect + ".level") { level = value; has_level = true; }
    }
    std::string words = PairWords(*multiplier, *modulator, d.parameters, single, d.log_column, position_unit);
    words[0] = static_cast<char>(std::toupper(static_cast<unsigned char>(words[0])));
    d.description += " " + words;
    if (has_level) d.description += fmt::format(", from a constant part of {:+.4g}{}", level, multiplier->unit);
    d.description += ".";
  }
  if (const std::string words = AmplitudeWords(d.parameters, d.amplitude_column); !words.empty()) {
    d.description += " " + words + ".";
  }
  return d;
}

void Summarise(const DiagnosisOptions& options, const std::string& ambiguity_note, DiagnosisResult* result) {
  const auto& wb = result->whiteness_before;
  result->notes.push_back(fmt::format("residual after the base refit: Ljung–Box Q = {:.4g}, p = {:.3g} ({})",
                                      wb.ljung_box_q, wb.p_value, wb.white ? "white" : "not white"));
  bool significant_peak = false;
  if (!result->position_peaks.empty()) {
    const auto& pk = result->position_peaks.front();
    significant_peak = pk.significant;
    result->notes.push_back(fmt::format(
        "strongest position-periodogram peak: period {}, {:.1f} % of the variance, false-alarm "
        "probability {:.2g} ({})",
        FormatPosition(pk.period, options.position_unit), 100.0 * pk.power, pk.false_alarm_probability, pk.significant ? "significant" : "not significant"));
  }
  if (const NoiseFloor& floor = result->noise_floor; floor.rms > 0.0) {
    const std::string quantization =
        floor.quantization_rms > 0.0
            ? fmt::format(" ({:.4g}), with what differentiating the position, logged in steps of {}, puts into the "
                          "motion's band ({:.4g}: the model's mass and damping times the derived motion's quantization noise)",
                          floor.white_rms, FormatPosition(floor.position_step, options.position_unit),
                          floor.quantization_rms)
            : std::string();
    result->notes.push_back(fmt::format(
        "noise floor: no model can do better than ≈ {:.4g} (RMS, the output's unit) on this record — the residual's "
        "level at {:.4g}–{:.4g} Hz, above the motion's band, taken as white{}; held-out RMSE after the chosen effects "
        "{:.4g} ({:.2f} × the floor)",
        floor.rms, floor.band_low_hz, floor.band_high_hz, quantization, result->heldout_rmse_after,
        result->heldout_rmse_after / floor.rms));
  }
  if (result->robust_weight_share < 0.999) {
    result->notes.push_back(fmt::format(
        "robust refit (Huber, k = {}): badly modelled samples are down-weighted, mean weight {:.3f}; held-out errors "
        "and shares are of the weighted residual",
        options.huber_k, result->robust_weight_share));
  }
  const auto is_law = [&](const DiagnosedEffect& e) {
    return std::find(result->friction_law.begin(), result->friction_law.end(), e.effect) != result->friction_law.end();
  };
  std::string law;
  const DiagnosedEffect* top = nullptr;
  for (const auto& e : result->effects) {
    if (!is_law(e)) {
      if (top == nullptr) top = &e;
      continue;
    }
    law += fmt::format("{}{}{}", law.empty() ? "" : ", ", e.effect,
                       e.parameters.empty() ? "" : " (" + FormatParameters(e.effect, e.parameters, options.position_unit, e.log_column) + ")");
  }
  if (!law.empty()) {
    result->summary = fmt::format("The friction law near zero velocity is wrong: {} replaces the model's; the other "
                                  "effects were searched in what it leaves. ", law);
  }
  if (result->missing_effect_found && top == nullptr) {
    result->summary += fmt::format("Nothing else is missing. Held-out RMSE {:.4g} → {:.4g}.", result->heldout_rmse_base,
                                   result->heldout_rmse_after);
  } else if (result->missing_effect_found) {
    result->summary += fmt::format(
        "Missing: {}{} — explains {:.1f} % of the held-out residual energy. All chosen effects together "
        "explain {:.1f} %; RMSE {:.4g} → {:.4g} (in-sample, base refit {:.4g}), held-out RMSE {:.4g} → {:.4g}.",
        top->effect, top->parameters.empty() ? "" : " (" + FormatParameters(top->effect, top->parameters, options.position_unit, top->log_column) + ")",
        100.0 * top->score, 100.0 * result->explained_share, result->rmse_before, result->rmse_after,
        result->rmse_base_refit, result->heldout_rmse_base, result->heldout_rmse_after);
    if (result->position_time_indistinguishable) result->summary += " " + ambiguity_note;
  } else if (wb.white && !significant_peak) {
    result->summary = fmt::format(
        "No missing effect: no candidate reduces the held-out error by {:.1f} % or more, the residual is "
        "white (Ljung–Box p = {:.3g}) and no position-periodogram peak is significant. RMSE {:.4g}.",
        100.0 * options.min_gain, wb.p_value, result->rmse_base_refit);
  } else {
    result->summary = fmt::format(
        "No missing effect from the catalogue: no candidate reduces the held-out error by {:.1f} % or more, "
        "but the residual is {}{}; the structure left is not one of the catalogue's effects (try the "
        "non-parametric TISO-GPR component). RMSE {:.4g}.",
        100.0 * options.min_gain, wb.white ? "white" : "not white", significant_peak ? " and has a significant position-periodic peak" : "",
        result->rmse_base_refit);
  }
}

void NoteWhatThePositionShows(const Eigen::VectorXd& residual, double sample_period, const std::string& unit,
                              DiagnosisResult* result) {
  constexpr double kStandsOut = 10.0;  // the peak over the residual's own level in the record's periodogram
  if (!result->loop || residual.size() < 64 || !(sample_period > 0.0)) return;
  const PowerSpectrum psd = WelchPowerSpectrum(residual, sample_period, std::min<Eigen::Index>(1024, residual.size()));
  const double record = static_cast<double>(residual.size()) * sample_period, bin = psd.frequency_hz(1);
  std::vector<std::string> levels;
  for (double decade = 1.0; decade < 0.25 / sample_period; decade *= 10.0) {
    for (const double f : {decade, 2.0 * decade, 5.0 * decade}) {
      if (!(f < 0.25 / sample_period) || f < 2.0 * bin) continue;
      const auto k = static_cast<Eigen::Index>(std::lround(f / bin));
      const double gain = result->loop->GainAt(f, sample_period);
      if (!(gain > 0.0) || k >= psd.density.size()) continue;
      const double smallest = std::sqrt(2.0 * kStandsOut * psd.density(k) / record) / gain;
      levels.push_back(fmt::format("{:.3g} {} at {:g} Hz", smallest, unit, f));
    }
  }
  if (levels.empty()) return;
  result->notes.push_back(fmt::format(
      "what the position can show (simulation mode): a periodic force of amplitude A at f moves it by A·|H(f)|, the "
      "closed loop's gain; against the residual's own level there, the smallest force whose peak stands {:g} × above "
      "it in this record's periodogram is {}; a force the equation-error view names below these, the position cannot "
      "show",
      kStandsOut, fmt::join(levels, ", ")));
}

}  // namespace mb::diagnosis_detail

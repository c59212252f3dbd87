#include "models/diagnosis/diagnosis.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <stdexcept>

#include <Eigen/Dense>
#include <fmt/format.h>

#include "engine/units.h"
#include "models/diagnosis/ambiguity_checks.h"
#include "models/diagnosis/backward_elimination.h"
#include "models/diagnosis/candidate_matrix.h"
#include "models/diagnosis/cross_validation.h"
#include "models/diagnosis/effect_proposal.h"
#include "models/diagnosis/effect_registry.h"
#include "models/diagnosis/forward_selection.h"
#include "models/diagnosis/joint_refinement.h"
#include "models/diagnosis/robust_weighting.h"

namespace mb {

using diagnosis_detail::AddFrictionLaw;
using diagnosis_detail::BlockGrams;
using diagnosis_detail::BuildCandidateMatrix;
using diagnosis_detail::Candidate;
using diagnosis_detail::CheckPositionTimeAmbiguity;
using diagnosis_detail::ChosenInstances;
using diagnosis_detail::LawSearch;
using diagnosis_detail::NoteHysteresis;
using diagnosis_detail::Percentile;
using diagnosis_detail::PruneChosenEffects;
using diagnosis_detail::Ranking;
using diagnosis_detail::RefineChosenEffects;
using diagnosis_detail::RegressorMatrix;
using diagnosis_detail::RetrySetAside;
using diagnosis_detail::RobustWeights;
using diagnosis_detail::SelectEffects;
using diagnosis_detail::Selection;
using diagnosis_detail::SetAsideForRetry;
using diagnosis_detail::StartSelection;

namespace {

// A position in the diagnosis' position unit: mm for metres, else the unit itself.
std::string FormatPosition(double x, const std::string& unit) {
  if (unit == "m") return fmt::format("{:.4g} mm", x * 1e3);
  return fmt::format("{:.4g} {}", x, unit);
}

std::string FormatParameters(const std::map<std::string, double>& p, const std::string& position_unit) {
  std::string out;
  for (const auto& [k, v] : p) {
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
    else item = fmt::format("{} {:.4g}", k, v);
    out += (out.empty() ? "" : ", ") + item;
  }
  return out;
}

AutocorrelationTest Whiteness(const Eigen::VectorXd& r) {
  const Eigen::Index lag = std::min<Eigen::Index>(25, r.size() / 4);
  if ((r.array() - r.mean()).matrix().squaredNorm() <= 0.0) return {};
  return ResidualAutocorrelation(r, lag);
}

// 0. What DiagnoseMissingEffects refuses.
void CheckDiagnosisInput(const DiagnosisSignals& signals, const BaseRegressors& base, const DiagnosisOptions& options) {
  signals.Validate();
  const Eigen::Index n = signals.size();
  const Eigen::Index p = base.columns.cols();
  if ((p > 0 && base.columns.rows() != n) || static_cast<Eigen::Index>(base.names.size()) != p) {
    throw std::invalid_argument(fmt::format(
        "DiagnoseMissingEffects: base regressors are {}×{} with {} names; need {} rows and one name per column",
        base.columns.rows(), p, base.names.size(), n));
  }
  if (p > 0 && !base.columns.allFinite()) {
    throw std::invalid_argument("DiagnoseMissingEffects: the base regressors hold NaN or Inf");
  }
  if (options.folds < 2 || options.folds > n / 16) {
    throw std::invalid_argument(fmt::format(
        "DiagnoseMissingEffects: folds = {} must lie in 2..{} (N/16)", options.folds, n / 16));
  }
  if (options.regressor_filter_hz > 0.0 && !(options.regressor_filter_hz < 0.5 / MedianTimeStep(signals.time))) {
    throw std::invalid_argument(fmt::format("DiagnoseMissingEffects: regressor_filter_hz = {} must be below the "
                                            "Nyquist frequency", options.regressor_filter_hz));
  }
  if (!(options.min_gain >= 0.0 && options.min_gain < 1.0)) {
    throw std::invalid_argument(fmt::format("DiagnoseMissingEffects: min_gain = {} must lie in [0, 1)", options.min_gain));
  }
  if (!(options.huber_k >= 0.0) || !(options.significance_t >= 0.0) || options.significance_batches < 2) {
    throw std::invalid_argument(fmt::format(
        "DiagnoseMissingEffects: huber_k = {} and significance_t = {} must be >= 0 and significance_batches = {} >= 2",
        options.huber_k, options.significance_t, options.significance_batches));
  }
  if (!(options.redundant_with_base > 0.0 && options.redundant_with_base <= 1.0)) {
    throw std::invalid_argument(fmt::format("DiagnoseMissingEffects: redundant_with_base = {} must lie in (0, 1]",
                                            options.redundant_with_base));
  }
}

// The final joint fit: coefficients in the columns' own units, their standard deviations, the fitted correction.
struct JointFit {
  Eigen::VectorXd coef, coef_std, fitted;
  double condition_number = 0.0;
};

// 4. Final joint fit of the base and the chosen effects on all data.
JointFit FitJointly(const RegressorMatrix& m, const BlockGrams& grams, const std::vector<Eigen::Index>& selected) {
  double sse = 0.0;
  const Eigen::VectorXd theta = grams.Fit(selected, &sse);
  const Eigen::Index k = static_cast<Eigen::Index>(selected.size());
  JointFit fit;
  fit.coef.resize(k);
  fit.coef_std.resize(k);
  fit.fitted = Eigen::VectorXd::Zero(m.x.rows());
  if (k == 0) return fit;
  const Eigen::MatrixXd g = grams.TotalGram(selected);
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(g);
  const double lmax = eig.eigenvalues().maxCoeff(), lmin = std::max(eig.eigenvalues().minCoeff(), 0.0);
  fit.condition_number = lmin > 0.0 ? std::sqrt(lmax / lmin) : std::numeric_limits<double>::infinity();
  const double sigma2 = sse / std::max(1.0, grams.n() - static_cast<double>(k));
  Eigen::MatrixXd g_reg = g;
  g_reg.diagonal().array() += 1e-9 * std::max(1.0, g.trace() / static_cast<double>(k));
  const Eigen::MatrixXd cov = sigma2 * g_reg.ldlt().solve(Eigen::MatrixXd::Identity(k, k));
  for (Eigen::Index i = 0; i < k; ++i) {
    const double s = m.scale(selected[static_cast<std::size_t>(i)]);
    fit.coef(i) = theta(i) / s;
    fit.coef_std(i) = std::sqrt(std::max(0.0, cov(i, i))) / s;
    fit.fitted += theta(i) * m.x.col(selected[static_cast<std::size_t>(i)]);
  }
  return fit;
}

// 5. One chosen effect in words: its share, parameters (periodic ones also their first harmonic's amplitude),
// coefficients, and where its fitted contribution is largest.
DiagnosedEffect DescribeEffect(const Candidate& c, double score, double cumulative, const Eigen::VectorXd& coefficients,
                               const Eigen::VectorXd& coefficient_std, const DiagnosisSignals& signals,
                               const std::string& position_unit, bool friction_law) {
  const Eigen::Index n = signals.size();
  DiagnosedEffect d;
  d.effect = c.effect.name;
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
  d.description = fmt::format(
      "{}{}{}: explains {:.1f} % of the held-out residual energy left before it was added ({:.1f} % "
      "cumulative); RMS contribution {:.3g}; largest for t in [{:.3g}, {:.3g}] s, x in [{}, {}], "
      "v in [{:.3g}, {:.3g}] {}/s. {}",
      friction_law ? "the friction law near zero velocity is wrong: " : "", d.effect,
      d.parameters.empty() ? "" : " (" + FormatParameters(d.parameters, position_unit) + ")", 100.0 * d.score, 100.0 * d.cumulative_share, d.contribution_rms, d.time_range[0], d.time_range[1],
      FormatPosition(d.position_range[0], position_unit), FormatPosition(d.position_range[1], position_unit),
      d.velocity_range[0], d.velocity_range[1], position_unit, c.type->physics);
  return d;
}

// 7. Evidence (whiteness, the strongest position-periodogram peak) and the summary for users.
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
                       e.parameters.empty() ? "" : " (" + FormatParameters(e.parameters, options.position_unit) + ")");
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
        top->effect, top->parameters.empty() ? "" : " (" + FormatParameters(top->parameters, options.position_unit) + ")",
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

// 1.–3a. Robust base refit, candidates, and the friction law near zero velocity first: each pass refits the base with
// the replacements chosen so far (Huber IRLS), proposes the candidates anew in what is left (ŷ corrected by that fit,
// so that an effect built from ŷ — a delay — sees the corrected model), and adds the best replacement if one passes;
// then 3b. the other effects are ranked in what the replacements leave. Fills rmse_base_refit, whiteness_before, the
// candidates, periodograms, notes and friction_law of `result`.
Ranking RankEffects(const DiagnosisSignals& signals, const Eigen::MatrixXd& base_cols, const DiagnosisOptions& options,
                    DiagnosisResult* result) {
  const Eigen::Index n = signals.size(), p = base_cols.cols();
  const Eigen::VectorXd& r = signals.residual;
  CatalogueOptions catalogue = options.catalogue;
  if (!(catalogue.revolution > 0.0)) catalogue.revolution = std::max(0.0, RevolutionIn(options.position_unit));
  if (options.regressor_filter_hz > 0.0 && !(catalogue.band_limit_hz > 0.0)) {
    catalogue.band_limit_hz = options.regressor_filter_hz;
  }
  DiagnosisSignals corrected = signals;
  LawSearch law;
  law.columns = base_cols;
  Ranking out;
  // Without a Coulomb law in the model there is no law to replace: the replacements (Stribeck) are ranked as the
  // other effects are.
  const bool replace_law = HasCoulombLaw(base_cols, signals.velocity);
  // The candidate matrix's notes of the last pass only (the one ranked): each pass rebuilds it, and the earlier
  // passes' notes would repeat.
  std::vector<std::string> matrix_notes;
  for (int pass = 0;; ++pass) {
    out.weights = RobustWeights(law.columns, r, options.huber_k, &out.law_residual);
    if (pass == 0) {
      result->rmse_base_refit = std::sqrt(out.law_residual.squaredNorm() / static_cast<double>(n));
      result->whiteness_before = Whiteness(out.law_residual);
    }
    if (signals.model_output.size() == n) corrected.model_output = signals.model_output + (r - out.law_residual);
    const CandidateSearch search = ProposeCandidateEffects(corrected, out.law_residual, law.columns, catalogue);
    result->candidates.insert(result->candidates.end(), search.candidates.begin(), search.candidates.end());
    result->position_peaks = search.position_periodogram.peaks;
    result->time_peaks = search.time_periodogram.peaks;
    if (pass == 0) result->notes = search.notes;
    std::vector<EffectInstance> list = law.effects;  // the replacements chosen are the first candidates
    list.insert(list.end(), search.candidates.begin(), search.candidates.end());
    matrix_notes.clear();
    out.m = BuildCandidateMatrix(corrected, base_cols, list, options, &matrix_notes);
    out.m.Weigh(r, out.weights);
    out.grams.emplace(out.m.wx, out.m.wr, options.folds);
    out.chosen = StartSelection(*out.grams, p);
    for (std::size_t i = 0; i < law.effects.size(); ++i) {
      out.chosen.order.push_back(i);
      out.chosen.selected.insert(out.chosen.selected.end(), out.m.cands[i].idx.begin(), out.m.cands[i].idx.end());
      out.chosen.scores.push_back(law.scores[i]);
      out.chosen.cumulative.push_back(law.cumulative[i]);
    }
    out.chosen.mse_last = out.grams->HeldOutMse(out.chosen.selected);
    if (!replace_law || !AddFrictionLaw(out.m, *out.grams, out.chosen, options, &law, &result->notes)) break;
  }
  result->notes.insert(result->notes.end(), matrix_notes.begin(), matrix_notes.end());
  out.law_columns = law.columns;
  std::vector<bool> used(out.m.cands.size());
  for (std::size_t c = 0; c < out.m.cands.size(); ++c) {
    used[c] = (replace_law && out.m.cands[c].type->traits.friction_law_replacement) ||
              std::find(out.chosen.order.begin(), out.chosen.order.end(), c) != out.chosen.order.end();
  }
  SelectEffects(out.m, *out.grams, used, options, &out.chosen, &result->notes);
  const std::vector<EffectInstance> retry = SetAsideForRetry(out);
  RefineChosenEffects(signals, base_cols, options, law.effects.size(), &out, &result->notes);
  RetrySetAside(signals, base_cols, options, law.effects.size(), retry, &out, &result->notes);
  const std::size_t laws = PruneChosenEffects(signals, base_cols, options, law.effects.size(), &out, &result->notes);
  const std::vector<EffectInstance> chosen = ChosenInstances(out);
  for (std::size_t i = 0; i < laws; ++i) result->friction_law.push_back(chosen[i].name);
  return out;
}

}  // namespace

std::vector<EffectInstance> DiagnosisResult::chosen() const {
  std::vector<EffectInstance> out;
  for (const auto& e : effects) out.push_back({e.effect, e.parameters});
  return out;
}

DiagnosisResult DiagnoseMissingEffects(const DiagnosisSignals& signals, const BaseRegressors& base,
                                       const DiagnosisOptions& options) {
  CheckDiagnosisInput(signals, base, options);
  const Eigen::Index n = signals.size();
  const Eigen::Index p = base.columns.cols();
  const Eigen::MatrixXd base_cols = p > 0 ? base.columns : Eigen::MatrixXd(n, 0);
  const Eigen::VectorXd& r = signals.residual;

  DiagnosisResult result;
  result.position_unit = options.position_unit;
  result.base_names = base.names;
  result.rmse_before = std::sqrt(r.squaredNorm() / static_cast<double>(n));

  // 1.–3. Robust base refit, the friction law near zero velocity, the other effects.
  Ranking ranked = RankEffects(signals, base_cols, options, &result);
  const RegressorMatrix& m = ranked.m;
  const Selection& chosen = ranked.chosen;
  result.heldout_rmse_base = std::sqrt(chosen.mse_base);
  result.heldout_rmse_after = std::sqrt(chosen.mse_last);
  result.explained_share = chosen.mse_base > 0.0 ? 1.0 - chosen.mse_last / chosen.mse_base : 0.0;

  // 4. Final joint fit on all data, its Huber weights refit with the chosen effects in (the weights of the search
  // came from the base's residual, where the missing effects themselves looked like outliers).
  Eigen::VectorXd weights = ranked.weights;
  if (!chosen.selected.empty()) {
    Eigen::MatrixXd selected(n, static_cast<Eigen::Index>(chosen.selected.size()));
    for (std::size_t j = 0; j < chosen.selected.size(); ++j) {
      selected.col(static_cast<Eigen::Index>(j)) = m.x.col(chosen.selected[j]);
    }
    Eigen::VectorXd rest;
    weights = RobustWeights(selected, r, options.huber_k, &rest);
    ranked.m.Weigh(r, weights);
    ranked.grams.emplace(ranked.m.wx, ranked.m.wr, options.folds);
  }
  const JointFit fit = FitJointly(m, *ranked.grams, chosen.selected);
  result.condition_number = fit.condition_number;
  result.robust_weight_share = weights.mean();
  const Eigen::VectorXd r_after = r - fit.fitted;
  result.rmse_after = std::sqrt(r_after.squaredNorm() / static_cast<double>(n));
  result.base_coefficients = fit.coef.head(p);
  result.base_coefficient_std = fit.coef_std.head(p);
  result.whiteness_after = Whiteness(r_after);

  // 5. Describe each chosen effect, highest score first; a law that takes over the model's Coulomb level names it.
  const Eigen::Index coulomb_column = CoulombLawColumn(base_cols, signals.velocity);
  Eigen::Index offset = p;
  for (std::size_t i = 0; i < chosen.order.size(); ++i) {
    const Candidate& c = m.cands[chosen.order[i]];
    const Eigen::Index kc = c.reg.columns.cols();
    result.effects.push_back(DescribeEffect(c, chosen.scores[i], chosen.cumulative[i], fit.coef.segment(offset, kc),
                                            fit.coef_std.segment(offset, kc), signals, options.position_unit,
                                            i < result.friction_law.size()));
    if (c.type->traits.replaces_coulomb_law && coulomb_column >= 0) {
      result.effects.back().replaced_parameter = base.names[static_cast<std::size_t>(coulomb_column)];
    }
    offset += kc;
  }
  // What is missing first (by score), then the friction-law replacements (by score): a replacement changes the
  // model's law rather than adding an effect (the summary names it; `--suggest` takes the first effect).
  const auto is_law = [&](const DiagnosedEffect& e) {
    return std::find(result.friction_law.begin(), result.friction_law.end(), e.effect) != result.friction_law.end();
  };
  std::stable_sort(result.effects.begin(), result.effects.end(), [&](const DiagnosedEffect& a, const DiagnosedEffect& b) {
    if (is_law(a) != is_law(b)) return !is_law(a);
    return a.score > b.score;
  });
  result.missing_effect_found = !result.effects.empty();

  // 6. Can position-periodic and time-periodic be told apart?
  const std::string ambiguity_note =
      CheckPositionTimeAmbiguity(signals, ranked.law_residual, ranked.law_columns, options, &result);
  NoteHysteresis(signals, r_after, &result);

  // 7. Evidence and summary.
  Summarise(options, ambiguity_note, &result);
  return result;
}

Eigen::VectorXd PredictCorrection(const DiagnosisResult& result, const DiagnosisSignals& signals,
                                  const BaseRegressors& base) {
  signals.Validate();
  const Eigen::Index n = signals.size();
  const Eigen::Index p = result.base_coefficients.size();
  if (base.columns.cols() != p || (p > 0 && base.columns.rows() != n)) {
    throw std::invalid_argument(fmt::format(
        "PredictCorrection: base regressors are {}×{}; the diagnosis used {} base columns on {} samples",
        base.columns.rows(), base.columns.cols(), p, n));
  }
  Eigen::VectorXd out = Eigen::VectorXd::Zero(n);
  if (p > 0) out += base.columns * result.base_coefficients;
  for (const auto& e : result.effects) {
    const EffectRegressors reg = BuildEffectRegressors({e.effect, e.parameters}, signals);
    out += reg.columns * e.coefficients;
  }
  return out;
}

BinnedResidual BinResidual(const Eigen::Ref<const Eigen::VectorXd>& abscissa,
                           const Eigen::Ref<const Eigen::VectorXd>& residual, Eigen::Index bins) {
  if (abscissa.size() != residual.size() || bins < 1) {
    throw std::invalid_argument(fmt::format(
        "BinResidual: abscissa ({}) and residual ({}) must be equally long and bins ({}) >= 1",
        abscissa.size(), residual.size(), bins));
  }
  const double lo = abscissa.minCoeff(), hi = abscissa.maxCoeff();
  if (!(hi > lo)) throw std::invalid_argument("BinResidual: the abscissa is constant, nothing to bin");
  const double width = (hi - lo) / static_cast<double>(bins);
  BinnedResidual out;
  out.centers = Eigen::VectorXd::LinSpaced(bins, lo + 0.5 * width, hi - 0.5 * width);
  out.mean = Eigen::VectorXd::Zero(bins);
  out.std = Eigen::VectorXd::Zero(bins);
  out.count = Eigen::VectorXi::Zero(bins);
  Eigen::VectorXd sum_sq = Eigen::VectorXd::Zero(bins);
  for (Eigen::Index i = 0; i < abscissa.size(); ++i) {
    const auto b = std::min(bins - 1, static_cast<Eigen::Index>((abscissa(i) - lo) / width));
    out.count(b) += 1;
    out.mean(b) += residual(i);
    sum_sq(b) += residual(i) * residual(i);
  }
  for (Eigen::Index b = 0; b < bins; ++b) {
    if (out.count(b) == 0) continue;
    const double c = static_cast<double>(out.count(b));
    out.mean(b) /= c;
    out.std(b) = std::sqrt(std::max(0.0, sum_sq(b) / c - out.mean(b) * out.mean(b)));
  }
  return out;
}

namespace {
nlohmann::json ToJsonArray(const Eigen::VectorXd& v) { return std::vector<double>(v.data(), v.data() + v.size()); }
nlohmann::json PeaksJson(const std::vector<PeriodogramPeak>& peaks) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& p : peaks) {
    out.push_back({{"period", p.period}, {"power", p.power}, {"amplitude", p.amplitude},
                   {"false_alarm_probability", p.false_alarm_probability}, {"significant", p.significant},
                   {"harmonic_of", p.harmonic_of}, {"harmonic_order", p.harmonic_order}});
  }
  return out;
}
nlohmann::json WhitenessJson(const AutocorrelationTest& a) {
  return {{"ljung_box_q", a.ljung_box_q}, {"p_value", a.p_value}, {"white", a.white}, {"band99", a.band99},
          {"autocorrelation", ToJsonArray(a.autocorrelation)}};
}
}  // namespace

nlohmann::json DiagnosisResult::ToJson() const {
  nlohmann::json j;
  j["missing_effect_found"] = missing_effect_found;
  j["position_time_indistinguishable"] = position_time_indistinguishable;
  j["summary"] = summary;
  j["notes"] = notes;
  j["rmse_before"] = rmse_before;
  j["rmse_base_refit"] = rmse_base_refit;
  j["rmse_after"] = rmse_after;
  j["heldout_rmse_base"] = heldout_rmse_base;
  j["heldout_rmse_after"] = heldout_rmse_after;
  j["explained_share"] = explained_share;
  j["condition_number"] = std::isfinite(condition_number) ? nlohmann::json(condition_number) : nlohmann::json(nullptr);
  nlohmann::json base = nlohmann::json::array();
  for (std::size_t i = 0; i < base_names.size(); ++i) {
    const auto ii = static_cast<Eigen::Index>(i);
    base.push_back({{"name", base_names[i]}, {"correction", base_coefficients(ii)}, {"std", base_coefficient_std(ii)}});
  }
  j["base_parameters"] = base;
  nlohmann::json effs = nlohmann::json::array();
  for (const auto& e : effects) {
    nlohmann::json coefs = nlohmann::json::array();
    for (std::size_t i = 0; i < e.column_names.size(); ++i) {
      const auto ii = static_cast<Eigen::Index>(i);
      coefs.push_back({{"column", e.column_names[i]}, {"value", e.coefficients(ii)}, {"std", e.coefficient_std(ii)}});
    }
    effs.push_back({{"effect", e.effect}, {"score", e.score}, {"cumulative_share", e.cumulative_share},
                    {"parameters", e.parameters}, {"coefficients", coefs}, {"contribution_rms", e.contribution_rms},
                    {"time_range", {e.time_range[0], e.time_range[1]}},
                    {"position_range", {e.position_range[0], e.position_range[1]}},
                    {"velocity_range", {e.velocity_range[0], e.velocity_range[1]}}, {"description", e.description}});
    if (!e.replaced_parameter.empty()) effs.back()["replaces"] = e.replaced_parameter;
  }
  j["effects"] = effs;
  j["whiteness_before"] = WhitenessJson(whiteness_before);
  j["whiteness_after"] = WhitenessJson(whiteness_after);
  j["position_peaks"] = PeaksJson(position_peaks);
  j["time_peaks"] = PeaksJson(time_peaks);
  nlohmann::json cands = nlohmann::json::array();
  for (const auto& c : candidates) cands.push_back({{"effect", c.name}, {"parameters", c.parameters}});
  j["candidates"] = cands;
  j["friction_law"] = friction_law;
  j["robust_weight_share"] = robust_weight_share;
  return j;
}

}  // namespace mb

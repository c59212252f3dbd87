// The diagnosis' pipeline (DiagnoseMissingEffects; the algorithm in diagnosis.h, DIAGNOSIS.md "Naming the missing
// effect"): the input checks, the ranking's passes (robust base refit, the friction law first, the other effects, then
// the chosen effects refined and pruned), the final joint fit, the descriptions, the checks and the summary; and the
// correction carried to another record (PredictCorrection) and the binned residual (BinResidual). Each job is in a file
// of its own (namespace mb::diagnosis_detail): robust_weighting, cross_validation, candidate_matrix, forward_selection,
// joint_refinement, backward_elimination, ambiguity_checks, diagnosis_text; DiagnosisResult::ToJson in diagnosis_json.
#include "models/diagnosis/diagnosis.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <fmt/format.h>

#include "engine/units.h"
#include "models/diagnosis/ambiguity_checks.h"
#include "models/diagnosis/amplitude_selection.h"
#include "models/diagnosis/backward_elimination.h"
#include "models/diagnosis/candidate_matrix.h"
#include "models/diagnosis/change_time_interval.h"
#include "models/diagnosis/cross_validation.h"
#include "models/diagnosis/diagnosis_text.h"
#include "models/diagnosis/effect_proposal.h"
#include "models/diagnosis/effect_registry.h"
#include "models/diagnosis/forward_selection.h"
#include "models/diagnosis/joint_refinement.h"
#include "models/diagnosis/multiplier_reconsideration.h"
#include "models/diagnosis/quantization_floor.h"
#include "models/diagnosis/rival_reconsideration.h"
#include "models/diagnosis/robust_weighting.h"
#include "models/diagnosis/simulated_refit.h"

namespace mb {

using diagnosis_detail::AddFrictionLaw;
using diagnosis_detail::BlockGrams;
using diagnosis_detail::BuildCandidateMatrix;
using diagnosis_detail::Candidate;
using diagnosis_detail::CheckDelayAgainstHysteresis;
using diagnosis_detail::CheckMultiplierAmbiguity;
using diagnosis_detail::CheckPositionTimeAmbiguity;
using diagnosis_detail::ChosenInstances;
using diagnosis_detail::DescribeEffect;
using diagnosis_detail::KeepChosenOnly;
using diagnosis_detail::LawSearch;
using diagnosis_detail::ModulateChosenEffects;
using diagnosis_detail::NoteHysteresis;
using diagnosis_detail::PruneChosenEffects;
using diagnosis_detail::Ranking;
using diagnosis_detail::ReconsiderMultipliers;
using diagnosis_detail::ReconsiderRivals;
using diagnosis_detail::RefineChosenEffects;
using diagnosis_detail::RefitThroughTheDiagram;
using diagnosis_detail::RegressorMatrix;
using diagnosis_detail::RetrySetAside;
using diagnosis_detail::RobustWeights;
using diagnosis_detail::SelectEffects;
using diagnosis_detail::Selection;
using diagnosis_detail::SearchedCount;
using diagnosis_detail::SetAsideForRetry;
using diagnosis_detail::StartSelection;
using diagnosis_detail::Summarise;

namespace {

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
  fit.fitted = Eigen::VectorXd::Zero(m.rows());
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
    fit.fitted += theta(i) * m.Col(selected[static_cast<std::size_t>(i)]);
  }
  return fit;
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
    out.m = RegressorMatrix();  // the last pass's columns freed before this pass's periodograms and matrix
    out.grams.reset();
    out.weights = RobustWeights(law.columns, r, options.huber_k, &out.law_residual);
    if (pass == 0) {
      result->rmse_base_refit = std::sqrt(out.law_residual.squaredNorm() / static_cast<double>(n));
      result->whiteness_before = Whiteness(out.law_residual);
      result->noise_floor =
          EstimateNoiseFloor(out.law_residual, MedianTimeStep(signals.time), options.regressor_filter_hz);
      AddQuantizationFloor(signals, options.regressor_filter_hz, &result->noise_floor);
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
    out.grams.emplace(out.m, options.folds, BlockGrams::Lazy{});
    out.chosen = StartSelection(*out.grams, p);
    // The white part only: the quantization part is of the unweighted residual, and the held-out errors compared are
    // of the Huber-weighted one, which clips the sparse spikes a count's toggling makes at low speed.
    out.chosen.leak_mse = std::pow(options.leak_floor_ratio * result->noise_floor.white_rms, 2);
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
  out.chosen.family = SearchedCount(out.m);  // the retries and refits below keep the search's family-wise significance
  const std::vector<EffectInstance> retry = SetAsideForRetry(out);
  const std::vector<std::pair<std::size_t, EffectInstance>> rivals = out.chosen.rivals;  // before the refinement's rebuild
  KeepChosenOnly(&out);
  out.grams->Detach();  // restricted (complete) when kept; else what the selection computed is all they hold
  RefineChosenEffects(signals, base_cols, options, law.effects.size(), &out, &result->notes);
  ReconsiderRivals(signals, base_cols, options, law.effects.size(), rivals, &out, &result->notes);
  RetrySetAside(signals, base_cols, options, law.effects.size(), retry, &out, &result->notes);
  ReconsiderMultipliers(signals, base_cols, options, law.effects.size(), &out, &result->notes);
  const std::size_t laws = PruneChosenEffects(signals, base_cols, options, law.effects.size(), &out, &result->notes);
  ModulateChosenEffects(signals, base_cols, options, laws, &out, &result->notes);
  const std::size_t kept = RefitThroughTheDiagram(signals, base_cols, options, laws, &out, &result->notes);
  const std::vector<EffectInstance> chosen = ChosenInstances(out);
  for (std::size_t i = 0; i < kept; ++i) result->friction_law.push_back(chosen[i].name);
  return out;
}

// 4. Final joint fit on all data, its Huber weights refit with the chosen effects in (the weights of the search
// came from the base's residual, where the missing effects themselves looked like outliers). Fills the in-sample
// figures of `result`: RMSE after, base corrections, whiteness after, condition number, mean weight.
JointFit FitFinally(const DiagnosisSignals& signals, Eigen::Index p, const DiagnosisOptions& options, Ranking* ranked,
                    DiagnosisResult* result) {
  const Eigen::Index n = signals.size();
  const Eigen::VectorXd& r = signals.residual;
  const RegressorMatrix& m = ranked->m;
  const Selection& chosen = ranked->chosen;
  Eigen::VectorXd weights = ranked->weights;
  if (!chosen.selected.empty()) {
    Eigen::MatrixXd selected(n, static_cast<Eigen::Index>(chosen.selected.size()));
    for (std::size_t j = 0; j < chosen.selected.size(); ++j) {
      selected.col(static_cast<Eigen::Index>(j)) = m.Col(chosen.selected[j]);
    }
    Eigen::VectorXd rest;
    weights = RobustWeights(selected, r, options.huber_k, &rest);
    ranked->m.Weigh(r, weights);
    ranked->grams.emplace(ranked->m, options.folds);
  }
  const JointFit fit = FitJointly(m, *ranked->grams, chosen.selected);
  result->condition_number = fit.condition_number;
  result->robust_weight_share = weights.mean();
  const Eigen::VectorXd r_after = r - fit.fitted;
  result->rmse_after = std::sqrt(r_after.squaredNorm() / static_cast<double>(n));
  result->base_coefficients = fit.coef.head(p);
  result->base_coefficient_std = fit.coef_std.head(p);
  result->whiteness_after = Whiteness(r_after);
  return fit;
}

// 5. Describe each chosen effect (in the order chosen; DiagnoseMissingEffects sorts them); a law that takes over the
// model's Coulomb level names it.
void DescribeChosenEffects(const Ranking& ranked, const JointFit& fit, const DiagnosisSignals& signals,
                           const Eigen::MatrixXd& base_cols, const std::vector<std::string>& base_names,
                           const std::string& position_unit, DiagnosisResult* result) {
  const RegressorMatrix& m = ranked.m;
  const Selection& chosen = ranked.chosen;
  const Eigen::Index coulomb_column = CoulombLawColumn(base_cols, signals.velocity);
  Eigen::Index offset = base_cols.cols();
  for (std::size_t i = 0; i < chosen.order.size(); ++i) {
    const Candidate& c = m.cands[chosen.order[i]];
    const Eigen::Index kc = c.reg.columns.cols();
    result->effects.push_back(DescribeEffect(c, chosen.scores[i], chosen.cumulative[i], fit.coef.segment(offset, kc),
                                             fit.coef_std.segment(offset, kc), signals, position_unit,
                                             i < result->friction_law.size()));
    result->effects.back().base_share = chosen.cumulative[i] - (i > 0 ? chosen.cumulative[i - 1] : 0.0);
    result->effects.back().selection_order = static_cast<int>(i);
    if (c.type->traits.replaces_coulomb_law && coulomb_column >= 0) {
      result->effects.back().replaced_parameter = base_names[static_cast<std::size_t>(coulomb_column)];
    }
    offset += kc;
  }
}

}  // namespace

std::vector<EffectInstance> DiagnosisResult::chosen() const {
  std::vector<EffectInstance> out;
  for (const auto& e : effects) out.push_back({e.effect, e.parameters});
  return out;
}

DiagnosisResult DiagnoseMissingEffects(const DiagnosisSignals& signals, const BaseRegressors& base,
                                       const DiagnosisOptions& given) {
  CheckDiagnosisInput(signals, base, given);
  DiagnosisOptions options = given;
  options.sample_period = MedianTimeStep(signals.time);
  const Eigen::Index n = signals.size();
  const Eigen::Index p = base.columns.cols();
  const Eigen::MatrixXd base_cols = p > 0 ? base.columns : Eigen::MatrixXd(n, 0);
  const Eigen::VectorXd& r = signals.residual;

  DiagnosisResult result;
  result.position_unit = options.position_unit;
  result.loop = options.catalogue.loop;
  result.base_names = base.names;
  result.rmse_before = std::sqrt(r.squaredNorm() / static_cast<double>(n));

  // 1.–3. Robust base refit, the friction law near zero velocity, the other effects.
  Ranking ranked = RankEffects(signals, base_cols, options, &result);
  const Selection& chosen = ranked.chosen;
  result.heldout_rmse_base = std::sqrt(chosen.mse_base);
  result.heldout_rmse_after = std::sqrt(chosen.mse_last);
  result.explained_share = chosen.mse_base > 0.0 ? 1.0 - chosen.mse_last / chosen.mse_base : 0.0;

  // 4′. Where the record places each change time: a change while the effect's multiplier is nearly zero (a drag that
  // steps while the axis rests) fits as well anywhere in that stretch; the user is told the stretch, and the time is
  // placed at its posterior median rather than at whichever end the noise favoured.
  std::vector<std::vector<diagnosis_detail::TimeInterval>> times(ranked.chosen.order.size());
  for (std::size_t i = 0; i < times.size(); ++i) {
    times[i] = diagnosis_detail::PlaceChangeTimes(&ranked, i, signals, options);
  }

  // 4.–5. The final joint fit on all data, and each chosen effect described.
  const JointFit fit = FitFinally(signals, p, options, &ranked, &result);
  const Eigen::VectorXd r_after = r - fit.fitted;
  DescribeChosenEffects(ranked, fit, signals, base_cols, base.names, options.position_unit, &result);
  for (std::size_t i = 0; i < times.size(); ++i) {
    for (const diagnosis_detail::TimeInterval& t : times[i]) {
      DiagnosedEffect& e = result.effects[i];
      e.time_intervals[t.parameter] = {t.low, t.high};
      e.description += fmt::format(" The record places the time it {} between {:.4g} and {:.4g} s",
                                   t.parameter == "on_time" ? "switches on" : t.parameter == "off_time" ? "switches off"
                                                                                                      : "changes",
                                   t.low, t.high);
      e.description += std::abs(t.estimate - t.best_fit) > 0.0
                           ? fmt::format(" (given at its posterior median; the best single fit, {:.4g} s, is one point "
                                         "of a nearly flat stretch).", t.best_fit)
                           : ".";
    }
  }

  // What is missing first, then the friction-law replacements, each by the share of the base's held-out residual it
  // removed (DiagnosedEffect::base_share, not the score: of what was left): a replacement changes the model's law
  // rather than adding an effect (the summary names it; `--suggest` takes the first effect).
  const auto is_law = [&](const DiagnosedEffect& e) {
    return std::find(result.friction_law.begin(), result.friction_law.end(), e.effect) != result.friction_law.end();
  };
  std::stable_sort(result.effects.begin(), result.effects.end(), [&](const DiagnosedEffect& a, const DiagnosedEffect& b) {
    if (is_law(a) != is_law(b)) return !is_law(a);
    return a.base_share > b.base_share;
  });
  result.missing_effect_found = !result.effects.empty();

  // 6. Can position-periodic and time-periodic be told apart?
  const std::string ambiguity_note =
      CheckPositionTimeAmbiguity(signals, ranked.law_residual, ranked.law_columns, options, &result);
  CheckMultiplierAmbiguity(signals, ranked.law_residual, ranked.law_columns, options, &result);
  CheckDelayAgainstHysteresis(signals, ranked.law_residual, ranked.law_columns, options, &result);
  NoteHysteresis(signals, r_after, &result);
  result.relevance = RankSignalRelevance(signals, r_after, options.folds);
  result.notes.push_back("what the residual left " + DescribeRelevance(result.relevance) +
                         " (held-out share a smooth function of each signal alone explains)");

  // 7. Evidence and summary.
  diagnosis_detail::NoteWhatThePositionShows(r_after, MedianTimeStep(signals.time),
                                             options.position_unit == "m" ? "N" : "N·m", &result);
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
  for (const auto& e : result.effects) out += EffectContribution(result, e, signals);
  return out;
}

Eigen::VectorXd EffectContribution(const DiagnosisResult& result, const DiagnosedEffect& effect,
                                   const DiagnosisSignals& signals) {
  const EffectRegressors reg = BuildEffectRegressors({effect.effect, effect.parameters}, signals);
  const Eigen::VectorXd force = reg.columns * effect.coefficients;
  const EffectTraits& traits = LookupEffect(effect.effect).traits;
  if (!result.loop || !ThroughTheLoop(traits) || EffectSimulatedInTheDiagram(traits, signals)) return force;
  return result.loop->Apply(force);
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

}  // namespace mb

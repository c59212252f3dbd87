// A third factor by modulation (DiagnoseMissingEffects, step 3e; amplitude_selection.h). A pair's amplitude that
// drifts with time or follows a temperature is a parameter that varies: the pair's columns times the scheduling
// variable join the fit (Ljung, System Identification, 2nd ed., §5.2), and the held-out blocks decide as for any term.
// Source: issue 45, item 3; docs/diagnosis.md, "A third factor".
#include "models/diagnosis/amplitude_selection.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <utility>

#include <fmt/format.h>

#include "models/diagnosis/amplitude_factor.h"
#include "models/diagnosis/candidate_matrix.h"
#include "models/diagnosis/cross_validation.h"
#include "models/diagnosis/effect_registry.h"
#include "models/diagnosis/factors.h"
#include "models/diagnosis/forward_selection.h"

namespace mb::diagnosis_detail {
namespace {

// The sources a chosen pair's amplitude may follow: −1 (time), then each unread column k that varies and is a new
// signal, but the column the pair follows already.
std::vector<double> SourcesFor(const EffectInstance& effect, const DiagnosisSignals& signals) {
  std::vector<double> out;
  out.push_back(-1.0);
  const auto own = effect.parameters.find("column");
  for (std::size_t k = 0; k < signals.extra_columns.size(); ++k) {
    if (own != effect.parameters.end() && own->second == static_cast<double>(k)) continue;
    const Eigen::VectorXd& c = signals.extra_columns[k];
    if (!(c.maxCoeff() > c.minCoeff()) || UnreadColumnDuplicate(signals, k)) continue;
    out.push_back(static_cast<double>(k));
  }
  return out;
}

// The fitted coefficients of chosen effect i's columns in the ranking's joint fit (in the columns' own units): the
// weights of its force.
Eigen::VectorXd FittedCoefficients(const Ranking& ranking, std::size_t i) {
  double sse = 0.0;
  const Eigen::VectorXd theta = ranking.grams->Fit(ranking.chosen.selected, &sse);
  const std::vector<Eigen::Index>& idx = ranking.m.cands[ranking.chosen.order[i]].idx;
  Eigen::VectorXd out(static_cast<Eigen::Index>(idx.size()));
  for (std::size_t j = 0; j < idx.size(); ++j) {
    const auto at = std::find(ranking.chosen.selected.begin(), ranking.chosen.selected.end(), idx[j]);
    out(static_cast<Eigen::Index>(j)) = theta(at - ranking.chosen.selected.begin()) / ranking.m.scale(idx[j]);
  }
  return out;
}

std::string SourceName(double with, const DiagnosisSignals& signals) {
  return with < 0.0 ? std::string("time") : "'" + signals.extra_names[static_cast<std::size_t>(with)] + "'";
}

// One source tried: the ranking rebuilt with effect i modulated, and its evidence.
struct Trial {
  double with = 0.0;
  std::optional<RegressorMatrix> m;
  Selection s;
  double mse = std::numeric_limits<double>::infinity();
  double t = 0.0;
};

// A modulated effect i that takes over what another chosen effect j explained: a force following a temperature that
// rises over the record is also a force settling in time, and the ranking chose that pair before the modulation was
// tried, so that beside it the modulation gains nothing. Found on the trial's own matrix (effect i modulated, all the
// chosen effects in it) by leaving j's columns out: the modulation must be significant where j is absent, j must no
// longer earn its place beside it (backward elimination's test), and the two together must beat the ranking as it
// stands by options.min_gain, as any term must.
struct Takeover {
  double with = 0.0;
  std::size_t dropped = 0;  // j, in the ranking's chosen order
  double mse = std::numeric_limits<double>::infinity();
  double t = 0.0;       // the modulation's Diebold–Mariano t, j left out
  double t_back = 0.0;  // j's t beside the modulated effect
};

// The ranking rebuilt on `trial` (the chosen effects, one of them changed): its matrix, Grams and selection in order;
// nullopt when an effect's columns cannot be built on this record.
struct Rebuilt {
  RegressorMatrix m;
  BlockGrams grams;
  Selection s;
};
std::optional<Rebuilt> Rebuild(const DiagnosisSignals& signals, const Eigen::MatrixXd& base_cols,
                               const DiagnosisOptions& options, std::size_t laws, const Ranking& ranking,
                               const std::vector<EffectInstance>& trial) {
  const JointRefinement refinement(signals, base_cols, ranking.weights, options, trial, laws);  // ŷ as the laws leave it
  std::vector<std::string> trial_notes;
  RegressorMatrix m = BuildCandidateMatrix(refinement.corrected(), base_cols, trial, options, &trial_notes);
  if (m.cands.size() != trial.size()) return std::nullopt;
  m.Weigh(signals.residual, ranking.weights);
  BlockGrams grams(m, options.folds);
  Selection s = SelectInOrder(m, grams, base_cols.cols(), m.cands.size());
  return Rebuilt{std::move(m), std::move(grams), std::move(s)};
}

// Effect i's modulation (the last column of its candidate in `r`, the trial rebuilt with it) taking over each other
// chosen effect j ≥ laws in turn (Takeover); `best` keeps the passing one with the lowest held-out MSE. `needed` is the
// family-wise t the modulation must reach, `mse_now` the held-out MSE of the ranking as it stands.
void FindTakeover(const Rebuilt& r, std::size_t i, std::size_t laws, double with, const DiagnosisOptions& options,
                  double needed, double mse_now, Takeover* best) {
  const Eigen::Index modulated = r.m.cands[i].idx.back();
  for (std::size_t j = laws; j < r.m.cands.size(); ++j) {
    if (j == i) continue;
    const std::vector<Eigen::Index>& own = r.m.cands[j].idx;
    std::vector<Eigen::Index> without_j;
    std::vector<Eigen::Index> without_both;
    for (const Eigen::Index c : r.s.selected) {
      if (std::find(own.begin(), own.end(), c) != own.end()) continue;
      without_j.push_back(c);
      if (c != modulated) without_both.push_back(c);
    }
    const double mse = r.grams.HeldOutMse(without_j);
    if (!(mse_now > 0.0) || 1.0 - mse / mse_now < options.min_gain || !(mse < best->mse)) continue;
    const double mse_both = r.grams.HeldOutMse(without_both);
    if (!(mse_both > 0.0) || 1.0 - mse / mse_both < options.min_gain) continue;
    const double t = GainSignificance(r.m, r.grams, without_both, without_j, options.significance_batches);
    if (options.significance_t > 0.0 && t < needed) continue;
    const double t_back = GainSignificance(r.m, r.grams, without_j, r.s.selected, options.significance_batches);
    if (options.significance_t > 0.0 && t_back >= options.significance_t) continue;
    *best = Takeover{with, j, mse, t, t_back};
  }
}

// X × 1 and X × a column, both chosen, are one pair: X whose amplitude follows the column (their columns span the same
// space). Merged, the description says so and improve adds them as one effect: alone, neither lowers the held-out
// error where the column's level differs between records (a quadratic drag following a further column: each refused).
void MergeColumnPartners(const DiagnosisSignals& signals, const Eigen::MatrixXd& base_cols,
                         const DiagnosisOptions& options, std::size_t laws, Ranking* out,
                         std::vector<std::string>* notes) {
  for (std::size_t i = laws; i < out->chosen.order.size(); ++i) {
    const std::vector<EffectInstance> chosen = ChosenInstances(*out);
    const EffectType& type = LookupEffect(chosen[i].name);
    if (type.multiplier.empty() || type.modulator != "constant" || chosen[i].parameters.count(kAmplitudeWith) > 0) {
      continue;
    }
    for (std::size_t j = laws; j < chosen.size(); ++j) {
      const EffectType& partner = LookupEffect(chosen[j].name);
      if (j == i || partner.multiplier != type.multiplier || partner.modulator != "column") continue;
      const std::optional<EffectInstance> modulated =
          WithAmplitudeSource(chosen[i], chosen[j].parameters.at("column"), FittedCoefficients(*out, i), signals);
      if (!modulated) continue;
      std::vector<EffectInstance> trial = chosen;
      trial[i] = *modulated;
      trial.erase(trial.begin() + static_cast<std::ptrdiff_t>(j));
      std::optional<Rebuilt> rebuilt = Rebuild(signals, base_cols, options, laws, *out, trial);
      if (!rebuilt) continue;
      notes->push_back(fmt::format("{} and {} are one effect: {} whose amplitude follows {}", chosen[i].name,
                                   chosen[j].name, chosen[i].name,
                                   SourceName(chosen[j].parameters.at("column"), signals)));
      rebuilt->s.leak_mse = out->chosen.leak_mse;
      const Eigen::VectorXd huber = out->weights;
      InstallRefined(signals, base_cols, options, laws, huber, std::move(rebuilt->m), std::move(rebuilt->s), out);
      if (j < i) --i;
      break;
    }
  }
}

// The ranking rebuilt with effect i modulated by the takeover's source and the effect it takes over left out, and a
// note; false (nothing changed) when the rebuilt ranking cannot be built or would fall below the leak floor.
bool TakeOver(const DiagnosisSignals& signals, const Eigen::MatrixXd& base_cols, const DiagnosisOptions& options,
              std::size_t laws, const std::vector<EffectInstance>& chosen, std::size_t i,
              const Eigen::VectorXd& weights, const Takeover& takeover, Ranking* out, std::vector<std::string>* notes) {
  const std::optional<EffectInstance> modulated = WithAmplitudeSource(chosen[i], takeover.with, weights, signals);
  if (!modulated) return false;
  std::vector<EffectInstance> trial = chosen;
  trial[i] = *modulated;
  trial.erase(trial.begin() + static_cast<std::ptrdiff_t>(takeover.dropped));
  std::optional<Rebuilt> rebuilt = Rebuild(signals, base_cols, options, laws, *out, trial);
  if (!rebuilt || rebuilt->s.mse_last < out->chosen.leak_mse) return false;
  const double gain = out->chosen.mse_last > 0.0 ? 1.0 - rebuilt->s.mse_last / out->chosen.mse_last : 0.0;
  const std::string& dropped = chosen[takeover.dropped].name;
  notes->push_back(fmt::format("{}'s amplitude following {} takes over what {} explained: kept, {} left out (the "
                               "factor's Diebold–Mariano t = {:.2f} without it, its own beside the factor {:.2f} < "
                               "{:.2f}; held-out gain {:.1f} %)",
                               chosen[i].name, SourceName(takeover.with, signals), dropped, dropped, takeover.t,
                               takeover.t_back, options.significance_t, 100.0 * gain));
  rebuilt->s.leak_mse = out->chosen.leak_mse;
  const Eigen::VectorXd huber = out->weights;
  InstallRefined(signals, base_cols, options, laws, huber, std::move(rebuilt->m), std::move(rebuilt->s), out);
  return true;
}

}  // namespace

void ModulateChosenEffects(const DiagnosisSignals& signals, const Eigen::MatrixXd& base_cols,
                           const DiagnosisOptions& options, std::size_t laws, Ranking* out,
                           std::vector<std::string>* notes) {
  MergeColumnPartners(signals, base_cols, options, laws, out, notes);
  for (std::size_t i = laws; i < out->chosen.order.size(); ++i) {
    const std::vector<EffectInstance> chosen = ChosenInstances(*out);
    const EffectInstance& effect = chosen[i];
    const EffectType& type = LookupEffect(effect.name);
    if (type.multiplier.empty() || effect.parameters.count(kAmplitudeWith) > 0) continue;
    const std::vector<double> sources = SourcesFor(effect, signals);
    const double needed = FamilyWiseT(options.significance_t, sources.size());
    const Eigen::VectorXd weights = FittedCoefficients(*out, i);
    Trial best;
    Takeover takeover;
    for (const double with : sources) {
      const std::optional<EffectInstance> modulated = WithAmplitudeSource(effect, with, weights, signals);
      if (!modulated) continue;
      std::vector<EffectInstance> trial = chosen;
      trial[i] = *modulated;
      std::optional<Rebuilt> rebuilt = Rebuild(signals, base_cols, options, laws, *out, trial);
      if (!rebuilt) continue;
      FindTakeover(*rebuilt, i, laws, with, options, needed, out->chosen.mse_last, &takeover);
      if (!(rebuilt->s.mse_last < best.mse)) continue;
      RegressorMatrix& m = rebuilt->m;
      Selection& s = rebuilt->s;
      // The same ranking without the modulated column (effect i's last): the gain is the factor's alone.
      const Eigen::Index modulated_column = m.cands[i].idx.back();
      std::vector<Eigen::Index> without;
      for (const Eigen::Index j : s.selected) {
        if (j != modulated_column) without.push_back(j);
      }
      best.t = GainSignificance(m, rebuilt->grams, without, s.selected, options.significance_batches);
      best.with = with;
      best.mse = s.mse_last;
      best.s = std::move(s);
      best.m = std::move(m);
    }
    if (std::isfinite(takeover.mse) && TakeOver(signals, base_cols, options, laws, chosen, i, weights, takeover,
                                                out, notes)) {
      if (takeover.dropped < i) --i;
      continue;
    }
    if (!best.m) continue;
    const double gain = out->chosen.mse_last > 0.0 ? 1.0 - best.mse / out->chosen.mse_last : 0.0;
    const std::string tried = fmt::format("{}'s amplitude following {} (held-out gain {:.1f} %, Diebold–Mariano t = "
                                          "{:.2f} against {:.2f} over {} source(s))",
                                          effect.name, SourceName(best.with, signals), 100.0 * gain, best.t, needed,
                                          sources.size());
    if (!(gain >= options.min_gain) || (options.significance_t > 0.0 && best.t < needed)) {
      if (gain > 0.0) notes->push_back(tried + ": not kept");
      continue;
    }
    if (best.mse < out->chosen.leak_mse) {
      notes->push_back(tried + ": refused, its held-out error would fall below the record's noise floor");
      continue;
    }
    notes->push_back(tried + ": kept");
    best.s.leak_mse = out->chosen.leak_mse;
    const Eigen::VectorXd huber = out->weights;
    InstallRefined(signals, base_cols, options, laws, huber, std::move(*best.m), std::move(best.s), out);
  }
}

}  // namespace mb::diagnosis_detail

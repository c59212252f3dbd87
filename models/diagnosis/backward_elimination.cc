// Pruning by backward elimination (DiagnoseMissingEffects, step 3e): once the chosen effects' parameters are refined
// jointly, each chosen effect's marginal held-out gain in the full set, 1 − MSE(all)/MSE(all but it), with its
// Diebold–Mariano t. A friction-law replacement whose gain is below min_gain or insignificant took what an effect found
// behind it explains better; of the other effects the weakest below min_gain was chosen on a parameter that has since
// moved. They are dropped (a note each) and the rest refined again. Source: DIAGNOSIS.md, "Naming the missing effect"
// (held-out gain as the criterion, nothing invented) and "When the base model is wrong elsewhere" (significance
// against autocorrelation); Diebold & Mariano, "Comparing predictive accuracy" (1995).
#include "models/diagnosis/backward_elimination.h"

#include <algorithm>
#include <limits>
#include <utility>

#include <fmt/format.h>

#include "models/diagnosis/candidate_matrix.h"
#include "models/diagnosis/cross_validation.h"
#include "models/diagnosis/forward_selection.h"

namespace mb::diagnosis_detail {
namespace {

// The marginal held-out gain of chosen effect i (order index) in the full selection: 1 − MSE(all)/MSE(all but it), and
// its Diebold–Mariano t (infinity when the gain is exempt or the test is off).
std::pair<double, double> MarginalGain(const Ranking& ranking, std::size_t i, const DiagnosisOptions& options) {
  const Candidate& c = ranking.m.cands[ranking.chosen.order[i]];
  const std::vector<Eigen::Index>& full = ranking.chosen.selected;
  std::vector<Eigen::Index> without;
  for (Eigen::Index col : full) {
    if (std::find(c.idx.begin(), c.idx.end(), col) == c.idx.end()) without.push_back(col);
  }
  const double mse_without = ranking.grams->HeldOutMse(without);
  const double gain = mse_without > 0.0 ? 1.0 - ranking.grams->HeldOutMse(full) / mse_without : 0.0;
  const double t = options.significance_t > 0.0 && gain < options.significance_exempt_gain
                       ? GainSignificance(ranking.m, *ranking.grams, without, full, options.significance_batches)
                       : std::numeric_limits<double>::infinity();
  return {gain, t};
}

}  // namespace

std::size_t PruneChosenEffects(const DiagnosisSignals& signals, const Eigen::MatrixXd& base_cols,
                               const DiagnosisOptions& options, std::size_t laws, Ranking* out,
                               std::vector<std::string>* notes) {
  const std::size_t count = out->chosen.order.size();
  if (options.refinement_sweeps <= 0 || count < 2) return laws;
  std::vector<bool> drop(count, false);
  std::vector<std::string> dropped;
  std::size_t weakest = count, left = laws;
  double weakest_gain = options.min_gain;
  for (std::size_t i = 0; i < count; ++i) {
    if (i < laws && count == laws) continue;  // no effect behind the laws
    const auto [gain, t] = MarginalGain(*out, i, options);
    if (i >= laws) {
      if (gain < weakest_gain) { weakest_gain = gain; weakest = i; }
      continue;
    }
    if (gain >= options.min_gain && t >= options.significance_t) continue;
    drop[i] = true;
    --left;
    dropped.push_back(fmt::format("{} dropped from the friction law: with the effects found behind it in, it lowers the "
                                  "held-out error by {:.1f} % (Diebold–Mariano t = {:.2f})",
                                  out->m.cands[out->chosen.order[i]].effect.name, 100.0 * gain, t));
  }
  if (weakest < count) {
    drop[weakest] = true;
    dropped.push_back(fmt::format("{} dropped: with its parameters and the others' refined, it lowers the held-out error "
                                  "by {:.1f} % only", out->m.cands[out->chosen.order[weakest]].effect.name,
                                  100.0 * weakest_gain));
  }
  if (dropped.empty()) return laws;
  std::vector<EffectInstance> kept;
  const std::vector<EffectInstance> chosen = ChosenInstances(*out);
  for (std::size_t i = 0; i < count; ++i) {
    if (!drop[i]) kept.push_back(chosen[i]);
  }
  JointRefinement refinement(signals, base_cols, out->weights, options, kept, left);
  refinement.Run(options.refinement_sweeps);
  std::vector<std::string> build_notes;
  RegressorMatrix refined = BuildCandidateMatrix(refinement.corrected(), base_cols, refinement.effects(), options, &build_notes);
  if (refined.cands.size() != kept.size()) return laws;
  refined.Weigh(signals.residual, refinement.weights());
  const BlockGrams grams(refined, options.folds);
  Selection s = SelectInOrder(refined, grams, base_cols.cols(), refined.cands.size());
  InstallRefined(signals, base_cols, options, left, refinement.weights(), std::move(refined), std::move(s), out);
  notes->insert(notes->end(), dropped.begin(), dropped.end());
  return left;
}

}  // namespace mb::diagnosis_detail

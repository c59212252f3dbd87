// The chosen products' multipliers chosen again with the laws and the other effects refit with each (step 3d′ of
// DiagnoseMissingEffects). A greedy forward path is not the best subset, and replacing one term at a time corrects it:
// Miller, Subset Selection in Regression (2nd ed., 2002), ch. 3 (sequential replacement); Hastie, Tibshirani &
// Friedman, The Elements of Statistical Learning (2nd ed.), § 3.3.2 (hybrid stepwise moves). The effect's presence was
// settled by the held-out error; which multiplier it carries is a choice between two fits of (nearly) the same size,
// made by their likelihood: BIC, and Vuong's test for non-nested models (Vuong 1989, Econometrica 57(2)) on the
// in-sample loss differences, their variance from batch means as the forward selection's Diebold–Mariano test. Blocked
// held-out errors are the wrong judge there: a block at a speed no other block reaches is an extrapolation for both,
// and on grammar draw 46 (a quadratic drag; one block at 0.072 m/s, every other under 0.046) it held 94 % of the
// held-out error and named the drive force's ŷ·|ŷ|, which v·|v| beat in sample by 15 %.
#include "models/diagnosis/multiplier_reconsideration.h"

#include <algorithm>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>

#include "models/diagnosis/candidate_matrix.h"
#include "models/diagnosis/cross_validation.h"
#include "models/diagnosis/effect_catalogue.h"
#include "models/diagnosis/effect_registry.h"
#include "models/diagnosis/forward_selection.h"

namespace mb::diagnosis_detail {
namespace {

bool HasParameter(const EffectType& type, const std::string& name) {
  return std::any_of(type.parameters.begin(), type.parameters.end(),
                     [&](const EffectParameter& p) { return p.name == name; });
}

// `chosen` as the product `type` of the same modulator: its shape as found, a slip velocity as found or else the
// dead band's, its own level carried where its row has one.
EffectInstance AsProduct(const EffectInstance& chosen, const EffectType& type, double dead_band) {
  EffectInstance alternative{type.name, {}};
  for (const auto& [name, value] : chosen.parameters) {
    if (HasParameter(type, name)) alternative.parameters[name] = value;
  }
  if (HasParameter(type, "slip_velocity") && !alternative.parameters.count("slip_velocity")) {
    alternative.parameters["slip_velocity"] = std::max(dead_band, 1e-12);
  }
  if (HasParameter(type, "own_level") && !alternative.parameters.count("own_level")) {
    alternative.parameters["own_level"] = 1.0;
  }
  return alternative;
}

// The effects `trial` refit jointly (laws first; `sweeps` 0: at their parameters as they are) and their matrix under
// the ranking's weights; nullopt when an effect has no columns on this record (ŷ in simulation mode) or the base spans
// one.
struct RefitSet {
  std::vector<EffectInstance> effects;
  RegressorMatrix m;
  std::vector<Eigen::Index> all;  // every column: the base's, then each effect's
  double bic = 0.0;               // N·ln(SSE/N) + k·ln N of the in-sample fit under the ranking's weights
};

// Schwarz's criterion of the in-sample fit on the columns `idx`.
double Bic(const BlockGrams& grams, const std::vector<Eigen::Index>& idx) {
  double sse = 0.0;
  grams.Fit(idx, &sse);
  const double n = grams.n();
  return n * std::log(std::max(sse, 1e-300) / n) + static_cast<double>(idx.size()) * std::log(n);
}
std::optional<RefitSet> Refit(const DiagnosisSignals& signals, const Eigen::MatrixXd& base_cols,
                              const DiagnosisOptions& options, std::size_t laws, const Eigen::VectorXd& weights,
                              std::vector<EffectInstance> trial, int sweeps) {
  const std::size_t count = trial.size();
  std::optional<RefitSet> set;
  try {
    JointRefinement refinement(signals, base_cols, weights, options, std::move(trial), laws);
    refinement.Run(sweeps);
    std::vector<std::string> build_notes;
    set.emplace();
    set->effects = refinement.effects();
    set->m = BuildCandidateMatrix(refinement.corrected(), base_cols, set->effects, options, &build_notes);
  } catch (const std::invalid_argument&) {  // not on this record (ŷ in simulation mode)
    return std::nullopt;
  }
  if (set->m.cands.size() != count) return std::nullopt;
  set->m.Weigh(signals.residual, weights);
  for (Eigen::Index j = 0; j < base_cols.cols(); ++j) set->all.push_back(j);
  for (const Candidate& c : set->m.cands) set->all.insert(set->all.end(), c.idx.begin(), c.idx.end());
  set->bic = Bic(BlockGrams(set->m, options.folds), set->all);
  return set;
}

}  // namespace

void ReconsiderMultipliers(const DiagnosisSignals& signals, const Eigen::MatrixXd& base_cols,
                           const DiagnosisOptions& options, std::size_t laws, Ranking* out,
                           std::vector<std::string>* notes) {
  // Equation-error mode only. In simulation mode it was measured to cost a case and gain none (bench_diagnosis
  // --simulation --compare-only: 34 → 33 of 41; a payload's mass × 1 replaced by the simulated drive force × 1,
  // t = 4.1, on a record where a Coulomb and a viscous friction and a hysteresis were chosen beside it).
  if (options.refinement_sweeps <= 0 || !out->grams || options.catalogue.loop) return;
  const double dead_band = options.catalogue.dead_band_fraction * signals.velocity.cwiseAbs().maxCoeff();
  for (std::size_t i = laws; i < out->chosen.order.size(); ++i) {
    const std::vector<EffectInstance> chosen = ChosenInstances(*out);
    const EffectType& type = LookupEffect(chosen[i].name);
    if (type.multiplier.empty() || type.modulator.empty()) continue;
    const double current = Bic(*out->grams, out->chosen.selected);
    // Every other product at the chosen one's shape, the others as they are (a screen), then the best of them refit
    // jointly: the refinement's coordinate scans are the cost (≈ 0.1 s a set with a law on 25k samples). Refitting the
    // best two named the same on the 300 grammar draws (bench_grammar) and cost 3 % more.
    std::vector<std::pair<double, std::vector<EffectInstance>>> screened;  // BIC, the effects
    for (const std::string& name : EffectNames()) {
      const EffectType& other = LookupEffect(name);
      if (other.modulator != type.modulator || other.multiplier.empty() || other.multiplier == type.multiplier) {
        continue;
      }
      if (other.searched && !options.catalogue.every_pair) continue;  // proposed only with the whole grammar
      std::vector<EffectInstance> trial = chosen;
      trial[i] = AsProduct(chosen[i], other, dead_band);
      if (std::optional<RefitSet> set = Refit(signals, base_cols, options, laws, out->weights, std::move(trial), 0)) {
        screened.emplace_back(set->bic, std::move(set->effects));  // its matrix freed (1M samples: 80 MB)
      }
    }
    const std::size_t tried = screened.size();
    const auto lowest = std::min_element(screened.begin(), screened.end(),
                                         [](const auto& a, const auto& b) { return a.first < b.first; });
    if (lowest == screened.end()) continue;
    std::optional<RefitSet> best =
        Refit(signals, base_cols, options, laws, out->weights, std::move(lowest->second), options.refinement_sweeps);
    if (best && !(best->bic < current)) {
      notes->push_back(fmt::format("{} kept: of the other products of its modulator, the best, {}, refit jointly with "
                                   "the friction laws and the other effects in its place, has a BIC {:.1f} higher ({} "
                                   "products tried)",
                                   chosen[i].name, best->m.cands[i].effect.name, best->bic - current, tried));
      best.reset();
    }
    if (!best) continue;
    // Its errors and the chosen set's are of the same weighted residual: Vuong's test on their in-sample loss
    // difference at the forward selection's t, family-wise (Bonferroni) over the products tried here: the best of them
    // is what is tested, so its t is the largest of `tried` and is held to the bar of that many. The same bar for every
    // product, named before or searched: the effect's presence was settled by the forward selection; what is asked
    // here is only which multiplier it carries, among the products of its modulator.
    const double needed = FamilyWiseT(options.significance_t, tried);
    const BlockGrams grams(best->m, options.folds);
    const double t = LossDifferenceT(out->grams->InSampleErrors(out->chosen.selected, out->m),
                                     grams.InSampleErrors(best->all, best->m), options.significance_batches);
    const std::string evidence = fmt::format(
        "{} refit jointly with the friction laws and the other effects in its place: BIC {:.1f} lower (Vuong's t = "
        "{:.2f} of {:.2f} needed on the in-sample loss; {} products tried)",
        best->m.cands[i].effect.name, current - best->bic, t, needed, tried);
    if (!(t >= needed)) {
      notes->push_back(fmt::format("{} kept: of the other products of its modulator, {}: not significant",
                                   chosen[i].name, evidence));
      continue;
    }
    notes->push_back(fmt::format("{} replaced by another product of its modulator, {}", chosen[i].name, evidence));
    Selection s = SelectInOrder(best->m, grams, base_cols.cols(), best->m.cands.size());
    InstallRefined(signals, base_cols, options, laws, out->weights, std::move(best->m), std::move(s), out);
  }
}

}  // namespace mb::diagnosis_detail

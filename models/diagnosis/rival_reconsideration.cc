// ReconsiderRivals (rival_reconsideration.h): a chosen effect against its rivals of the same round, each refined.
#include "models/diagnosis/rival_reconsideration.h"

#include <optional>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>

#include "models/diagnosis/candidate_matrix.h"
#include "models/diagnosis/cross_validation.h"
#include "models/diagnosis/effect_registry.h"
#include "models/diagnosis/forward_selection.h"

namespace mb::diagnosis_detail {

void ReconsiderRivals(const DiagnosisSignals& signals, const Eigen::MatrixXd& base_cols, const DiagnosisOptions& options,
                      std::size_t laws, const std::vector<std::pair<std::size_t, EffectInstance>>& rivals, Ranking* out,
                      std::vector<std::string>* notes) {
  if (options.refinement_sweeps <= 0 || !out->grams) return;
  for (std::size_t first = 0; first < rivals.size();) {
    const std::size_t position = rivals[first].first;
    std::size_t last = first;
    while (last < rivals.size() && rivals[last].first == position) ++last;
    const std::vector<EffectInstance> chosen = ChosenInstances(*out);
    if (position < laws || position >= chosen.size()) {
      first = last;
      continue;
    }
    const double current = out->grams->HeldOutMse(out->chosen.selected);
    struct Best {
      RegressorMatrix m;
      double mse = 0.0;
    };
    std::optional<Best> best;
    for (std::size_t r = first; r < last; ++r) {
      const EffectInstance& rival = rivals[r].second;
      std::vector<EffectInstance> trial = chosen;
      trial[position] = rival;
      Best b;
      try {
        JointRefinement refinement(signals, base_cols, out->weights, options, trial, laws);
        refinement.Run(options.refinement_sweeps);
        std::vector<std::string> build_notes;
        b.m = BuildCandidateMatrix(refinement.corrected(), base_cols, refinement.effects(), options, &build_notes);
      } catch (const std::invalid_argument&) {
        continue;
      }
      if (b.m.cands.size() != trial.size()) continue;
      b.m.Weigh(signals.residual, out->weights);
      const BlockGrams grams(b.m, options.folds);
      std::vector<Eigen::Index> all;
      for (Eigen::Index j = 0; j < base_cols.cols(); ++j) all.push_back(j);
      for (const Candidate& c : b.m.cands) all.insert(all.end(), c.idx.begin(), c.idx.end());
      b.mse = grams.HeldOutMse(all);
      const EffectInstance& refit = b.m.cands[position].effect;
      const std::string& parameter = LookupEffect(rival.name).traits.refined_parameter;
      const std::string shape = refit.parameters.count(parameter) && rival.parameters.count(parameter)
                                    ? fmt::format(" ({} {:.5g} → {:.5g})", parameter, rival.parameters.at(parameter),
                                                  refit.parameters.at(parameter))
                                    : "";
      const bool below_floor = b.mse < out->chosen.leak_mse;  // it would fit the noise (AddBestEffect's leak check)
      const bool lower = b.mse < (1.0 - kHeldOutTie) * current && !below_floor;
      notes->push_back(fmt::format("{}'s rival {}{}, refit in its place with the chosen effects: held-out MSE {:.4g} "
                                   "against {:.4g}{}",
                                   chosen[position].name, rival.name, shape, b.mse, current,
                                   lower ? ": lower" : below_floor ? ": below the noise floor, kept" : ": not lower, kept"));
      if (lower && (!best || b.mse < best->mse)) best = std::move(b);
    }
    first = last;
    if (!best) continue;
    notes->push_back(fmt::format("{} replaced by its rival {}, refined", chosen[position].name,
                                 best->m.cands[position].effect.name));
    const Eigen::VectorXd weights = out->weights;
    const BlockGrams grams(best->m, options.folds);
    Selection s = SelectInOrder(best->m, grams, base_cols.cols(), best->m.cands.size());
    InstallRefined(signals, base_cols, options, laws, weights, std::move(best->m), std::move(s), out);
  }
}

}  // namespace mb::diagnosis_detail

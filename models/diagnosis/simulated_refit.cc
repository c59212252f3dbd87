// The chosen effects refit through the full diagram in simulation mode: the output-error model's sensitivities
// simulated rather than linearised (Ljung, System Identification, 2nd ed., §7.3: the prediction error's gradient is
// the model's own response to each parameter). The search needs the linearised loop (thousands of columns and
// shape trials, each a convolution); the few columns chosen can afford two simulations each. Where the loop is far
// from linear along the record — an axis that sticks at each reversal, where the regularised Coulomb friction is a
// damper two hundred times stiffer than the viscous one — the linearised columns of the base's own forces (a mass, an
// offset) differ from the base's simulated sensitivities by up to 40 % of their energy, and that difference fitted
// other effects' residuals: a mass mismatch of −21 kg beside a plant mass left free.
#include "models/diagnosis/simulated_refit.h"

#include <utility>

#include <fmt/format.h>

#include "models/diagnosis/candidate_matrix.h"
#include "models/diagnosis/cross_validation.h"
#include "models/diagnosis/forward_selection.h"

namespace mb::diagnosis_detail {

std::size_t RefitThroughTheDiagram(const DiagnosisSignals& signals, const Eigen::MatrixXd& base_cols,
                                   const DiagnosisOptions& options, std::size_t laws, Ranking* out,
                                   std::vector<std::string>* notes) {
  const LoopResponse* loop = options.catalogue.loop.get();
  if (loop == nullptr || !loop->can_simulate() || out->chosen.order.empty()) return laws;
  const LoopResponse::SimulatedCount before = loop->simulated_count();
  DiagnosisOptions simulated = options;
  simulated.simulate_loop_columns = true;
  // Only for ŷ corrected by the base and the laws, as every step after the selection builds the columns on it.
  const JointRefinement refinement(signals, base_cols, out->weights, options, ChosenInstances(*out), laws);
  std::vector<EffectInstance> kept = ChosenInstances(*out);
  std::size_t left = laws;
  std::vector<std::string> spanned, weak, build_notes;
  for (;;) {
    RegressorMatrix m = BuildCandidateMatrix(refinement.corrected(), base_cols, kept, simulated, &build_notes);
    // BuildCandidateMatrix keeps the order and leaves out only what the base spans (or what cannot be computed).
    std::vector<EffectInstance> built;
    std::size_t built_laws = 0;
    for (std::size_t i = 0, j = 0; i < kept.size(); ++i) {
      if (j < m.cands.size() && m.cands[j].effect.name == kept[i].name &&
          m.cands[j].effect.parameters == kept[i].parameters) {
        built.push_back(kept[i]);
        built_laws += i < left ? 1 : 0;
        ++j;
      } else {
        spanned.push_back(kept[i].name);
      }
    }
    kept = std::move(built);
    left = built_laws;
    m.Weigh(signals.residual, out->weights);
    const BlockGrams grams(m, options.folds);
    Selection s = SelectInOrder(m, grams, base_cols.cols(), m.cands.size());
    // An effect that, simulated, lowers the held-out error by less than the selection's least gain was chosen on the
    // linearisation's error: dropped, as the selection would not have taken it.
    std::vector<EffectInstance> strong;
    for (std::size_t i = 0; i < kept.size(); ++i) {
      if (i >= left && s.scores[i] < options.min_gain) {
        weak.push_back(fmt::format("{} ({:.2f} %)", kept[i].name, 100.0 * s.scores[i]));
      } else {
        strong.push_back(kept[i]);
      }
    }
    if (strong.size() == kept.size()) {
      InstallRefined(signals, base_cols, options, left, out->weights, std::move(m), std::move(s), out);
      break;
    }
    kept = std::move(strong);
  }
  std::string dropped;
  if (!spanned.empty()) {
    dropped += fmt::format("; {} dropped: the base's own parameters reproduce what {} left of the output",
                           fmt::join(spanned, ", "), spanned.size() > 1 ? "they" : "it");
  }
  if (!weak.empty()) {
    dropped += fmt::format("; {} dropped: simulated, {} the held-out error by less than {:.0f} %",
                           fmt::join(weak, ", "), weak.size() > 1 ? "they lower" : "it lowers", 100.0 * options.min_gain);
  }
  const LoopResponse::SimulatedCount after = loop->simulated_count();
  const Eigen::Index columns = after.columns - before.columns, linearised = after.linearised - before.linearised;
  notes->push_back(fmt::format(
      "simulation mode: the chosen effects' forces were simulated through the full diagram for the final fit (the "
      "output's exact response to each, where the search used the loop linearised at one stretch){}{}",
      linearised == 0 ? std::string()
                      : fmt::format("; {} of their {} columns kept the linearised response: pushed either way, the "
                                    "diagram answered differently (it switches within the push: a stick–slip law, a "
                                    "limit) or a pushed run failed to simulate", linearised, columns),
      dropped));
  notes->insert(notes->end(), build_notes.begin(), build_notes.end());
  return left;
}

}  // namespace mb::diagnosis_detail

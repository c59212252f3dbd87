#pragma once
// Forward selection of the missing effects (forward_selection.cc): rounds that add the candidate with the lowest
// held-out error, scored by the share of the held-out residual it explains, chosen only when the gain is significant
// (DiagnoseMissingEffects, steps 3–3b).

#include <cstddef>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>

#include "models/diagnosis/candidate_matrix.h"
#include "models/diagnosis/cross_validation.h"

namespace mb::diagnosis_detail {

// Held-out MSEs within this share of each other are a tie: the forward selection takes the lower BIC among them, and
// a rival (ReconsiderRivals) must beat the chosen one by more.
inline constexpr double kHeldOutTie = 1e-3;
// A candidate whose held-out MSE is within this share above the chosen one's is its rival (Selection::rivals).
inline constexpr double kRivalMargin = 0.25;
inline constexpr std::size_t kMaxRivals = 3;

// What the forward selection chose.
struct Selection {
  std::vector<Eigen::Index> selected;  // columns of the regressor matrix: the base's, then the chosen effects'
  std::vector<std::size_t> order;      // the chosen candidates, in the order they were added
  std::vector<double> scores, cumulative;
  double mse_base = 0.0;  // held-out MSE of the base alone
  double mse_last = 0.0;  // held-out MSE after the last chosen effect
  std::vector<std::size_t> set_aside;  // candidates whose gain was not significant (AddBestEffect)
  // The chosen ones' rivals (AddBestEffect): candidates of their round with a shape parameter to refine
  // (EffectTraits::refined_parameter) whose held-out MSE came within kRivalMargin of theirs, at most kMaxRivals each,
  // closest first, as (the chosen one's position in `order`, the rival). ReconsiderRivals compares them refined.
  std::vector<std::pair<std::size_t, EffectInstance>> rivals;
  // Held-out MSE below which a candidate fits the noise (DiagnosisOptions::leak_floor_ratio × the noise floor, squared);
  // 0 = no check.
  double leak_mse = 0.0;
  // How many searched candidates (EffectType::searched) the search this selection belongs to tried (0 = its own
  // matrix's): the family-wise significance counts them (DiagnosisOptions::significance_t) — a candidate tried again
  // alone after its parameter was re-estimated is still one of the search's ~100, not a family of one.
  std::size_t family = 0;
};

// The candidates of `m` that the grammar's search proposed (EffectType::searched): the family of the family-wise
// significance (Selection::family).
std::size_t SearchedCount(const RegressorMatrix& m);

// The one-sided t a gain must reach among `candidates` tried at once: the normal quantile of 1 − p/candidates, p the
// one-sided tail of `t_single` (Bonferroni; DiagnosisOptions::significance_t). `t_single` for one candidate or none.
double FamilyWiseT(double t_single, std::size_t candidates);

// A selection holding the base's p columns.
Selection StartSelection(const BlockGrams& grams, Eigen::Index p);

// The first `count` candidates of `m` chosen in their order, each scored on the held-out error it removes (after the
// base's p columns).
Selection SelectInOrder(const RegressorMatrix& m, const BlockGrams& grams, Eigen::Index p, std::size_t count);

// No invented effect: is the held-out gain of `trial` over `selected` significant against the residual's own
// autocorrelation? Diebold–Mariano on the per-sample held-out loss differences δ = e_prev² − e_new², the variance of
// their mean from contiguous batch means (batches ≈ the effective sample size). Returns the one-sided t.
double GainSignificance(const RegressorMatrix& m, const BlockGrams& grams, const std::vector<Eigen::Index>& selected,
                        const std::vector<Eigen::Index>& trial, Eigen::Index batches);
// The same test on two fits' held-out errors of the same weighted residual (N each; BlockGrams::HeldOutErrors), from
// any two regressor sets: the one-sided t that `after` predicts better than `before`.
double LossDifferenceT(const Eigen::VectorXd& before, const Eigen::VectorXd& after, Eigen::Index batches);
// The means of `x` (N) over `batches` contiguous batches, their count clamped to [2, max(2, N/8)]: the batch-means
// estimate of a serially correlated series' long-run variance is their variance times the batch length.
Eigen::VectorXd BatchMeans(const Eigen::VectorXd& x, Eigen::Index batches);

// One round: adds the best candidate not `used` (near-ties to the lower BIC) whose gain reaches min_gain and is
// significant (GainSignificance; an insignificant best is set aside with a note and the next one tried) and whose
// held-out MSE stays above s->leak_mse (else it is refused with a note: it fits the noise). False when none passes.
bool AddBestEffect(const RegressorMatrix& m, const BlockGrams& grams, const DiagnosisOptions& options,
                   std::vector<bool>* used, Selection* s, std::vector<std::string>* notes);

// 3. Forward selection on the held-out error among the candidates not `used`, continuing `s`: rounds of AddBestEffect
// until options.max_effects effects are chosen or none passes.
void SelectEffects(const RegressorMatrix& m, const BlockGrams& grams, std::vector<bool> used,
                   const DiagnosisOptions& options, Selection* s, std::vector<std::string>* notes);

// The friction-law replacements chosen so far (DiagnoseMissingEffects, step 3a): instances, scores, and the base's
// columns with theirs appended (their raw columns, as the base's).
struct LawSearch {
  std::vector<EffectInstance> effects;
  std::vector<double> scores, cumulative;
  Eigen::MatrixXd columns;
};

// One round of forward selection among the friction-law replacements not chosen yet (at most 3 in all; the chosen
// ones are the first candidates of `m`): true, with `law` extended, when one passes.
bool AddFrictionLaw(const RegressorMatrix& m, const BlockGrams& grams, const Selection& chosen,
                    const DiagnosisOptions& options, LawSearch* law, std::vector<std::string>* notes);

}  // namespace mb::diagnosis_detail

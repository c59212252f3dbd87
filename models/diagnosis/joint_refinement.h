#pragma once
// Joint refinement of the chosen effects' nonlinear parameters (joint_refinement.cc): coordinate scans of the joint fit
// with every chosen effect in (a delay, a gap, a law's velocity scale), and the ranking rebuilt on the refined effects,
// with the candidates set aside as insignificant tried again (DiagnoseMissingEffects, steps 3c–3d).

#include <cstddef>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "models/diagnosis/diagnosis.h"
#include "models/diagnosis/forward_selection.h"

namespace mb::diagnosis_detail {

// 3c. The chosen effects' nonlinear parameters re-estimated jointly (EffectTraits::refined_parameter): each was found in
// what the effects chosen before it left, without those found after it. A coordinate pass per parameter: the weighted
// (Huber) residual sum of squares of the residual on [base, every chosen effect's columns], scanned over the parameter
// alone (MinimiseOnLogGrid). A friction-law replacement also changes ŷ corrected by the laws, and with it the columns
// built from ŷ (a delay's).
class JointRefinement {
 public:
  JointRefinement(const DiagnosisSignals& signals, const Eigen::MatrixXd& base, const Eigen::VectorXd& weights,
                  const DiagnosisOptions& options, std::vector<EffectInstance> effects, std::size_t laws);

  // Coordinate passes (at most `sweeps`) until no parameter moves by 0.1 %, each with the Huber weights refit (IRLS)
  // with every chosen effect in: the ranking's came from the laws' residual, where the effects found behind them looked
  // like outliers (a delay's error at the reversals) and were down-weighted.
  void Run(int sweeps);

  const std::vector<EffectInstance>& effects() const { return effects_; }
  const Eigen::VectorXd& weights() const { return weights_; }
  // The signals with ŷ corrected by the base and the (refined) law replacements: the pairs of ŷ multiply ŷ there, as
  // their blocks do; only their shapes were scanned on the predicted command (PredictCommands).
  DiagnosisSignals corrected() const;

 private:
  static constexpr std::size_t kAll = static_cast<std::size_t>(-1);

  // Effect i's columns on the corrected signals, filtered as BuildCandidateMatrix filters them.
  Eigen::MatrixXd Columns(std::size_t i) const { return ColumnsOf(effects_[i]); }
  // The same for an instance of one of the effects (a trial value of its parameter).
  Eigen::MatrixXd ColumnsOf(const EffectInstance& effect) const;
  // Effect j's columns anew (kAll: every effect's); after a law, ŷ corrected anew and the columns built from it.
  void Rebuild(std::size_t j);
  // ŷ + the weighted least-squares fit of the residual on [base, laws' columns], as RankEffects' passes correct it.
  void Correct();
  // Equation-error mode (no drive_force, a model output): while the passes scan the shapes, each pair of ŷ multiplies
  // the command predicted with it in (DiagnosisSignals::command_with: ŷ corrected + its own part of the weighted joint
  // fit), set at every Reweigh; its columns rebuilt from it.
  void PredictCommands();
  // Is effect i a pair of ŷ (MultiplierRow::model_force) with a shape, whose columns the predicted command changes?
  // Not ŷ × 1: it has no shape that 1/(1 + δ) distorts, and its level is the base's or its multiplier's own.
  bool MultipliesTheCommand(std::size_t i) const;
  // [base, every effect's current columns] (N × k).
  Eigen::MatrixXd Design() const;
  // The Huber weights of the joint fit with the current columns (RobustWeights), ŷ corrected with them, and the
  // commands the pairs of ŷ multiply (PredictCommands).
  void Reweigh();
  // √w, the weighted base and residual, the base's weighted Gram and moment, from weights_.
  void Weigh();
  // While effect j's parameter is scanned: does effect i's column change with it (j itself; for a law, the columns
  // built from ŷ)?
  bool Varies(std::size_t i, std::size_t j) const;

  // The weighted joint fit's part that does not change while effect j's parameter is scanned: the base and the fixed
  // effects' columns, their Gram, and the response less the fixed error columns. An effect whose regressor is the error
  // itself (EffectTraits::regressor_is_error: ŷ delayed minus ŷ) enters with its physical coefficient 1: free, the fit
  // trades the coefficient against the parameter (a delay of 3.1 ms with coefficient 1.16 for 3.5 ms).
  struct FixedPart {
    Eigen::MatrixXd x, gram;
    Eigen::VectorXd response, moment;  // moment = xᵀ·response
    double response_squared = 0.0;
  };
  FixedPart Fix(std::size_t j) const;

  // The weighted residual sum of squares of the joint fit: the fixed part and the varying effects' current columns
  // (normal equations scaled to a unit diagonal, ridge 1e-10, as ResidualSumOfSquares); effect j's taken from
  // own_columns when given (a trial's, columns_ untouched).
  double Sse(const FixedPart& f, std::size_t j, const Eigen::MatrixXd* own_columns = nullptr) const;

  // Scans effect j's refined parameter with the others fixed; true when it moved by more than 0.1 %.
  bool RefineOne(std::size_t j);

  const DiagnosisSignals& signals_;
  DiagnosisSignals corrected_;
  const Eigen::MatrixXd& base_;
  const DiagnosisOptions& options_;
  std::vector<EffectInstance> effects_;
  std::size_t laws_;
  Eigen::VectorXd weights_, sw_, wr_;
  Eigen::MatrixXd wbase_;
  Eigen::VectorXd base_norm_;      // the base's column norms (p)
  Eigen::MatrixXd base_wgram_;     // wbase_ᵀ wbase_ (p × p)
  Eigen::VectorXd base_wmoment_;   // wbase_ᵀ wr_ (p)
  std::vector<Eigen::MatrixXd> columns_;
};

// What the ranking (steps 1–3) leaves for the final fit.
struct Ranking {
  RegressorMatrix m;
  std::optional<BlockGrams> grams;
  Selection chosen;
  Eigen::VectorXd weights;         // the Huber weights of the search
  Eigen::MatrixXd law_columns;     // the base's columns and the chosen friction-law replacements'
  Eigen::VectorXd law_residual;    // the residual after their robust fit
};

// Keeps only the chosen effects' candidates in the ranking's matrix (in the order chosen: the selection becomes its
// columns 0, 1, …) and their entries of the Grams, exactly; the other candidates' columns are freed (on 10⁶ samples,
// ≈ 30 columns of 8 MB each), since the steps after the selection read the chosen ones only. The candidates set aside
// are forgotten (their indices were the old matrix's): call SetAsideForRetry first.
void KeepChosenOnly(Ranking* ranking);

// The chosen effects as instances, in the order they were chosen.
std::vector<EffectInstance> ChosenInstances(const Ranking& ranking);

// The ranking rebuilt on a refined set of chosen effects (the first `laws` of m's candidates are the law replacements):
// its matrix, Grams, selection, weights, and the laws' columns and residual.
void InstallRefined(const DiagnosisSignals& signals, const Eigen::MatrixXd& base_cols, const DiagnosisOptions& options,
                    std::size_t laws, const Eigen::VectorXd& weights, RegressorMatrix m, Selection s, Ranking* out);

// 3c. Re-estimates the chosen effects' refined parameters jointly (JointRefinement) and, when one moved, rebuilds the
// ranking on them: the regressor matrix of the chosen effects alone, in their order, their held-out scores recomputed in
// that order, and a note per parameter that moved.
void RefineChosenEffects(const DiagnosisSignals& signals, const Eigen::MatrixXd& base_cols,
                         const DiagnosisOptions& options, std::size_t laws, Ranking* out,
                         std::vector<std::string>* notes);

// 3d. The candidates to try again (RetrySetAside) — those set aside as insignificant whose parameter the joint
// refinement may correct (EffectTraits::refined_parameter; not a law replacement) — and the retry: each is refined
// jointly with the chosen effects, then chosen when its held-out gain passes (AddBestEffect). Its first estimate was
// made in what the laws left: a gap of 1.44 mm for 1 mm behind a Stribeck law, insignificant there (t = 2.32), is 1 mm
// and clear once both are refit together.
std::vector<EffectInstance> SetAsideForRetry(const Ranking& ranking);
void RetrySetAside(const DiagnosisSignals& signals, const Eigen::MatrixXd& base_cols, const DiagnosisOptions& options,
                   std::size_t laws, const std::vector<EffectInstance>& retry, Ranking* out,
                   std::vector<std::string>* notes);

}  // namespace mb::diagnosis_detail

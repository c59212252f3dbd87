#pragma once
// gpr: the TISO-GPR disturbance model of the seed paper (§3) as a block — the posterior mean
// μ(x, ẋ) + mean(d) (eq. 22 with the training mean added back, eq. 24) of a model fitted by
// `motionblocks fit-gpr` (models/gpr, docs/gpr.md), and optionally its posterior standard deviation
// (√ of eq. 23). In the paper's loop its output goes through α and F_gp (eq. 53).

#include "engine/block.h"
#include "engine/registry.h"
#include "models/gpr/gpr_model.h"

namespace mb {

/// mean = d̂(x, ẋ) = mean(d) + ψ(x, clamp(ẋ))ᵀβ (GprModel::PredictPosteriorMean, eq. 22/24);
/// std = σ(x, ẋ), the latent posterior standard deviation (GprModel::Predict, √ eq. 23).
/// Ports: in "x" [m] and "xdot" [m/s] (both feed through), with learning "online" "d" (the unit of
/// the training disturbance; no feedthrough); out "mean" (the unit of the training disturbance,
/// e.g. N) and, with output_std, "std" (same unit).
/// Parameters:
///  - model: the model file (gpr_io.h format), relative to the diagram's folder
///    (BlockConfig::base_directory), inside it or a folder allowed with --allow-path, a regular file
///    (engine/file_access.h); read once, at construction;
///  - output_std: declare the "std" output (default false; O(M²) per call instead of O(M));
///  - confidence_weighting: output g(x, ẋ)·d̂ instead of d̂, with the confidence weight
///    g = clip(1 − σ²/σ_f², 0, 1) of GprModel::ConfidenceWeight (default false; O(M²) per call):
///    the compensation fades where the model has no data, α(x, ẋ) = α_max·g with α_max the f_gp
///    weight. `motionblocks stability` then uses the Lipschitz constants of g·d̂.
///  - learning: "off" (default: the model file's posterior, fixed) or "online": the posterior over
///    the basis weights is learned during the run from the observed disturbance on input "d" (e.g.
///    the DOB's estimate plus the compensation already applied), a recursive Bayesian update at every
///    `update_every`-th sample hit (models/gpr/gpr_recursive.h: O(M²), no allocation), with
///    exponential forgetting bounded by the prior `forgetting` λ ∈ (0, 1] (memory ≈ 1/(1 − λ) updates; 1 = none); it
///    starts from the model file's posterior (`learn_from` "model") or from its prior (`learn_from`
///    "prior": the basis, hyperparameters and mean, no data). Needs a `sampleTime`. The posterior
///    (m: M, P: M×M) is the block's discrete state; "d" does not feed through (read only in the
///    update), so the loop d̂ → gpr → compensation → d̂ is no algebraic loop. `motionblocks
///    stability` analyses the model the learner starts from.
/// Sample time: inherited without a `sampleTime`, discrete with one ([Ts, offset]; outputs held
/// between hits).
/// Outside the trained ranges (as the model documents, gpr_model.h): ẋ is clamped to the trained
/// velocity range, x is not (PS repeats the learned pattern with period τ, DS decays to the mean);
/// non-finite inputs give the prior mean and prior std.
/// CalcOutput is noexcept and allocation-free (O(M) for the mean, the features on the stack).
/// @throws std::runtime_error / std::invalid_argument naming the parameter, the resolved path and
/// the problem (file missing, not JSON with the byte of the syntax error, every invalid field with
/// its JSON pointer) — the diagram loader adds the element's name and JSON pointer.
class Gpr final : public Block {
 public:
  explicit Gpr(const BlockConfig& config);
  void Initialize(const BlockContext& context) const override;
  void CalcOutput(const BlockContext& context) const noexcept override;
  void UpdateDiscrete(const BlockContext& context) const noexcept override;

  /// The loaded model.
  const GprModel& model() const noexcept { return model_; }

 private:
  GprPosteriorView Posterior(const BlockContext& context) const noexcept;

  GprModel model_;
  bool output_std_;
  bool confidence_weighting_;
  bool online_;
  bool learn_from_prior_;
  double forgetting_;
  int update_every_;
};

}  // namespace mb

#include "blocks/gpr.h"

#include <filesystem>
#include <stdexcept>
#include <string>

#include "engine/block_roles.h"
#include "engine/file_access.h"
#include "models/gpr/gpr_io.h"
#include "models/gpr/gpr_recursive.h"

namespace mb {

namespace {

// Loads the `model` parameter's file, resolved against the diagram's folder. Rethrows with the
// parameter, the path as written and as resolved, keeping the exception type (runtime_error for
// an unreadable or non-JSON file, invalid_argument for an invalid model).
GprModel LoadModelParameter(const BlockConfig& config) {
  const std::string& written = config.parameters.String("model");
  if (written.empty()) {
    throw std::invalid_argument("parameter model is empty: give the model file written by "
                                "`motionblocks fit-gpr` (relative to the diagram's folder)");
  }
  std::filesystem::path path;
  try {
    path = ResolveDiagramFile(written, config.base_directory);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(std::string("parameter model ") + e.what());
  }
  const std::string where = "parameter model \"" + written + "\" (" + path.string() + "): ";
  try {
    return LoadGprModel(path);
  } catch (const std::invalid_argument& e) {
    throw std::invalid_argument(where + e.what());
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(where + e.what());
  }
}

}  // namespace

Gpr::Gpr(const BlockConfig& config)
    : Block(config.name),
      model_(LoadModelParameter(config)),
      output_std_(config.parameters.Bool("output_std")),
      confidence_weighting_(config.parameters.Bool("confidence_weighting")),
      online_(config.parameters.String("learning") == "online"),
      learn_from_prior_(config.parameters.String("learn_from") == "prior"),
      forgetting_(config.parameters.Number("forgetting")),
      update_every_(config.parameters.Integer("update_every")) {
  DeclareInputPort("x", 1, "m");
  DeclareInputPort("xdot", 1, "m/s");
  DeclareOutputPort("mean");
  if (output_std_) DeclareOutputPort("std");
  if (config.sample_time) SetSampleTime(*config.sample_time);
  if (online_) {
    if (!config.sample_time) {
      throw std::invalid_argument("learning \"online\" needs a sampleTime [Ts, 0]: the posterior is updated at the "
                                  "block's sample hits (e.g. the controller's 1 ms)");
    }
    DeclareInputPort("d", 1, "", /*direct_feedthrough=*/false);
    const int m = model_.feature_count();
    DeclareDiscreteState(m + m * m + 1);  // weights m, covariance P (column-major), hits since the last update
  }
}

GprPosteriorView Gpr::Posterior(const BlockContext& c) const noexcept {
  if (!online_) return model_.fitted_posterior();
  const double* state = c.discrete_state().data();
  return {state, state + model_.feature_count()};
}

void Gpr::Initialize(const BlockContext& c) const {
  if (!online_) return;
  const Eigen::Index m = model_.feature_count();
  auto xd = c.discrete_state();
  if (learn_from_prior_) {
    WriteGprPriorPosterior(model_, xd.data(), xd.data() + m);
  } else {
    xd.head(m) = model_.data().weights;
    xd.segment(m, m * m) = model_.data().weight_covariance.reshaped();
  }
  xd(xd.size() - 1) = 0.0;
}

void Gpr::CalcOutput(const BlockContext& c) const noexcept {
  const double x = c.u(0);
  const double xdot = c.u(1);
  const GprPosteriorView posterior = Posterior(c);
  c.y(0) = confidence_weighting_ ? model_.PredictConfidenceWeightedMean(posterior, x, xdot)
                                 : model_.PredictPosteriorMean(posterior, x, xdot);
  if (output_std_) model_.Predict(posterior, x, xdot, nullptr, &c.y(1));
}

void Gpr::UpdateDiscrete(const BlockContext& c) const noexcept {
  if (!online_) return;
  auto xd = c.discrete_state();
  double& hits = xd(xd.size() - 1);
  hits += 1.0;
  if (hits < update_every_) return;
  hits = 0.0;
  double* state = xd.data();
  UpdateGprWeightPosterior(model_, forgetting_, c.u(0), c.u(1), c.u(2), state, state + model_.feature_count());
}

MB_REGISTER_BLOCK(Gpr, BlockType{
    "gpr",
    "TISO-GPR disturbance model (paper §3): mean = μ(x, ẋ) + mean(d) (eq. 22/24), optional std (√eq. 23), "
    "from a model file written by `motionblocks fit-gpr`. In: x [m], xdot [m/s] (ẋ clamped to the trained "
    "range). Inherited sample time, or discrete with a sampleTime. learning \"online\": the weights are learned "
    "during the run from input d (models/gpr/gpr_recursive.h).",
    {FileName("model", "GPR model file (JSON), relative to the diagram's folder"),
     Optional("output_std", false, "", "also output the posterior standard deviation \"std\"",
              ParamType::kBool),
     Optional("confidence_weighting", false, "",
              "scale the mean by the confidence weight g = clip(1 - std^2/prior variance, 0, 1): the compensation "
              "fades where the model has no data",
              ParamType::kBool),
     Choice("learning", "off",
            "\"off\" (the model file's posterior) or \"online\" (learn the weights during the run from input d, "
            "a recursive Bayesian update at the sample hits; needs a sampleTime)",
            {"off", "online"}),
     Choice("learn_from", "model",
            "learning \"online\" starts from the model file's posterior (\"model\") or from its prior (\"prior\": "
            "basis, hyperparameters and mean, no data)",
            {"model", "prior"}),
     Bounded("forgetting", 1.0, "",
             "forgetting factor λ of learning \"online\" (memory ≈ 1/(1 − λ) updates; 1 = none)", 1e-6,
             1.0),
     Bounded("update_every", 1, "", "learning \"online\": update at every k-th sample hit", 1, 1e9,
             ParamType::kInteger)},
    SampleTimeRule::kOptional,
    [](const BlockConfig& c) { return std::make_unique<Gpr>(c); }})
// "gp": the GP model of the loop's GP path, and the block `compare --suggest` adds as the non-parametric fallback
// (tools/workflow/suggest.cc finds it by this role); tools/workflow/loop_from_diagram.h reads its
// confidence_weighting through it.
MB_REGISTER_LOOP_ROLES(Gpr, "gpr", {"gp"})

}  // namespace mb

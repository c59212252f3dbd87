#include "blocks/gpr.h"

#include <filesystem>
#include <stdexcept>
#include <string>

#include "engine/block_roles.h"
#include "engine/file_access.h"
#include "models/gpr/gpr_io.h"

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
      confidence_weighting_(config.parameters.Bool("confidence_weighting")) {
  DeclareInputPort("x", 1, "m");
  DeclareInputPort("xdot", 1, "m/s");
  DeclareOutputPort("mean");
  if (output_std_) DeclareOutputPort("std");
  if (config.sample_time) SetSampleTime(*config.sample_time);
}

void Gpr::CalcOutput(const BlockContext& c) const noexcept {
  const double x = c.u(0);
  const double xdot = c.u(1);
  c.y(0) = confidence_weighting_ ? model_.PredictConfidenceWeightedMean(x, xdot)
                                 : model_.PredictPosteriorMean(x, xdot);
  if (output_std_) model_.Predict(x, xdot, nullptr, &c.y(1));
}

MB_REGISTER_BLOCK(Gpr, BlockType{
    "gpr",
    "TISO-GPR disturbance model (paper §3): mean = μ(x, ẋ) + mean(d) (eq. 22/24), optional std (√eq. 23), "
    "from a model file written by `motionblocks fit-gpr`. In: x [m], xdot [m/s] (ẋ clamped to the trained "
    "range). Inherited sample time, or discrete with a sampleTime.",
    {FileName("model", "GPR model file (JSON), relative to the diagram's folder"),
     Optional("output_std", false, "", "also output the posterior standard deviation \"std\"",
              ParamType::kBool),
     Optional("confidence_weighting", false, "",
              "scale the mean by the confidence weight g = clip(1 - std^2/prior variance, 0, 1): the compensation "
              "fades where the model has no data",
              ParamType::kBool)},
    SampleTimeRule::kOptional,
    [](const BlockConfig& c) { return std::make_unique<Gpr>(c); }})
// "gp": the GP model of the loop's GP path, and the block `compare --suggest` adds as the non-parametric fallback
// (tools/workflow/suggest.cc finds it by this role); tools/workflow/loop_from_diagram.h reads its
// confidence_weighting through it.
MB_REGISTER_LOOP_ROLES(Gpr, "gpr", {"gp"})

}  // namespace mb

// reproduce, step 3: MAP fits of DS and PS on D(1..3), and the ablation's PS fitted to the true disturbance.

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <chrono>
#include <mutex>

#include "models/gpr/gpr_fit.h"
#include "models/gpr/gpr_io.h"
#include "tools/experiments/paper/reproduce_context.h"
#include "tools/report/output_files.h"

namespace mb::paper {

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

// PS on D(2) with another training target (a column of the scans); saved as models/<file>.
void FitPsOnTarget(ReproduceContext& c, const std::string& target, const std::string& what, const std::string& file,
                   std::unique_ptr<GprModel>* model, fs::path* path) {
  const ReproduceOptions& o = c.options;
  const GprTrainingSet data = SelectTrainingWindow(c.scans, kWindowLength[1], 1, target);
  GprFitOptions options;
  options.kernel = GprKernel::kPeriodicSe;
  options.restarts = o.quick ? 0 : 2;
  options.source = "motionblocks reproduce: D2 window, target = " + what;
  *model = std::make_unique<GprModel>(FitGpr(data.x, data.xdot, data.d, options));
  *path = fs::absolute(o.out / "models" / file);
  SaveGprModel(**model, *path);
}

void FitAblationModel(ReproduceContext& c) {
  // Ablation (simulation only): PS on D(2) trained on the true disturbance instead of the DOB estimate.
  FitPsOnTarget(c, "plant.disturbance", "true disturbance (ablation)", "PS_D2_true_disturbance.json",
                &c.ps_true_target, &c.ps_true_target_path);
  // Beyond the paper, from measured signals only: the smoothed (zero-phase) inverse-model estimate.
  FitPsOnTarget(c, kSmoothedTarget, "smoothed inverse-model estimate (zero-phase)", "PS_D2_smoothed.json",
                &c.ps_smoothed_target, &c.ps_smoothed_target_path);
}

}  // namespace

void FitModels(ReproduceContext& c) {
  const ReproduceOptions& o = c.options;
  // 3. MAP fits: {DS, PS} × {D1, D2, D3} × {every sample, paper-size}.
  for (int paper = 0; paper < 2; ++paper) {
    for (int kernel = 0; kernel < 2; ++kernel) {
      for (int k = 0; k < 3; ++k) c.fits.push_back(PaperFit{kernel, k, paper == 1, nullptr, 0.0});
    }
  }
  c.Say(fmt::format("[3/{}] MAP fits of DS and PS on D(1..3): {} models (every sample, and paper-size for the record)",
                    kSteps, c.fits.size()));
  {
    ProgressLine progress("fits");
    std::mutex mutex;
    int done = 0;
    c.arena.execute([&] {
      tbb::parallel_for(std::size_t{0}, c.fits.size(), [&](std::size_t i) {
        PaperFit& f = c.fits[i];
        const GprTrainingSet& data = f.paper_size ? c.paper_size[f.window] : c.full[f.window];
        GprFitOptions fo;
        fo.kernel = kKernel[f.kernel];
        fo.restarts = o.quick ? 0 : 2;
        fo.source = fmt::format("motionblocks reproduce: {} window L = {} mm, {} scans{}", kWindowName[f.window],
                                kWindowLength[f.window] * 1e3, c.scans.size(), f.paper_size ? ", paper-size" : "");
        const auto t0 = std::chrono::steady_clock::now();
        f.model = std::make_unique<GprModel>(FitGpr(data.x, data.xdot, data.d, fo));
        f.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
        std::lock_guard<std::mutex> lock(mutex);
        ++done;
        if (o.progress) progress.Update(static_cast<double>(done) / static_cast<double>(c.fits.size()));
      });
    });
    if (o.progress) progress.Done();
  }
  json models_json;
  for (const auto& f : c.fits) {
    const std::string name =
        fmt::format("{}_{}{}", kKernelName[f.kernel], kWindowName[f.window], f.paper_size ? "_paper_size" : "");
    fs::path path = o.out / "models" / (name + ".json");
    SaveGprModel(*f.model, path);
    c.model_paths[name] = fs::absolute(path);
    const auto& h = f.model->hyperparameters();
    models_json[name] = {{"file", path.string()},
                         {"samples", f.model->data().provenance.sample_count},
                         {"features", f.model->feature_count()},
                         {"fit_seconds", f.seconds},
                         {"signal_variance_x", h.signal_variance_x},
                         {"length_scale_x", h.length_scale_x},
                         {"signal_variance_xdot", h.signal_variance_xdot},
                         {"length_scale_xdot", h.length_scale_xdot},
                         {"noise_variance", h.noise_variance}};
  }
  c.results["models"] = models_json;
  FitAblationModel(c);
}

}  // namespace mb::paper

// motionblocks.fit_gpr and GprModel: the TISO-GPR disturbance model (paper §3; models/gpr) as `fit-gpr` and
// `predict-gpr` compute it — MAP fit on every sample (FitGprToLog), posterior mean and standard deviation, the model
// file the `gpr` block loads.

#include <cmath>
#include <filesystem>
#include <memory>
#include <sstream>
#include <optional>

#include <fmt/format.h>
#include <pybind11/eigen.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "engine/input_file.h"
#include "engine/text_excerpt.h"
#include "models/gpr/gpr_io.h"
#include "models/gpr/gpr_log.h"
#include "python/bindings.h"

namespace mb::python {

namespace {

using Vector = Eigen::VectorXd;

// The arrays as the training table fit-gpr reads (columns position_m, velocity_m_s, disturbance), so that the model
// is the one `motionblocks fit-gpr` fits on the same numbers.
GprModel FitGprToArrays(const Vector& x, const Vector& xdot, const Vector& d, const std::string& kernel, double period,
                        const std::string& solver, bool estimate_period, const std::optional<std::pair<double, double>>& window,
                        int downsample, int restarts, std::uint64_t seed) {
  if (x.size() != xdot.size() || x.size() != d.size()) {
    throw std::invalid_argument(fmt::format("fit_gpr: x, xdot and d must have one length (got {}, {} and {})", x.size(),
                                            xdot.size(), d.size()));
  }
  const Table table({"position_m", "velocity_m_s", "disturbance"}, {x, xdot, d}, "<fit_gpr arrays>");
  GprTrainingSelection selection;
  selection.disturbance_column = "disturbance";
  if (window) selection.window = GprRange{window->first, window->second};
  selection.downsample = downsample;
  GprFitOptions options;
  options.kernel = ParseGprKernel(kernel);
  options.solver = ParseGprSolver(solver);
  options.period = period;
  options.estimate_period = estimate_period;
  options.restarts = restarts;
  options.seed = seed;
  py::gil_scoped_release release;
  return FitGprToLog(table, selection, options);
}

// A model file's JSON syntax, checked before LoadGprModel: a syntax error is a ValueError as the model's other
// problems are (the docstring's promise), not a RuntimeError.
void RequireGprModelJsonSyntax(const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) return;  // LoadGprModel says why (missing, a folder, a device)
  std::istringstream in(ReadInputFile(path, "GP model file"));
  try {
    // Parsed only to be checked (GCC ignores a cast to void of a [[nodiscard]] result: a named, unused value).
    [[maybe_unused]] const nlohmann::json parsed = nlohmann::json::parse(in);
  } catch (const nlohmann::json::parse_error& e) {
    throw std::invalid_argument(fmt::format("{}: not valid JSON (corrupt or truncated?): {}", path, JsonErrorText(e)));
  }
}

// NaN or ±inf in a prediction's input would give the prior without a word (issue 30): refused naming the argument.
void RequireFinite(const Vector& values, const char* argument) {
  for (Eigen::Index i = 0; i < values.size(); ++i) {
    if (!std::isfinite(values(i))) {
      throw std::invalid_argument(fmt::format("predict(): {}[{}] is {}: give finite numbers (drop or fill the "
                                              "samples that are not)",
                                              argument, i, values(i)));
    }
  }
}

py::dict Hyperparameters(const GprModel& model) {
  const GprHyperparameters& h = model.data().hyperparameters;
  py::dict d;
  d["signal_variance_x"] = h.signal_variance_x;
  d["length_scale_x"] = h.length_scale_x;
  d["signal_variance_xdot"] = h.signal_variance_xdot;
  d["length_scale_xdot"] = h.length_scale_xdot;
  d["noise_variance"] = h.noise_variance;
  d["period"] = h.period;
  return d;
}

}  // namespace

void BindGpr(py::module_& m) {
  py::class_<GprModel, std::shared_ptr<GprModel>>(
      m, "GprModel",
      "A fitted TISO-GPR d(x, ẋ) (paper eq. 19–24): weight-space form, immutable. Save it for a diagram's gpr block.")
      .def_static(
          "load",
          [](const py::object& path) {
            const std::string p = PathText(path);
            RequireGprModelJsonSyntax(p);
            return LoadGprModel(p);
          },
          py::arg("path"),
          "Reads a model file (fit-gpr's JSON). Raises OSError if it cannot be opened, ValueError if invalid (a JSON "
          "syntax error with its line and column included).")
      .def(
          "predict",
          [](const GprModel& model, const Vector& x, const Vector& xdot) {
            RequireFinite(x, "x");
            RequireFinite(xdot, "xdot");
            Vector mean(x.size()), std(x.size());
            model.Predict(x, xdot, mean, std);
            return std::make_pair(mean, std);
          },
          py::arg("x"), py::arg("xdot"),
          "Posterior mean d̂ (eq. 22, 24) and the latent posterior standard deviation (√ eq. 23) at positions x [m] "
          "and velocities xdot [m/s], 1-D arrays of one length N: returns (mean, std), each shape (N,), in the "
          "disturbance's unit. ẋ is clamped to the trained range. Raises ValueError on a length mismatch or a NaN or "
          "infinite input (naming the argument and the index).")
      .def("save", [](const GprModel& model, const py::object& path) { SaveGprModel(model, PathText(path)); },
           py::arg("path"), "Writes the model file (JSON) that a diagram's gpr block and predict-gpr read.")
      .def_property_readonly("kernel", [](const GprModel& model) { return std::string(GprKernelName(model.kernel())); },
                             "'PS' (periodic in x + SE in ẋ) or 'DS' (SE + SE).")
      .def_property_readonly("hyperparameters", &Hyperparameters,
                             "dict: signal variances (disturbance unit²), length scales (ℓ_x: dimensionless for 'PS', [m] for 'DS'; "
                             "ℓ_ẋ [m/s]), noise variance (disturbance unit²), period τ [m].")
      .def_property_readonly("mean", [](const GprModel& model) { return model.data().mean; },
                             "The training targets' mean (eq. 14), added back by eq. 24.")
      .def_property_readonly("feature_count", &GprModel::feature_count, "M, the number of basis features.")
      .def("to_dict", [](const GprModel& model) { return FromJson(GprModelToJson(model)); }, "The model file's JSON.")
      .def("__repr__", [](const GprModel& model) {
        const GprHyperparameters& h = model.data().hyperparameters;
        const bool periodic = model.kernel() == GprKernel::kPeriodicSe;
        // PS: ℓ_x is dimensionless (paper eq. 20); DS: a length [m].
        return fmt::format("<GprModel {}: {}ℓ_x {:.3g}{}, ℓ_ẋ {:.3g} m/s; noise σ {:.3g}; {} features, N = {} samples>",
                           GprKernelName(model.kernel()), periodic ? fmt::format("period {:.4g} m, ", h.period) : "",
                           h.length_scale_x, periodic ? "" : " m", h.length_scale_xdot, std::sqrt(h.noise_variance),
                           model.feature_count(), model.data().provenance.sample_count);
      });
  m.def("fit_gpr", &FitGprToArrays, py::arg("x"), py::arg("xdot"), py::arg("d"), py::kw_only(),
        py::arg("kernel") = "PS", py::arg("period") = 0.0225, py::arg("solver") = "weight_space",
        py::arg("estimate_period") = false, py::arg("window") = std::nullopt, py::arg("downsample") = 1,
        py::arg("restarts") = 2, py::arg("seed") = 1,
        "Fits the TISO-GPR by MAP on every sample, as `motionblocks fit-gpr`: x [m], xdot [m/s] and the disturbance "
        "d (e.g. the DOB estimate [N]) as 1-D arrays of one length N. kernel 'PS' (periodic with `period` τ [m], the "
        "pole pitch, in x + SE in ẋ) or 'DS' (SE + SE); solver 'weight_space' (O(N·M²)) or 'exact' (N ≤ 10,000); "
        "`window` (xmin, xmax) [m] trains on that position range; `downsample` keeps every n-th sample. Returns a "
        "GprModel. Raises ValueError for bad samples or options.");
}

}  // namespace mb::python

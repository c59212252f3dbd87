#include "models/gpr/residual_gpr.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "models/diagnosis/effect_registry.h"

namespace mb {
namespace {

// Every stride-th index of [0, n) outside [skip_begin, skip_end), at most `limit` of them.
std::vector<Eigen::Index> TrainingIndices(Eigen::Index n, Eigen::Index skip_begin, Eigen::Index skip_end,
                                          Eigen::Index limit) {
  const Eigen::Index available = n - (skip_end - skip_begin);
  const Eigen::Index stride = std::max<Eigen::Index>(1, (available + limit - 1) / limit);
  std::vector<Eigen::Index> idx;
  idx.reserve(static_cast<std::size_t>(available / stride + 1));
  Eigen::Index seen = 0;
  for (Eigen::Index i = 0; i < n; ++i) {
    if (i >= skip_begin && i < skip_end) continue;
    if (seen++ % stride == 0) idx.push_back(i);
  }
  return idx;
}

GprModel FitOn(const DiagnosisSignals& s, const Eigen::VectorXd& r, const std::vector<Eigen::Index>& idx,
               const GprFitOptions& options) {
  const auto m = static_cast<Eigen::Index>(idx.size());
  Eigen::VectorXd x(m), v(m), y(m);
  for (Eigen::Index k = 0; k < m; ++k) {
    const Eigen::Index i = idx[static_cast<std::size_t>(k)];
    x(k) = s.position(i);
    v(k) = s.velocity(i);
    y(k) = r(i);
  }
  return FitGpr(x, v, y, options);
}

}  // namespace

nlohmann::json ResidualGprResult::ToJson() const {
  return {{"useful", useful},
          {"kernel", std::string(GprKernelName(kernel))},
          {"period_m", kernel == GprKernel::kPeriodicSe ? nlohmann::json(period) : nlohmann::json(nullptr)},
          {"heldout_rmse_before", heldout_rmse_before},
          {"heldout_rmse_after", heldout_rmse_after},
          {"heldout_share", heldout_share},
          {"rmse_after", rmse_after},
          {"description", description}};
}

ResidualGprResult FitResidualGpr(const DiagnosisSignals& signals, const Eigen::Ref<const Eigen::VectorXd>& residual,
                                 const ResidualGprOptions& options) {
  signals.Validate();
  const Eigen::Index n = signals.size();
  if (residual.size() != n) {
    throw std::invalid_argument(
        fmt::format("FitResidualGpr: the residual has {} samples, the signals {}", residual.size(), n));
  }
  if (!residual.allFinite()) throw std::invalid_argument("FitResidualGpr: the residual holds NaN or Inf");
  if (options.folds < 2) throw std::invalid_argument(fmt::format("FitResidualGpr: folds = {} must be >= 2", options.folds));
  if (options.folds > n / 64) {  // a record too short: said in the user's terms, as commands and Python show it
    throw std::invalid_argument(fmt::format("the record has {} samples, too few for the {}-fold cross-validation that "
                                            "judges it (at least {})",
                                            n, options.folds, 64 * options.folds));
  }
  if (!(options.min_gain >= 0.0 && options.min_gain < 1.0)) {
    throw std::invalid_argument(fmt::format("FitResidualGpr: min_gain = {} must lie in [0, 1)", options.min_gain));
  }
  if (!(options.period >= 0.0) || !std::isfinite(options.period)) {
    throw std::invalid_argument(fmt::format("FitResidualGpr: period = {} must be >= 0 (0 = none)", options.period));
  }
  if (options.max_training_samples < 64) {
    throw std::invalid_argument(fmt::format("FitResidualGpr: max_training_samples = {} must be >= 64",
                                            options.max_training_samples));
  }

  ResidualGprResult result;
  result.kernel = options.kernel.value_or(options.period > 0.0 ? GprKernel::kPeriodicSe : GprKernel::kSeSe);
  if (result.kernel == GprKernel::kPeriodicSe && !(options.period > 0.0)) {
    throw std::invalid_argument("FitResidualGpr: the \"PS\" kernel needs a period > 0 [m] (the pole pitch, or the "
                                "residual's position-periodogram peak)");
  }
  result.period = result.kernel == GprKernel::kPeriodicSe ? options.period : 0.0;
  GprFitOptions fit;
  fit.kernel = result.kernel;
  if (result.period > 0.0) {
    fit.period = result.period;
  } else if (const double travel = signals.position.maxCoeff() - signals.position.minCoeff(); travel > 0.0) {
    // DS: the position's length-scale prior is set from a period (GprFitOptions::period, default the paper's 22.5 mm
    // pole pitch); a tenth of the record's travel instead, in the position's own unit (rad, rev, mm alike).
    fit.period = 0.1 * travel;
  }
  fit.restarts = options.restarts;
  fit.source = "residual of the diagnosis (non-parametric fallback)";

  const Eigen::VectorXd r = residual;
  double sse_before = 0.0;
  double sse_after = 0.0;
  for (Eigen::Index b = 0; b < options.folds; ++b) {
    const Eigen::Index begin = b * n / options.folds;
    const Eigen::Index end = (b + 1) * n / options.folds;
    const GprModel model = FitOn(signals, r, TrainingIndices(n, begin, end, options.max_training_samples), fit);
    for (Eigen::Index i = begin; i < end; ++i) {
      const double e = r(i) - model.PredictPosteriorMean(signals.position(i), signals.velocity(i));
      sse_before += r(i) * r(i);
      sse_after += e * e;
    }
  }
  const double count = static_cast<double>(n);
  result.heldout_rmse_before = std::sqrt(sse_before / count);
  result.heldout_rmse_after = std::sqrt(sse_after / count);
  result.heldout_share = sse_before > 0.0 ? 1.0 - sse_after / sse_before : 0.0;
  result.useful = result.heldout_share >= options.min_gain;

  const std::string kernel_text = result.kernel == GprKernel::kPeriodicSe
                                      ? (options.position_unit == "m"
                                             ? fmt::format("PS, period {:.4g} mm", 1e3 * result.period)
                                             : fmt::format("PS, period {:.4g} {}", result.period, options.position_unit))
                                      : std::string("DS");
  if (result.useful) {
    GprModel model = FitOn(signals, r, TrainingIndices(n, 0, 0, options.max_training_samples), fit);
    double sse = 0.0;
    for (Eigen::Index i = 0; i < n; ++i) {
      const double e = r(i) - model.PredictPosteriorMean(signals.position(i), signals.velocity(i));
      sse += e * e;
    }
    result.rmse_after = std::sqrt(sse / count);
    result.model = std::move(model);
    result.description = fmt::format(
        "A TISO-GPR on position and velocity ({}) explains {:.1f} % of the remaining residual energy on held-out "
        "blocks (RMSE {:.4g} → {:.4g}): something still depends on the motion state that no catalogue effect "
        "names. Add a gpr block with the fitted model to the diagram, or look for the physics in its shape.",
        kernel_text, 100.0 * result.heldout_share, result.heldout_rmse_before, result.heldout_rmse_after);
  } else {
    result.rmse_after = std::sqrt(r.squaredNorm() / count);
    result.description = fmt::format(
        "A TISO-GPR on position and velocity ({}) explains {:.1f} % of the remaining residual energy on held-out "
        "blocks: what is left does not depend on the motion state (noise, or an effect of time).",
        kernel_text, 100.0 * std::max(0.0, result.heldout_share));
  }
  return result;
}

ResidualGprResult FitResidualGprAfterDiagnosis(const DiagnosisSignals& signals, const BaseRegressors& base,
                                               const DiagnosisResult& diagnosis, ResidualGprOptions options) {
  if (options.period == 0.0 && !options.kernel) {
    for (const auto& e : diagnosis.effects) {
      if (LookupEffect(e.effect).traits.periodicity == Periodicity::kPosition && e.parameters.count("period")) {
        options.period = e.parameters.at("period");
        break;
      }
    }
  }
  options.position_unit = diagnosis.position_unit;
  const Eigen::VectorXd left = signals.residual - PredictCorrection(diagnosis, signals, base);
  return FitResidualGpr(signals, left, options);
}

}  // namespace mb

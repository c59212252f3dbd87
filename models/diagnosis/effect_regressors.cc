#include "models/diagnosis/effect_regressors.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include <fmt/format.h>

#include "models/diagnosis/effect_registry.h"
#include "models/physics/fourier_series.h"

namespace mb {

double RequiredParameter(const EffectInstance& e, const char* key) {
  const auto it = e.parameters.find(key);
  if (it == e.parameters.end() || !std::isfinite(it->second)) {
    throw std::invalid_argument(fmt::format(
        "effect '{}': parameter '{}' is missing or not finite; set it (SI units)", e.name, key));
  }
  return it->second;
}

double PositiveParameter(const EffectInstance& e, const char* key) {
  const double v = RequiredParameter(e, key);
  if (!(v > 0.0)) {
    throw std::invalid_argument(fmt::format("effect '{}': parameter '{}' = {} must be positive", e.name, key, v));
  }
  return v;
}

int HarmonicsParameter(const EffectInstance& e) {
  const auto it = e.parameters.find("harmonics");
  if (it == e.parameters.end()) return 1;
  const double h = it->second;
  if (!(h >= 1.0 && h <= 50.0) || h != std::round(h)) {
    throw std::invalid_argument(fmt::format(
        "effect '{}': parameter 'harmonics' = {} must be an integer in 1..50", e.name, h));
  }
  return static_cast<int>(h);
}

const Eigen::VectorXd& CommandOf(const EffectInstance& e, const DiagnosisSignals& s,
                                 const Eigen::VectorXd& equation_error) {
  if (s.drive_force.size() == s.size()) return s.drive_force;
  if (equation_error.size() != s.size()) {
    throw std::invalid_argument(fmt::format(
        "effect '{}' needs the command: the logged command (equation-error mode) or the model's drive force "
        "(simulation mode), which is absent",
        e.name));
  }
  return equation_error;
}

Eigen::VectorXd CommandPathLoad(const EffectInstance& e, const DiagnosisSignals& s,
                                const std::function<Eigen::VectorXd(const Eigen::VectorXd& command)>& lost) {
  if (s.drive_force.size() != s.size()) {
    throw std::invalid_argument(fmt::format(
        "effect '{}' in simulation mode needs the model's drive force (DiagnosisSignals::drive_force), which is absent",
        e.name));
  }
  const Eigen::VectorXd& u0 = s.drive_force;
  Eigen::VectorXd load = lost(u0);
  if (!s.drive_force_response) return load;
  // Anderson acceleration of depth kDepth (Walker & Ni, SIAM J. Numer. Anal. 49, 2011): the next iterate mixes the last
  // ones so that their residuals f = G(L) − L cancel best in least squares; a plain fixed-point step contracted by only
  // ~0.75 per step on a 4 ms lag under a 15 Hz loop.
  constexpr int kDepth = 3;
  const auto g = [&](const Eigen::VectorXd& l) { return lost(u0 + s.drive_force_response->Apply(l).col(0)); };
  std::vector<Eigen::VectorXd> iterates, residuals;  // the last kDepth + 1 of each
  double best = std::numeric_limits<double>::infinity();
  Eigen::VectorXd best_load = load;
  for (int k = 0; k < kCommandPathIterations; ++k) {
    const Eigen::VectorXd mapped = g(load);
    const Eigen::VectorXd f = mapped - load;
    const double size = f.norm();
    if (!std::isfinite(size)) break;
    if (size < best) {
      best = size;
      best_load = mapped;
    }
    if (size <= 1e-4 * mapped.norm()) break;
    iterates.push_back(mapped);
    residuals.push_back(f);
    if (static_cast<int>(iterates.size()) > kDepth + 1) {
      iterates.erase(iterates.begin());
      residuals.erase(residuals.begin());
    }
    const auto m = static_cast<Eigen::Index>(residuals.size()) - 1;
    if (m == 0) {
      load = mapped;
      continue;
    }
    Eigen::MatrixXd df(f.size(), m), dg(f.size(), m);
    for (Eigen::Index j = 0; j < m; ++j) {
      df.col(j) = residuals[static_cast<std::size_t>(j + 1)] - residuals[static_cast<std::size_t>(j)];
      dg.col(j) = iterates[static_cast<std::size_t>(j + 1)] - iterates[static_cast<std::size_t>(j)];
    }
    const Eigen::VectorXd gamma = df.colPivHouseholderQr().solve(f);
    load = mapped - dg * gamma;
  }
  return best_load;
}

const Eigen::VectorXd& NeedModelOutput(const EffectInstance& e, const DiagnosisSignals& s) {
  if (s.model_output.size() == 0) {
    throw std::invalid_argument(fmt::format(
        "effect '{}' needs the model output ŷ (DiagnosisSignals::model_output), which is absent", e.name));
  }
  return s.model_output;
}

Eigen::VectorXd SignDeadBand(const Eigen::VectorXd& v, double dead_band) {
  return v.unaryExpr([dead_band](double x) { return std::abs(x) <= dead_band ? 0.0 : (x > 0.0 ? 1.0 : -1.0); });
}

Eigen::VectorXd PlayOperator(const Eigen::VectorXd& x, double half_width) {
  Eigen::VectorXd y(x.size());
  double far = x.size() > 0 ? x(0) : 0.0;
  for (Eigen::Index i = 0; i < x.size(); ++i) {
    far = std::clamp(far, x(i) - half_width, x(i) + half_width);
    y(i) = far;
  }
  return y;
}

std::vector<double> LogSpaced(double lo, double hi, int n) {
  std::vector<double> out(static_cast<std::size_t>(std::max(n, 1)), lo);
  for (int i = 1; i < n; ++i) {
    out[static_cast<std::size_t>(i)] = lo * std::pow(hi / lo, static_cast<double>(i) / (n - 1));
  }
  return out;
}

EffectRegressors SingleColumn(const std::string& effect, Eigen::VectorXd column) {
  EffectRegressors out;
  out.columns = std::move(column);
  out.column_names = {effect};
  return out;
}

EffectRegressors PeriodicColumns(const Eigen::VectorXd& z, double period, int harmonics, const std::string& prefix,
                                 const Eigen::VectorXd* scale) {
  EffectRegressors out;
  out.columns = FourierDesignMatrix(z, period, harmonics, scale);
  for (int k = 1; k <= harmonics; ++k) {
    out.column_names.push_back(fmt::format("{}.cos{}", prefix, k));
    out.column_names.push_back(fmt::format("{}.sin{}", prefix, k));
  }
  return out;
}

void RefinePositionPeriod(EffectTraits* traits) {
  constexpr double kMinCycles = 3.0;  // CatalogueOptions::min_position_cycles_with_harmonics' default
  traits->refined_parameter = "period";
  traits->refinement_range = 1.1;
  traits->refined_upper_bound = [](const DiagnosisSignals& s) {
    return s.position.size() > 0 ? (s.position.maxCoeff() - s.position.minCoeff()) / kMinCycles : 0.0;
  };
}

EffectRegressors InertiaColumns(const Eigen::VectorXd& z, const Eigen::VectorXd& v, const Eigen::VectorXd& a,
                                double period, int harmonics, const std::string& prefix) {
  EffectRegressors out = PeriodicColumns(z, period, harmonics, prefix, &a);
  const Eigen::VectorXd half_v2 = 0.5 * v.cwiseAbs2();
  const Eigen::MatrixXd kinetic = FourierDesignMatrix(z, period, harmonics, &half_v2);  // ½v²·cos, ½v²·sin
  for (int k = 1; k <= harmonics; ++k) {
    const double wavenumber = 2.0 * std::numbers::pi * k / period;  // d/dz of cos(kθ) is −(2πk/P)·sin(kθ)
    out.columns.col(2 * (k - 1)) -= wavenumber * kinetic.col(2 * (k - 1) + 1);
    out.columns.col(2 * (k - 1) + 1) += wavenumber * kinetic.col(2 * (k - 1));
  }
  return out;
}

EffectRegressors PowerColumns(const Eigen::VectorXd& z, double center, double half_range, int degree,
                              const std::string& prefix, const Eigen::VectorXd* scale) {
  EffectRegressors out;
  out.columns.resize(z.size(), degree);
  const Eigen::ArrayXd xi = (z.array() - center) / half_range;
  Eigen::ArrayXd power = Eigen::ArrayXd::Ones(z.size());
  if (scale) power = scale->array();
  for (int j = 0; j < degree; ++j) {
    power *= xi;
    out.columns.col(j) = power.matrix();
    out.column_names.push_back(fmt::format("{}.p{}", prefix, j + 1));
  }
  return out;
}

}  // namespace mb

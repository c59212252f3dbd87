// The third factor's columns, words and parts (amplitude_factor.h).
#include "models/diagnosis/amplitude_factor.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>
#include <vector>

#include <fmt/format.h>

namespace mb {
namespace {

double Required(const EffectInstance& effect, const char* key) {
  const auto it = effect.parameters.find(key);
  if (it == effect.parameters.end() || !std::isfinite(it->second)) {
    throw std::invalid_argument(fmt::format("effect '{}': its third factor has no finite '{}'", effect.name, key));
  }
  return it->second;
}

}  // namespace

const Eigen::VectorXd& AmplitudeSource(double with, const DiagnosisSignals& signals) {
  if (with == -1.0) return signals.time;
  if (with >= 0.0 && with == std::floor(with) && with < static_cast<double>(signals.extra_columns.size())) {
    return signals.extra_columns[static_cast<std::size_t>(with)];
  }
  throw std::invalid_argument(fmt::format(
      "a third factor of source {} names no unread log column of this record (it has {}): a record carried to another "
      "must hold the same columns",
      with, signals.extra_columns.size()));
}

EffectRegressors WithAmplitudeFactor(EffectRegressors reg, const EffectInstance& effect,
                                     const DiagnosisSignals& signals) {
  const auto with = effect.parameters.find(kAmplitudeWith);
  if (with == effect.parameters.end()) return reg;
  const double origin = Required(effect, kAmplitudeOrigin), scale = Required(effect, kAmplitudeScale);
  if (!(scale > 0.0)) {
    throw std::invalid_argument(fmt::format("effect '{}': its third factor's scale {} must be > 0", effect.name, scale));
  }
  const Eigen::Index k = reg.columns.cols();
  const Eigen::VectorXd weights = AmplitudeWeights(effect.parameters);
  if (weights.size() != k) {
    throw std::invalid_argument(fmt::format("effect '{}': its third factor has {} weights for {} columns", effect.name,
                                            weights.size(), k));
  }
  const Eigen::VectorXd z = (AmplitudeSource(with->second, signals).array() - origin) / scale;
  reg.columns.conservativeResize(Eigen::NoChange, k + 1);
  reg.columns.col(k) = (reg.columns.leftCols(k) * weights).cwiseProduct(z);
  reg.column_names.push_back(effect.name + kAmplitudeColumnSuffix);
  return reg;
}

std::optional<EffectInstance> WithAmplitudeSource(const EffectInstance& effect, double with,
                                                  const Eigen::VectorXd& weights, const DiagnosisSignals& signals) {
  const Eigen::VectorXd& z = AmplitudeSource(with, signals);
  const double lo = z.minCoeff(), hi = z.maxCoeff();
  if (!(hi > lo)) return std::nullopt;
  EffectInstance out = effect;
  out.parameters[kAmplitudeWith] = with;
  out.parameters[kAmplitudeOrigin] = 0.5 * (lo + hi);
  out.parameters[kAmplitudeScale] = 0.5 * (hi - lo);
  for (Eigen::Index j = 0; j < weights.size(); ++j) out.parameters[kAmplitudeWeight + std::to_string(j)] = weights(j);
  return out;
}

Eigen::VectorXd AmplitudeWeights(const std::map<std::string, double>& parameters) {
  std::vector<double> w;
  for (std::size_t j = 0;; ++j) {
    const auto it = parameters.find(kAmplitudeWeight + std::to_string(j));
    if (it == parameters.end()) break;
    w.push_back(it->second);
  }
  return Eigen::Map<const Eigen::VectorXd>(w.data(), static_cast<Eigen::Index>(w.size()));
}

double AmplitudeChange(const Eigen::MatrixXd& columns, const Eigen::VectorXd& coefficients,
                       const Eigen::VectorXd& weights) {
  const Eigen::Index k = weights.size();
  const Eigen::VectorXd force = columns.leftCols(k) * coefficients.head(k);
  const double energy = force.squaredNorm();
  return energy > 0.0 ? coefficients(k) * force.dot(columns.leftCols(k) * weights) / energy : 0.0;
}

std::string AmplitudeWords(const std::map<std::string, double>& parameters, const std::string& column) {
  const auto with = parameters.find(kAmplitudeWith);
  const auto slope = parameters.find(kAmplitudeSlope);
  const auto scale = parameters.find(kAmplitudeScale);
  if (with == parameters.end() || slope == parameters.end() || scale == parameters.end()) return "";
  const double over_range = 200.0 * slope->second * scale->second;  // from z₀ − h to z₀ + h
  if (with->second < 0.0) {
    return fmt::format("Its amplitude changes with time: {:+.3g} % per second ({:+.3g} % over the record)",
                       100.0 * slope->second, over_range);
  }
  return fmt::format("Its amplitude follows '{}': {:+.3g} % per unit of it ({:+.3g} % over the record's range)",
                     column, 100.0 * slope->second, over_range);
}

AmplitudeParts SplitAmplitudeFactor(const DiagnosedEffect& effect) {
  AmplitudeParts out{effect, std::nullopt};
  const auto with = effect.parameters.find(kAmplitudeWith);
  if (with == effect.parameters.end()) return out;
  const EffectInstance instance{effect.effect, effect.parameters};
  const double origin = Required(instance, kAmplitudeOrigin), scale = Required(instance, kAmplitudeScale);
  const Eigen::VectorXd weights = AmplitudeWeights(effect.parameters);
  const Eigen::Index k = weights.size();
  const auto modulated = std::find(effect.column_names.begin(), effect.column_names.end(),
                                   effect.effect + kAmplitudeColumnSuffix);
  if (modulated == effect.column_names.end() || effect.coefficients.size() != k + 1) {
    throw std::invalid_argument(fmt::format("effect '{}': its third factor's column or coefficients are missing ({} "
                                            "coefficients for {} weights)",
                                            effect.effect, effect.coefficients.size(), k));
  }
  const double gamma = effect.coefficients(k);
  DiagnosedEffect part = effect;
  for (DiagnosedEffect* e : {&out.main, &part}) {
    for (auto it = e->parameters.begin(); it != e->parameters.end();) {
      it = it->first.starts_with("amplitude_") ? e->parameters.erase(it) : std::next(it);
    }
    e->column_names.pop_back();
    e->coefficient_std.resize(0);
  }
  // G·c + γ·G·w·(z − z₀)/h: the pair as it is at z₀, and its part (G·γ·w/h) times z − z₀.
  out.main.coefficients = effect.coefficients.head(k);
  part.coefficients = (gamma / scale) * weights;
  part.parameters[kAmplitudeOrigin] = origin;
  part.description = with->second < 0.0 ? fmt::format("the part of {} that grows with time", effect.effect)
                                        : fmt::format("the part of {} that follows '{}'", effect.effect,
                                                      effect.amplitude_column);
  out.part = std::move(part);
  return out;
}

}  // namespace mb

#pragma once
// The third factor of a product (issue 45, item 3): a chosen pair whose amplitude varies with time or with a log column
// the diagram does not read — "the cogging's amplitude falls 1.1 %/K with magnet_temperature_C". The pair's force
// f = G·w (its columns G, N × k, with the weights w its first fit gave them) is joined by one column f ⊙ z̃, z̃ = (z −
// z₀)/h the time or the column centred on the record and scaled to ±1, so that the pair's force becomes G·c + γ·f·z̃ ≈
// G·c·(1 + γ·z̃): its amplitude, not its shape, follows z (a ripple's phase that drifts is no amplitude). It is linear in
// its coefficients, so the held-out test decides it as every term (ModulateChosenEffects); any effect that is a product
// of the grammar may carry it, through the registry (EffectRegistry::Add wraps every effect's regressors with
// WithAmplitudeFactor), so that a new row of the tables gets it with nothing else written.
// Source: Ljung, System Identification (2nd ed., 1999), §5.2 (a parameter that varies: a linear model in the
// parameter's scheduling variable); docs/diagnosis.md, "A third factor".

#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>

#include "models/diagnosis/diagnosis.h"
#include "models/diagnosis/effect_catalogue.h"

namespace mb {

/// The instance parameters of a third factor (EffectInstance::parameters; absent = none):
/// the source, −1 for time or k ≥ 0 for unread column k (DiagnosisSignals::extra_columns);
inline constexpr const char* kAmplitudeWith = "amplitude_with";
/// z₀, the source's value where the factor is 1 [s, or the column's unit]: the middle of the diagnosed record;
inline constexpr const char* kAmplitudeOrigin = "amplitude_origin";
/// h > 0, the scale of z̃ = (z − z₀)/h [same unit]: half the source's range on the diagnosed record;
inline constexpr const char* kAmplitudeScale = "amplitude_scale";
/// w_j, the weight of the pair's column j in its force f = G·w: "amplitude_weight.0", "amplitude_weight.1", …;
inline constexpr const char* kAmplitudeWeight = "amplitude_weight.";
/// reported: γ/h, the amplitude's relative change per unit of the source [1/s, or 1/(the column's unit)].
inline constexpr const char* kAmplitudeSlope = "amplitude_slope";
/// The name of the modulated column f ⊙ z̃: "<effect>:amplitude".
inline constexpr const char* kAmplitudeColumnSuffix = ":amplitude";

/// The source z of the factor `with` (−1: time; k: unread column k) on `signals` (N). Throws std::invalid_argument
/// when k names no unread column.
const Eigen::VectorXd& AmplitudeSource(double with, const DiagnosisSignals& signals);

/// `reg` (N × k) joined by the column (G·w) ⊙ z̃, named "<effect>:amplitude", when `effect` carries a third factor
/// (kAmplitudeWith), else `reg` itself. Throws std::invalid_argument when the factor's parameters are incomplete (a
/// weight per column), h ≤ 0, or the source is absent.
EffectRegressors WithAmplitudeFactor(EffectRegressors reg, const EffectInstance& effect,
                                     const DiagnosisSignals& signals);

/// `effect` with a third factor of source `with` (−1 time, k column k), centred and scaled on `signals` (z₀ the middle
/// of the source's range, h half of it), its force's weights `weights` (k, the pair's fitted coefficients). nullopt
/// when the source does not vary.
std::optional<EffectInstance> WithAmplitudeSource(const EffectInstance& effect, double with,
                                                  const Eigen::VectorXd& weights, const DiagnosisSignals& signals);

/// The pair's weights w (k) of an instance with a third factor; empty when it has none.
Eigen::VectorXd AmplitudeWeights(const std::map<std::string, double>& parameters);

/// The relative change of the amplitude per unit of z̃ of a pair with columns G (N × k), coefficients `coefficients`
/// (k + 1: c, then γ) and weights w: ⟨G·c, γ·G·w⟩/⟨G·c, G·c⟩, the modulated part's least-squares share along the force
/// (γ when c = w). 0 when the force is 0.
double AmplitudeChange(const Eigen::MatrixXd& columns, const Eigen::VectorXd& coefficients,
                       const Eigen::VectorXd& weights);

/// The words for a diagnosed effect's third factor: "Its amplitude follows 'magnet_temperature_C': −1.1 % per unit of
/// it (−8.8 % over the record's range)", "Its amplitude changes with time: +2.3 % per second (+25 % over the record)";
/// "" when it has none. `column` is the source column's name ("" for time).
std::string AmplitudeWords(const std::map<std::string, double>& parameters, const std::string& column);

/// A diagnosed effect with a third factor as the two parts a diagram adds (tools/workflow/suggest.cc): `main`, the pair
/// as it is where z = z₀ (its columns G with coefficients c), and `part`, its share proportional to z − z₀ (the same
/// columns' names, coefficients γ·w/h, and the parameter kAmplitudeOrigin z₀), which the diagram multiplies by z − z₀
/// (a clock, or the column's input connector, less a constant z₀). Neither carries the factor's other parameters.
/// `part` is nullopt when the effect has no third factor (and `main` is the effect). Throws std::invalid_argument when
/// the factor's column or coefficients are missing.
struct AmplitudeParts {
  DiagnosedEffect main;
  std::optional<DiagnosedEffect> part;
};
AmplitudeParts SplitAmplitudeFactor(const DiagnosedEffect& effect);

}  // namespace mb

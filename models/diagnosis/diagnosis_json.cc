// The diagnosis as JSON for compare.json and improve.json (DiagnosisResult::ToJson, diagnosis.h): every field of the
// result, Eigen vectors as arrays, a non-finite condition number as null. Source: docs/diagnosis.md (the report's
// fields).
#include "models/diagnosis/diagnosis.h"

#include <cmath>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "models/diagnosis/effect_registry.h"

namespace mb {

namespace {
nlohmann::json ToJsonArray(const Eigen::VectorXd& v) { return std::vector<double>(v.data(), v.data() + v.size()); }
nlohmann::json PeaksJson(const std::vector<PeriodogramPeak>& peaks) {
  nlohmann::json out = nlohmann::json::array();
  for (const auto& p : peaks) {
    out.push_back({{"period", p.period}, {"power", p.power}, {"amplitude", p.amplitude},
                   {"false_alarm_probability", p.false_alarm_probability}, {"significant", p.significant},
                   {"harmonic_of", p.harmonic_of}, {"harmonic_order", p.harmonic_order}});
  }
  return out;
}
// An effect's parameters, a count (a parameter without a unit in the effect registry, whole-valued: the harmonics)
// as an integer, not 2.0.
nlohmann::json ParametersJson(const std::string& effect, const std::map<std::string, double>& parameters) {
  nlohmann::json out = parameters;
  const EffectType* type = EffectRegistry::Global().Find(effect);
  if (!type) return out;
  for (const auto& p : type->parameters) {
    const auto it = parameters.find(p.name);
    if (it == parameters.end() || !p.unit.empty()) continue;
    if (std::abs(it->second) < 1e15 && it->second == std::round(it->second)) {
      out[p.name] = static_cast<long long>(it->second);
    }
  }
  return out;
}
nlohmann::json WhitenessJson(const AutocorrelationTest& a) {
  return {{"ljung_box_q", a.ljung_box_q}, {"p_value", a.p_value}, {"white", a.white}, {"band99", a.band99},
          {"autocorrelation", ToJsonArray(a.autocorrelation)}};
}
}  // namespace

nlohmann::json DiagnosedEffect::ParametersJson() const { return mb::ParametersJson(effect, parameters); }

nlohmann::json DiagnosisResult::ToJson() const {
  nlohmann::json j;
  j["missing_effect_found"] = missing_effect_found;
  j["position_time_indistinguishable"] = position_time_indistinguishable;
  j["summary"] = summary;
  j["notes"] = notes;
  j["rmse_before"] = rmse_before;
  j["rmse_base_refit"] = rmse_base_refit;
  j["rmse_after"] = rmse_after;
  j["heldout_rmse_base"] = heldout_rmse_base;
  j["heldout_rmse_after"] = heldout_rmse_after;
  j["explained_share"] = explained_share;
  j["relevance"] = nlohmann::json::array();
  for (const SignalRelevance& s : relevance) j["relevance"].push_back({{"signal", s.signal}, {"heldout_share", s.heldout_share}});
  j["noise_floor"] = {{"rms", noise_floor.rms},
                      {"white_rms", noise_floor.white_rms},
                      {"quantization_rms", noise_floor.quantization_rms},
                      {"position_step", noise_floor.position_step},
                      {"band_hz", {noise_floor.band_low_hz, noise_floor.band_high_hz}}};
  j["condition_number"] = std::isfinite(condition_number) ? nlohmann::json(condition_number) : nlohmann::json(nullptr);
  nlohmann::json base = nlohmann::json::array();
  for (std::size_t i = 0; i < base_names.size(); ++i) {
    const auto ii = static_cast<Eigen::Index>(i);
    base.push_back({{"name", base_names[i]}, {"correction", base_coefficients(ii)}, {"std", base_coefficient_std(ii)}});
  }
  j["base_parameters"] = base;
  nlohmann::json effs = nlohmann::json::array();
  for (const auto& e : effects) {
    nlohmann::json coefs = nlohmann::json::array();
    for (std::size_t i = 0; i < e.column_names.size(); ++i) {
      const auto ii = static_cast<Eigen::Index>(i);
      coefs.push_back({{"column", e.column_names[i]}, {"value", e.coefficients(ii)}, {"std", e.coefficient_std(ii)}});
    }
    effs.push_back({{"effect", e.effect}, {"score", e.score}, {"cumulative_share", e.cumulative_share},
                    {"base_share", e.base_share}, {"selection_order", e.selection_order},
                    {"parameters", e.ParametersJson()}, {"coefficients", coefs},
                    {"contribution_rms", e.contribution_rms},
                    {"time_range", {e.time_range[0], e.time_range[1]}},
                    {"position_range", {e.position_range[0], e.position_range[1]}},
                    {"velocity_range", {e.velocity_range[0], e.velocity_range[1]}}, {"description", e.description}});
    if (!e.replaced_parameter.empty()) effs.back()["replaces"] = e.replaced_parameter;
    if (!e.log_column.empty()) effs.back()["log_column"] = e.log_column;
    if (!e.amplitude_column.empty()) effs.back()["amplitude_column"] = e.amplitude_column;
    if (!e.multiplier.empty()) {  // the grammar's pair, beside the effect's name (issue 45)
      effs.back()["multiplier"] = e.multiplier;
      effs.back()["modulator"] = e.modulator;
    }
    if (!e.alike.empty()) effs.back()["alike"] = e.alike;  // what the record cannot tell it from
    if (!e.time_intervals.empty()) effs.back()["time_intervals"] = e.time_intervals;  // [low, high] s per change time
  }
  j["effects"] = effs;
  j["whiteness_before"] = WhitenessJson(whiteness_before);
  j["whiteness_after"] = WhitenessJson(whiteness_after);
  j["position_peaks"] = PeaksJson(position_peaks);
  j["time_peaks"] = PeaksJson(time_peaks);
  nlohmann::json cands = nlohmann::json::array();
  for (const auto& c : candidates) {
    cands.push_back({{"effect", c.name}, {"parameters", ParametersJson(c.name, c.parameters)}});
  }
  j["candidates"] = cands;
  j["friction_law"] = friction_law;
  j["robust_weight_share"] = robust_weight_share;
  return j;
}

}  // namespace mb

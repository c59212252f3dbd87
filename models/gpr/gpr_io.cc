// GCC 12 at -O3 reports a false -Warray-bounds inside libstdc++'s _Rb_tree when nlohmann::json
// objects are built from initializer lists (GCC bug 107852 family); nothing here indexes arrays.
#pragma GCC diagnostic ignored "-Warray-bounds"

#include "models/gpr/gpr_io.h"

#include "engine/output_file.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include "engine/closest_names.h"
#include "engine/file_error.h"
#include "engine/input_file.h"
#include "engine/json_limits.h"
#include "engine/text_excerpt.h"

#include <Eigen/Eigenvalues>
#include <fmt/format.h>
#include <fmt/ranges.h>

namespace mb {
namespace {

using nlohmann::json;

json Range(GprRange r) { return json::array({r.min, r.max}); }

json Domain(const HilbertDomain& d) {
  return {{"center", d.center}, {"half_width", d.half_width}, {"count", d.count}};
}

json MaybeInfinite(double v) { return std::isinf(v) ? json("inf") : json(v); }

// Reads typed values by JSON pointer and collects every problem instead of stopping at the first.
class Reader {
 public:
  explicit Reader(const json& root) : root_(root) {}

  const json* Find(const std::string& pointer) {
    try {
      return &root_.at(json::json_pointer(pointer));
    } catch (const json::exception&) {
      errors_.push_back(pointer + ": missing");
      return nullptr;
    }
  }

  double Number(const std::string& pointer, bool positive = false, bool allow_inf = false) {
    const json* v = Find(pointer);
    if (v == nullptr) return 0.0;
    if (allow_inf && v->is_string() && v->get<std::string>() == "inf") {
      return std::numeric_limits<double>::infinity();
    }
    if (!v->is_number()) {
      errors_.push_back(pointer + ": must be a number, but is " + TypeText(*v));
      return 0.0;
    }
    const double d = v->get<double>();
    if (!allow_inf && !std::isfinite(d)) errors_.push_back(pointer + ": must be a finite number");
    if (positive && !(d > 0.0)) errors_.push_back(pointer + ": must be > 0, got " + std::to_string(d));
    return d;
  }

  int Integer(const std::string& pointer, int min_value) {
    const json* v = Find(pointer);
    if (v == nullptr) return 0;
    if (!v->is_number_integer()) {
      errors_.push_back(pointer + ": must be an integer, but is " + TypeText(*v));
      return 0;
    }
    const auto i = v->get<long long>();
    if (i < min_value || i > std::numeric_limits<int>::max()) {
      errors_.push_back(pointer + ": must be an integer >= " + std::to_string(min_value) +
                        ", got " + std::to_string(i));
      return 0;
    }
    return static_cast<int>(i);
  }

  std::string String(const std::string& pointer) {
    const json* v = Find(pointer);
    if (v == nullptr) return {};
    if (!v->is_string()) {
      errors_.push_back(pointer + ": must be a string, but is " + TypeText(*v));
      return {};
    }
    return v->get<std::string>();
  }

  bool Boolean(const std::string& pointer) {
    const json* v = Find(pointer);
    if (v == nullptr) return false;
    if (!v->is_boolean()) {
      errors_.push_back(pointer + ": must be true or false, but is " + TypeText(*v));
      return false;
    }
    return v->get<bool>();
  }

  // An array of numbers; `expected` < 0 accepts any length.
  Eigen::VectorXd Numbers(const std::string& pointer, Eigen::Index expected) {
    const json* v = Find(pointer);
    if (v == nullptr) return {};
    if (!v->is_array()) {
      errors_.push_back(pointer + ": must be an array of numbers, but is " + TypeText(*v));
      return {};
    }
    if (expected >= 0 && static_cast<Eigen::Index>(v->size()) != expected) {
      errors_.push_back(pointer + ": must have " + std::to_string(expected) + " entries, has " +
                        std::to_string(v->size()));
      return {};
    }
    Eigen::VectorXd out(static_cast<Eigen::Index>(v->size()));
    for (std::size_t i = 0; i < v->size(); ++i) {
      const json& e = (*v)[i];
      if (!e.is_number()) {
        errors_.push_back(pointer + "/" + std::to_string(i) + ": must be a number, but is " +
                          TypeText(e));
        return {};
      }
      out(static_cast<Eigen::Index>(i)) = e.get<double>();
      if (!std::isfinite(out(static_cast<Eigen::Index>(i)))) {
        errors_.push_back(pointer + "/" + std::to_string(i) + ": must be a finite number");
        return {};
      }
    }
    return out;
  }

  GprRange ReadRange(const std::string& pointer) {
    const Eigen::VectorXd v = Numbers(pointer, 2);
    if (v.size() != 2) return {};
    if (v(1) < v(0)) errors_.push_back(pointer + ": must be [min, max] with min <= max");
    return {v(0), v(1)};
  }

  HilbertDomain ReadDomain(const std::string& pointer) {
    HilbertDomain d;
    d.center = Number(pointer + "/center");
    d.half_width = Number(pointer + "/half_width", true);
    d.count = Integer(pointer + "/count", 1);
    return d;
  }

  void Fail(std::string message) { errors_.push_back(std::move(message)); }
  const std::vector<std::string>& errors() const { return errors_; }

 private:
  static std::string TypeText(const json& v) {
    return v.is_null() ? std::string("null (NaN and infinity are not valid here)")
                       : std::string(v.type_name());
  }
  const json& root_;
  std::vector<std::string> errors_;
};

std::string FormatNumber(double value) { return std::isnan(value) ? "NaN" : fmt::format("{:.6g}", value); }

[[noreturn]] void Throw(std::string_view origin, const std::vector<std::string>& errors) {
  std::string message = std::string(origin) + ": invalid GPR model file:";
  for (const auto& e : errors) message += "\n  " + e;
  throw std::invalid_argument(message);
}

}  // namespace

json GprModelToJson(const GprModel& model) {
  const GprModelData& m = model.data();
  const GprHyperparameters& hp = m.hyperparameters;
  json j;
  j["format"] = kGprModelFormat;
  j["version"] = kGprModelFileVersion;
  j["kernel"] = GprKernelName(m.kernel);
  j["hyperparameters"] = {{"signal_variance_x", hp.signal_variance_x},
                          {"length_scale_x", hp.length_scale_x},
                          {"signal_variance_xdot", hp.signal_variance_xdot},
                          {"length_scale_xdot", hp.length_scale_xdot},
                          {"noise_variance", hp.noise_variance},
                          {"period", hp.period}};
  j["mean"] = m.mean;
  j["trained_range"] = {{"x", Range(m.x_range)}, {"xdot", Range(m.xdot_range)}};
  json basis;
  if (m.kernel == GprKernel::kPeriodicSe) {
    basis["harmonics"] = m.basis.harmonics;
    basis["period"] = m.basis.period;
  } else {
    basis["x_domain"] = Domain(m.basis.x_domain);
  }
  basis["xdot_domain"] = Domain(m.basis.xdot_domain);
  j["basis"] = basis;
  j["weights"] = std::vector<double>(m.weights.data(), m.weights.data() + m.weights.size());
  std::vector<double> lower;
  for (Eigen::Index r = 0; r < m.weight_covariance.rows(); ++r) {
    for (Eigen::Index c = 0; c <= r; ++c) lower.push_back(m.weight_covariance(r, c));
  }
  j["weight_covariance_lower"] = lower;
  const GprProvenance& p = m.provenance;
  json priors = json::object();
  for (int i = 0; i < kGprParameterCount; ++i) {
    const auto& prior = p.priors[static_cast<std::size_t>(i)];
    priors[std::string(GprParameterName(i))] = {{"median", prior.median},
                                                {"log_sd", MaybeInfinite(prior.log_sd)},
                                                {"lower", prior.lower},
                                                {"upper", MaybeInfinite(prior.upper)}};
  }
  j["provenance"] = {{"created_utc", p.created_utc},
                     {"library_version", p.library_version},
                     {"solver", p.solver},
                     {"source", p.source},
                     {"sample_count", p.sample_count},
                     {"log_marginal_likelihood", p.log_marginal_likelihood},
                     {"log_posterior", p.log_posterior},
                     {"fit_seconds", p.fit_seconds},
                     {"tolerance", p.tolerance},
                     {"period_estimated", p.period_estimated},
                     {"priors", priors}};
  if (!p.position_column.empty()) j["provenance"]["position_column"] = p.position_column;
  if (!p.velocity_column.empty()) j["provenance"]["velocity_column"] = p.velocity_column;
  return j;
}

namespace {

// /format and /version: a motionblocks GPR model of the version this build reads.
void CheckHeader(const json& j, std::string_view origin) {
  Reader header(j);
  const std::string format = header.String("/format");
  const int version = header.Integer("/version", 0);
  if (!header.errors().empty()) Throw(origin, header.errors());
  if (format != kGprModelFormat) {
    Throw(origin, {"/format: expected \"" + std::string(kGprModelFormat) + "\", got \"" + format +
                   "\" (not a motionblocks GPR model)"});
  }
  if (version != kGprModelFileVersion) {
    Throw(origin, {"/version: file version " + std::to_string(version) +
                   " is not supported (this build reads version " + std::to_string(kGprModelFileVersion) +
                   "); refit the model with this build"});
  }
}

// The kernel, hyperparameters, mean, trained ranges, basis, weights and their covariance (errors collected in r).
void ReadPosterior(Reader& r, GprModelData* m) {
  const std::string kernel = r.String("/kernel");
  if (kernel == "PS" || kernel == "DS") {
    m->kernel = ParseGprKernel(kernel);
  } else if (!kernel.empty()) {
    r.Fail("/kernel: must be \"PS\" or \"DS\", got \"" + kernel + "\"");
  }
  GprHyperparameters& hp = m->hyperparameters;
  hp.signal_variance_x = r.Number("/hyperparameters/signal_variance_x", true);
  hp.length_scale_x = r.Number("/hyperparameters/length_scale_x", true);
  hp.signal_variance_xdot = r.Number("/hyperparameters/signal_variance_xdot", true);
  hp.length_scale_xdot = r.Number("/hyperparameters/length_scale_xdot", true);
  hp.noise_variance = r.Number("/hyperparameters/noise_variance", true);
  hp.period = r.Number("/hyperparameters/period", true);
  m->mean = r.Number("/mean");
  m->x_range = r.ReadRange("/trained_range/x");
  m->xdot_range = r.ReadRange("/trained_range/xdot");
  m->basis.kernel = m->kernel;
  if (m->kernel == GprKernel::kPeriodicSe) {
    m->basis.harmonics = r.Integer("/basis/harmonics", 0);
    m->basis.period = r.Number("/basis/period", true);
  } else {
    m->basis.x_domain = r.ReadDomain("/basis/x_domain");
  }
  m->basis.xdot_domain = r.ReadDomain("/basis/xdot_domain");
  const Eigen::Index features = r.errors().empty() ? GprFeatureCount(m->basis) : -1;
  m->weights = r.Numbers("/weights", features);
  const Eigen::VectorXd lower =
      r.Numbers("/weight_covariance_lower", features >= 0 ? features * (features + 1) / 2 : -1);
  if (features >= 0 && lower.size() == features * (features + 1) / 2) {
    m->weight_covariance.resize(features, features);
    Eigen::Index k = 0;
    for (Eigen::Index row = 0; row < features; ++row) {
      for (Eigen::Index col = 0; col <= row; ++col, ++k) {
        m->weight_covariance(row, col) = lower(k);
        m->weight_covariance(col, row) = lower(k);
      }
    }
  }
}

// Keys the reader does not know, at every level (issue 41: a model file with an unknown key was read as if it were
// not there): "<pointer>/<key>: unknown key (did you mean 'k'?); the keys here are: …".
void CheckKnownKeys(const json& object, const std::string& pointer, const std::vector<std::string>& known, Reader& r) {
  if (!object.is_object()) return;  // the typed reads say what a non-object is
  for (const auto& item : object.items()) {
    if (std::find(known.begin(), known.end(), item.key()) != known.end()) continue;
    const auto closest = ClosestNames(item.key(), known, 1);
    r.Fail(fmt::format("{}/{}: unknown key{}; the keys here are: {} (a model file holds what fit-gpr writes: refit "
                       "the model, or remove the key)",
                       pointer, Excerpt(item.key(), 80),
                       closest.empty() ? "" : fmt::format(" (did you mean '{}'?)", closest.front()),
                       fmt::join(known, ", ")));
  }
}

void CheckModelKeys(const json& j, GprKernel kernel, Reader& r) {
  CheckKnownKeys(j, "", {"format", "version", "kernel", "hyperparameters", "mean", "trained_range", "basis", "weights",
                         "weight_covariance_lower", "provenance"}, r);
  std::vector<std::string> parameters;
  for (int i = 0; i < kGprParameterCount; ++i) parameters.emplace_back(GprParameterName(i));
  const auto child = [&](const json& parent, const char* key) -> const json& {
    static const json kNone;
    return parent.is_object() && parent.contains(key) ? parent[key] : kNone;
  };
  CheckKnownKeys(child(j, "hyperparameters"), "/hyperparameters", parameters, r);
  CheckKnownKeys(child(j, "trained_range"), "/trained_range", {"x", "xdot"}, r);
  const json& basis = child(j, "basis");
  CheckKnownKeys(basis, "/basis",
                 kernel == GprKernel::kPeriodicSe ? std::vector<std::string>{"harmonics", "period", "xdot_domain"}
                                                  : std::vector<std::string>{"x_domain", "xdot_domain"},
                 r);
  for (const char* domain : {"x_domain", "xdot_domain"}) {
    CheckKnownKeys(child(basis, domain), fmt::format("/basis/{}", domain), {"center", "half_width", "count"}, r);
  }
  const json& provenance = child(j, "provenance");
  CheckKnownKeys(provenance, "/provenance",
                 {"created_utc", "library_version", "solver", "source", "sample_count", "log_marginal_likelihood",
                  "log_posterior", "fit_seconds", "tolerance", "period_estimated", "priors", "position_column",
                  "velocity_column"},
                 r);
  const json& priors = child(provenance, "priors");
  CheckKnownKeys(priors, "/provenance/priors", parameters, r);
  for (const auto& name : parameters) {
    CheckKnownKeys(child(priors, name.c_str()), "/provenance/priors/" + name, {"median", "log_sd", "lower", "upper"},
                   r);
  }
}

// How the model was made: /provenance and its priors (errors collected in r).
void ReadProvenance(const json& j, Reader& r, GprProvenance* p) {
  p->created_utc = r.String("/provenance/created_utc");
  p->library_version = r.String("/provenance/library_version");
  p->solver = r.String("/provenance/solver");
  p->source = r.String("/provenance/source");
  p->sample_count = r.Integer("/provenance/sample_count", 0);
  p->log_marginal_likelihood = r.Number("/provenance/log_marginal_likelihood");
  p->log_posterior = r.Number("/provenance/log_posterior");
  p->fit_seconds = r.Number("/provenance/fit_seconds");
  p->tolerance = r.Number("/provenance/tolerance");
  p->period_estimated = r.Boolean("/provenance/period_estimated");
  for (auto [key, column] : {std::pair{"position_column", &p->position_column}, {"velocity_column", &p->velocity_column}}) {
    if (j.contains("provenance") && j["provenance"].is_object() && j["provenance"].contains(key)) {
      *column = r.String(std::string("/provenance/") + key);
    }
  }
  for (int i = 0; i < kGprParameterCount; ++i) {
    const std::string base = "/provenance/priors/" + std::string(GprParameterName(i));
    auto& prior = p->priors[static_cast<std::size_t>(i)];
    prior.median = r.Number(base + "/median");
    prior.log_sd = r.Number(base + "/log_sd", false, true);
    prior.lower = r.Number(base + "/lower");
    prior.upper = r.Number(base + "/upper", false, true);
  }
}

// The posterior must be one (issue 30: a negative covariance gave std 0 everywhere): Cov β positive semidefinite.
void CheckCovariance(const Eigen::MatrixXd& covariance, std::string_view origin) {
  if (covariance.size() == 0) return;
  const Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eigen(covariance, Eigen::EigenvaluesOnly);
  const Eigen::VectorXd& lambda = eigen.eigenvalues();  // ascending
  const double largest = lambda.cwiseAbs().maxCoeff();
  if (!(lambda(0) >= -1e-9 * largest)) {
    Throw(origin, {"/weight_covariance_lower: the weight covariance is not positive semidefinite (smallest "
                   "eigenvalue " + FormatNumber(lambda(0)) + ", largest " + FormatNumber(lambda(lambda.size() - 1)) +
                   "): the file was edited or is corrupt; refit the model (motionblocks fit-gpr)"});
  }
}

// A posterior variance is never above the prior's: ψᵀ Cov(β) ψ ≤ ψᵀ diag(s) ψ ≤ σ_f² (the data can only pin the
// model down). Twice the prior (round-off has no such size) marks a covariance edited or corrupt (issue 41: one of
// 1e200 everywhere predicted ± 1e101 N as if the model knew nothing less than that).
constexpr double kMaxPosteriorOverPriorVariance = 2.0;

// Weights that overflow (all 1e308) predict NaN, a covariance far above the prior a standard deviation no fit gives:
// both checked on a 5 × 5 grid over the trained range, where the model is meant to be used.
void CheckPredictionsAreFinite(const GprModel& model, std::string_view origin) {
  const GprModelData& d = model.data();
  const double prior_variance = d.hyperparameters.signal_variance_x + d.hyperparameters.signal_variance_xdot;
  for (int i = 0; i <= 4; ++i) {
    const double x = d.x_range.min + 0.25 * i * (d.x_range.max - d.x_range.min);
    for (int k = 0; k <= 4; ++k) {
      const double xdot = d.xdot_range.min + 0.25 * k * (d.xdot_range.max - d.xdot_range.min);
      double mean = 0.0, std = 0.0;
      model.Predict(x, xdot, &mean, &std);
      if (!std::isfinite(mean) || !std::isfinite(std)) {
        Throw(origin, {"/weights: the model predicts " + FormatNumber(mean) + " ± " + FormatNumber(std) +
                       " at x = " + FormatNumber(x) + " m, xdot = " + FormatNumber(xdot) +
                       " m/s inside its trained range (weights or mean too large for double arithmetic): the file "
                       "was edited or is corrupt; refit the model (motionblocks fit-gpr)"});
      }
      if (std * std > kMaxPosteriorOverPriorVariance * prior_variance) {
        Throw(origin, {"/weight_covariance_lower: the model's standard deviation at x = " + FormatNumber(x) +
                       " m, xdot = " + FormatNumber(xdot) + " m/s inside its trained range is " + FormatNumber(std) +
                       ", above its prior's " + FormatNumber(std::sqrt(prior_variance)) +
                       " (signal_variance_x + signal_variance_xdot): a posterior is never less certain than its "
                       "prior, so the covariance was edited or is corrupt; refit the model (motionblocks fit-gpr)"});
      }
    }
  }
}

}  // namespace

GprModel GprModelFromJson(const json& j, std::string_view origin) {
  if (!j.is_object()) Throw(origin, {"/: the model must be a JSON object"});
  CheckHeader(j, origin);
  Reader r(j);
  GprModelData m;
  ReadPosterior(r, &m);
  ReadProvenance(j, r, &m.provenance);
  CheckModelKeys(j, m.kernel, r);
  if (!r.errors().empty()) Throw(origin, r.errors());
  CheckCovariance(m.weight_covariance, origin);
  GprModel model = [&] {
    try {
      return GprModel(std::move(m));
    } catch (const std::invalid_argument& e) {
      throw std::invalid_argument(std::string(origin) + ": " + e.what());
    }
  }();
  CheckPredictionsAreFinite(model, origin);
  return model;
}

void SaveGprModel(const GprModel& model, const std::filesystem::path& path) {
  try {
    WriteFileSafely(path, GprModelToJson(model).dump(1) + "\n");
  } catch (const std::runtime_error& e) {
    throw std::runtime_error(std::string("SaveGprModel: ") + e.what());
  }
}

GprModel LoadGprModel(const std::filesystem::path& path) {
  if (!std::filesystem::exists(path)) {
    throw FileOpenError(path.string() + ": cannot open the GP model file (does it exist?); check the path, or fit a "
                        "model with motionblocks fit-gpr");
  }
  const std::string text = ReadInputFile(path, "GP model file");  // a regular file within the size limit
  json j;
  try {
    j = ParseJsonLimited(text, path.string());
  } catch (const json::parse_error& e) {
    throw std::runtime_error(path.string() + ": not a valid JSON file (corrupt or truncated?) at byte " +
                             std::to_string(e.byte) + ": " + JsonErrorText(e));
  }
  return GprModelFromJson(j, path.string());
}

}  // namespace mb

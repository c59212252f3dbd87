#include "tools/workflow/comparison.h"
#include "tools/workflow/loop_probe.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <optional>
#include <stdexcept>

#include <Eigen/Dense>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <tbb/parallel_for.h>
#include <unsupported/Eigen/NonLinearOptimization>

#include "engine/closest_names.h"
#include "engine/diagram_document.h"
#include "engine/diagram_loader.h"
#include "engine/numerical_error.h"
#include "engine/registry.h"
#include "engine/units.h"
#include "models/diagnosis/measurement_log.h"
#include "models/diagnosis/signal_processing.h"

namespace mb {

namespace fs = std::filesystem;
using nlohmann::json;

std::vector<FreeParameter> ResolveFreeParameters(const json& diagram, const std::vector<std::string>& names) {
  const DiagramDocument document(diagram);
  std::vector<FreeParameter> out;
  for (const auto& name : names) {
    const auto dot = name.find('.');
    if (dot == std::string::npos) {
      throw std::invalid_argument(fmt::format("free parameter '{}': write block.parameter, e.g. mass.gain", name));
    }
    const std::string block = name.substr(0, dot), parameter = name.substr(dot + 1);
    if (!document.Has(block)) throw std::invalid_argument(fmt::format("free parameter '{}': no element '{}'", name, block));
    const json value = document.Parameter(block, parameter);
    const ParamSpec spec = document.ParameterSpec(block, parameter);
    const std::string& unit = spec.unit;  // on the diagram's axis
    const double lower = spec.min.value_or(-std::numeric_limits<double>::infinity());
    const double upper = spec.max.value_or(std::numeric_limits<double>::infinity());
    if (value.is_number()) {
      out.push_back({block, parameter, -1, name, unit, lower, upper});
    } else if (value.is_array() && !value.empty() && value[0].is_number()) {
      for (std::size_t i = 0; i < value.size(); ++i) {
        out.push_back({block, parameter, static_cast<int>(i), fmt::format("{}[{}]", name, i), unit, lower, upper});
      }
    } else {
      throw std::invalid_argument(fmt::format(
          "free parameter '{}': element '{}' ({}) has no numeric parameter '{}'", name, block,
          document.TypeOf(block), parameter));
    }
  }
  return out;
}

Eigen::VectorXd GetParameterValues(const json& diagram, const std::vector<FreeParameter>& params) {
  const DiagramDocument document(diagram);
  Eigen::VectorXd v(static_cast<Eigen::Index>(params.size()));
  for (std::size_t i = 0; i < params.size(); ++i) {
    const json value = document.Parameter(params[i].block, params[i].parameter);
    v(static_cast<Eigen::Index>(i)) =
        params[i].index < 0 ? value.get<double>() : value.at(static_cast<std::size_t>(params[i].index)).get<double>();
  }
  return v;
}

void SetParameterValues(json* diagram, const std::vector<FreeParameter>& params,
                        const Eigen::Ref<const Eigen::VectorXd>& values) {
  DiagramDocument document(std::move(*diagram));
  for (std::size_t i = 0; i < params.size(); ++i) {
    const double x = values(static_cast<Eigen::Index>(i));
    if (params[i].index < 0) {
      document.SetParameter(params[i].block, params[i].parameter, x);
    } else {
      json vector = document.Parameter(params[i].block, params[i].parameter);
      if (!vector.is_array()) vector = json::array({vector});
      vector[static_cast<std::size_t>(params[i].index)] = x;
      document.SetParameter(params[i].block, params[i].parameter, vector);
    }
  }
  *diagram = document.json();
}

namespace {
/// A mapped column whose name states a unit (position_m, iq_A; ColumnUnit) must measure what the connector does:
/// --map force=position_m would compare newtons with metres. Units outside the motion quantities are not judged.
void CheckMappedUnit(const std::string& connector, const std::string& connector_unit, const std::string& column) {
  const std::string column_unit = ColumnUnit(column);
  const MotionQuantity wanted = QuantityOfUnit(connector_unit), given = QuantityOfUnit(column_unit);
  if (wanted == MotionQuantity::kOther || given == MotionQuantity::kOther) return;
  if (PortAcceptsUnit(connector_unit, column_unit) || PortAcceptsUnit(column_unit, connector_unit)) return;
  throw std::invalid_argument(fmt::format(
      "--map {}={}: the connector '{}' is in {} but the column '{}' is in {} (its name's suffix): they measure "
      "different things; map a column in {} (or a rotary/drive unit of the same quantity)",
      connector, column, connector, connector_unit, column, column_unit, connector_unit));
}

/// Every --map names a connector of the diagram (a misspelled one would silently change nothing) and a column of
/// the connector's quantity when both units are known.
void CheckColumnMap(const Diagram& d, const std::map<std::string, std::string>& column_map) {
  std::vector<std::string> connectors;
  std::map<std::string, std::string> units;
  for (const auto& in : d.inputs()) {
    connectors.push_back(in.name);
    units[in.name] = in.unit;
  }
  for (const auto& out : d.outputs()) {
    connectors.push_back(out.name);
    units[out.name] = out.unit;
  }
  for (const auto& [connector, column] : column_map) {
    if (std::find(connectors.begin(), connectors.end(), connector) != connectors.end()) {
      CheckMappedUnit(connector, units[connector], column);
      continue;
    }
    const auto close = ClosestNames(connector, connectors, 1);
    throw std::invalid_argument(fmt::format(
        "--map {}={}: the diagram has no connector '{}'{}; its input and output connectors: {}", connector, column,
        connector, close.empty() ? "" : fmt::format(" (did you mean '{}'?)", close.front()),
        connectors.empty() ? "(none)" : fmt::format("{}", fmt::join(connectors, ", "))));
  }
}
}  // namespace

ModelComparison::ModelComparison(json diagram, fs::path base_directory, std::string source,
                                 const MeasurementLog& log, const std::map<std::string, std::string>& column_map)
    : diagram_(std::move(diagram)), base_(std::move(base_directory)), source_(std::move(source)), log_(log) {
  const auto& t = log.time();
  DiagramDocument document(std::move(diagram_));
  document.SetExperiment(t(0), t(t.size() - 1), MedianTimeStep(t));
  diagram_ = document.json();
  const Diagram d = BuildDiagram(diagram_, base_, source_);
  CheckColumnMap(d, column_map);
  auto column_for = [&](const std::string& connector, const std::string& fallback) {
    auto it = column_map.find(connector);
    return it != column_map.end() ? it->second : fallback;
  };
  std::string present;
  for (const auto& n : log.names()) present += (present.empty() ? "" : ", ") + n;
  for (const auto& in : d.inputs()) {
    const std::string column = column_for(in.name, in.measurement);
    if (log.has_column(column)) {
      input_columns_[in.name] = column;
    } else if (!in.optional) {
      throw std::invalid_argument(fmt::format(
          "{}: the diagram's input '{}' reads column '{}', which the log lacks; columns present: {}. Map another "
          "column with --map {}=COLUMN",
          log.source(), in.name, column, present, in.name));
    }
  }
  for (const auto& out : d.outputs()) {
    const std::string column = column_for(out.name, out.measurement);
    if (log.has_column(column)) output_columns_[out.name] = column;
  }
  if (output_columns_.empty()) {
    std::string outs;
    for (const auto& out : d.outputs()) outs += (outs.empty() ? "" : ", ") + out.name + " ← " + out.measurement;
    throw std::invalid_argument(fmt::format(
        "{}: no output of the diagram can be compared: its outputs read columns {} and the log has {}. Map one with "
        "--map OUTPUT=COLUMN",
        log.source(), outs.empty() ? "(none: add an output connector)" : outs, present));
  }
}

namespace {

// Linear interpolation of a simulated signal (st, sv) onto the measured time stamps t.
Eigen::VectorXd OnMeasuredTimes(const std::vector<double>& st, const std::vector<double>& sv,
                                const Eigen::VectorXd& t) {
  Eigen::VectorXd out(t.size());
  std::size_t j = 0;
  for (Eigen::Index i = 0; i < t.size(); ++i) {
    while (j + 2 < st.size() && st[j + 1] < t(i)) ++j;
    const double w = st.size() < 2 ? 0.0 : std::clamp((t(i) - st[j]) / (st[j + 1] - st[j]), 0.0, 1.0);
    out(i) = st.size() < 2 ? sv[0] : sv[j] + w * (sv[j + 1] - sv[j]);
  }
  return out;
}

}  // namespace

SignalLog ModelComparison::Run(const Diagram& d) const {
  Simulator sim(d);
  for (const auto& [connector, column] : input_columns_) sim.SetInput(connector, SeriesOf(log_, column));
  sim.Initialize();
  sim.AdvanceTo(d.experiment().stop_time);
  return sim.log();
}

std::map<std::string, std::string> ModelComparison::ColumnMap() const {
  std::map<std::string, std::string> all = input_columns_;
  all.insert(output_columns_.begin(), output_columns_.end());
  return all;
}

std::vector<std::pair<std::string, Eigen::VectorXd>> ModelComparison::SimulateBlockOutputs(
    std::size_t max_signals) const {
  json diagram = diagram_;
  json logged = json::array();
  {
    const Diagram d = BuildDiagram(diagram_, base_, source_, SchemaCheck::kSkipRevalidation);
    for (const auto& block : d.blocks()) {
      for (const PortSpec& port : block->output_ports()) {
        if (port.width == 1 && logged.size() < max_signals) logged.push_back(block->name() + "." + port.name);
      }
    }
  }
  diagram["log"] = logged;
  const SignalLog log = Run(BuildDiagram(diagram, base_, source_, SchemaCheck::kSkipRevalidation));
  std::vector<std::pair<std::string, Eigen::VectorXd>> out;
  for (const auto& name : logged) {
    const std::string signal = name.get<std::string>();
    out.emplace_back(signal, OnMeasuredTimes(log.time, log.Column(signal), log_.time()));
  }
  return out;
}

Eigen::VectorXd ModelComparison::FitWeights() const {
  const Eigen::Index n = log_.rows();
  if (output_filter_hz_ <= 0.0 || n < 2) return Eigen::VectorXd::Ones(n);
  const double dt = MedianTimeStep(log_.time());
  return InteriorWeights(n, log_.segment_starts(), dt, DerivativeCutoffHz(output_filter_hz_, dt, log_.source()));
}

std::vector<ComparedOutput> ModelComparison::Simulate() const {
  const Diagram d = BuildDiagram(diagram_, base_, source_, SchemaCheck::kSkipRevalidation);
  const SignalLog log = Run(d);
  std::vector<ComparedOutput> out;
  const auto& t = log_.time();
  for (const auto& o : d.outputs()) {
    auto it = output_columns_.find(o.name);
    if (it == output_columns_.end()) continue;
    ComparedOutput c;
    c.connector = o.name;
    c.column = it->second;
    c.unit = o.unit;
    c.measured = log_.column(it->second);
    c.model = OnMeasuredTimes(log.time, log.Column(o.name), t);
    if (output_filter_hz_ > 0.0 && c.model.allFinite()) {
      // The cut-off the log's measured outputs were filtered with (the default follows the sample rate).
      const double dt = MedianTimeStep(t);
      c.model = ZeroPhaseLowPassBySegment(c.model, dt, DerivativeCutoffHz(output_filter_hz_, dt, log_.source()),
                                          log_.segment_starts());
    }
    if (!c.model.allFinite()) {
      throw std::runtime_error(fmt::format("the simulated output '{}' is not finite (NaN/Inf): the model diverged "
                                           "with these parameters",
                                           o.name));
    }
    c.rmse = Rmse(c.measured, c.model);
    c.fit_percent = FitPercent(c.measured, c.model);
    for (const auto& in : d.inputs()) {  // the reference of a closed loop: an input in the output's unit
      const auto column = input_columns_.find(in.name);
      if (column == input_columns_.end() || o.unit.empty() || in.unit != o.unit) continue;
      const Eigen::VectorXd tracking = log_.column(column->second) - c.measured;
      const double spread = (tracking.array() - tracking.mean()).matrix().norm();
      if (!(spread > 0.0)) continue;
      c.tracking_input = in.name;
      c.tracking_fit_percent = 100.0 * (1.0 - (c.measured - c.model).norm() / spread);
      break;
    }
    out.push_back(std::move(c));
  }
  return out;
}

std::vector<ComparedOutput> ModelComparison::Simulate(const std::vector<FreeParameter>& params,
                                                      const Eigen::Ref<const Eigen::VectorXd>& values) const {
  ModelComparison copy = *this;
  copy.SetParameterValues(params, values);
  return copy.Simulate();
}

void ModelComparison::SetParameterValues(const std::vector<FreeParameter>& params,
                                         const Eigen::Ref<const Eigen::VectorXd>& values) {
  mb::SetParameterValues(&diagram_, params, values);
}

namespace {

// `x` with each entry clamped into its parameter's declared bounds (FreeParameter::lower, upper).
Eigen::VectorXd WithinBounds(const std::vector<FreeParameter>& params, Eigen::VectorXd x) {
  for (std::size_t i = 0; i < params.size(); ++i) {
    const auto k = static_cast<Eigen::Index>(i);
    x(k) = std::clamp(x(k), params[i].lower, params[i].upper);
  }
  return x;
}

// Residual functor for Eigen's Levenberg–Marquardt: scaled residuals of all compared outputs, the trial parameters
// projected into their declared bounds first. Without the projection a parameter fitted to its bound (a Coulomb level
// of 0 beside a Stribeck law) made every step that crossed it a refused diagram, and Levenberg–Marquardt shrank its
// step to nothing and reported convergence where it started (a quadratic drag added at 31 000 N·s²/m² kept a fit RMSE
// of 21.9 N against the base's 7.9).
struct ResidualFunctor {
  using Scalar = double;
  using InputType = Eigen::VectorXd;
  using ValueType = Eigen::VectorXd;
  using JacobianType = Eigen::MatrixXd;
  enum { InputsAtCompileTime = Eigen::Dynamic, ValuesAtCompileTime = Eigen::Dynamic };

  const ModelComparison* comparison;
  const std::vector<FreeParameter>* params;
  Eigen::VectorXd scale;   // per output
  Eigen::VectorXd weight;  // per sample (ModelComparison::FitWeights), the same for every output
  Eigen::Index n_values;

  int inputs() const { return static_cast<int>(params->size()); }
  int values() const { return static_cast<int>(n_values); }
  int operator()(const Eigen::VectorXd& x, Eigen::VectorXd& f) const {
    std::vector<ComparedOutput> outs;
    try {
      outs = comparison->Simulate(*params, WithinBounds(*params, x));
    } catch (const std::exception&) {
      f.setConstant(1e6);  // a diverging trial point: make it very bad, LM retreats
      return 0;
    }
    Eigen::Index k = 0;
    for (std::size_t o = 0; o < outs.size(); ++o) {
      const Eigen::Index n = outs[o].measured.size();
      f.segment(k, n) = weight.cwiseProduct(outs[o].measured - outs[o].model) / scale(static_cast<Eigen::Index>(o));
      k += n;
    }
    return 0;
  }

  // The forward-difference Jacobian with steps h = √ε·max(|x_j|, 1) (SI units; as OutputJacobian's), its p + 1 runs in
  // parallel: each is an independent simulation of its own copy of the diagram. Not Eigen::NumericalDiff's √ε·|x_j|:
  // a parameter the fit drives towards 0 (a Coulomb level of 2e-8 N beside a Stribeck law) got a step of 3e-16, whose
  // output change is below the output's rounding, and the garbage column stalled Levenberg–Marquardt at its evaluation
  // limit far from the optimum (a quadratic drag's refit ended 11 × above the noise floor). Returns the evaluations
  // made, which Levenberg–Marquardt counts against maxfev.
  int df(const Eigen::VectorXd& x, Eigen::MatrixXd& jac) const {
    const Eigen::Index p = x.size();
    const double eps = std::sqrt(std::numeric_limits<double>::epsilon());
    std::vector<Eigen::VectorXd> f(static_cast<std::size_t>(p + 1), Eigen::VectorXd(values()));
    Eigen::VectorXd h(p);
    for (Eigen::Index j = 0; j < p; ++j) h(j) = eps * std::max(std::abs(x(j)), 1.0);
    tbb::parallel_for(Eigen::Index{0}, p + 1, [&](Eigen::Index j) {
      Eigen::VectorXd trial = x;
      if (j < p) trial(j) += h(j);
      (*this)(trial, f[static_cast<std::size_t>(j)]);
    });
    for (Eigen::Index j = 0; j < p; ++j) jac.col(j) = (f[static_cast<std::size_t>(j)] - f.back()) / h(j);
    return static_cast<int>(p + 1);
  }
};

}  // namespace

Eigen::MatrixXd OutputJacobian(const ModelComparison& comparison, const std::vector<FreeParameter>& params,
                               const Eigen::Ref<const Eigen::VectorXd>& values) {
  const Eigen::Index p = values.size();
  const Eigen::VectorXd y0 = comparison.Simulate(params, values).front().model;
  Eigen::MatrixXd jac(y0.size(), p);
  // A trial value the diagram refuses (a parameter at its bound, e.g. a friction level fitted to 0): nullopt.
  const auto model_at = [&](const Eigen::VectorXd& v) -> std::optional<Eigen::VectorXd> {
    try {
      return comparison.Simulate(params, v).front().model;
    } catch (const DiagramError&) {
      return std::nullopt;
    }
  };
  // The 2p runs are independent simulations: in parallel.
  std::vector<std::optional<Eigen::VectorXd>> runs(static_cast<std::size_t>(2 * p));
  tbb::parallel_for(Eigen::Index{0}, 2 * p, [&](Eigen::Index k) {
    const Eigen::Index j = k / 2;
    Eigen::VectorXd v = values;
    v(j) += (k % 2 == 0 ? 1.0 : -1.0) * 1e-6 * std::max(1.0, std::abs(values(j)));
    runs[static_cast<std::size_t>(k)] = model_at(v);
  });
  for (Eigen::Index j = 0; j < p; ++j) {
    const double h = 1e-6 * std::max(1.0, std::abs(values(j)));
    const auto& yp = runs[static_cast<std::size_t>(2 * j)];
    const auto& ym = runs[static_cast<std::size_t>(2 * j + 1)];
    if (yp && ym) {
      jac.col(j) = (*yp - *ym) / (2.0 * h);  // central
    } else if (yp) {
      jac.col(j) = (*yp - y0) / h;  // at a lower bound: forward
    } else if (ym) {
      jac.col(j) = (y0 - *ym) / h;  // at an upper bound: backward
    } else {
      throw std::invalid_argument(fmt::format("parameter '{}': the diagram refuses every value within {} of {}",
                                              params[static_cast<std::size_t>(j)].name, h, values(j)));
    }
  }
  return jac;
}

json FitResult::ToJson() const {
  json params_json = json::array();
  for (std::size_t i = 0; i < parameters.size(); ++i) {
    const auto k = static_cast<Eigen::Index>(i);
    params_json.push_back({{"name", parameters[i].name},
                           {"unit", parameters[i].unit},
                           {"initial", initial(k)},
                           {"estimate", estimate(k)},
                           {"standard_error", standard_error(k)},
                           {"ci95", {estimate(k) - 1.96 * standard_error(k), estimate(k) + 1.96 * standard_error(k)}}});
  }
  json j = {{"parameters", params_json},         {"iterations", iterations},    {"status", status},
            {"condition_number", condition_number}, {"identifiable", identifiable}};
  if (!identifiable) {
    j["not_identifiable"] = {{"no_effect", no_effect}, {"cannot_be_told_apart", indistinguishable}};
    j["warning"] = identifiability_problem;
  }
  return j;
}

namespace {

// Fills result's identifiability from its Jacobian (N × p) at the estimate; `output_norm` = ‖model output‖ there.
void CheckIdentifiability(double output_norm, FitResult* result) {
  const Eigen::MatrixXd& jac = result->jacobian;
  const auto p = jac.cols();
  std::vector<Eigen::Index> active;  // the columns with an effect
  for (Eigen::Index k = 0; k < p; ++k) {
    // The output's change over the parameter's scale: its value, but at least 1 (SI units, as the Jacobian's steps): a
    // Coulomb level fitted to 1e-8 N beside a Stribeck law still acts, 1 N of it is 1 N on every moving sample.
    const double value = std::max({std::abs(result->estimate(k)), std::abs(result->initial(k)), 1.0});
    const double effect = jac.col(k).norm() * value;
    if (!(effect > kNoEffectRelative * output_norm) || !std::isfinite(effect)) {
      result->no_effect.push_back(result->parameters[static_cast<std::size_t>(k)].name);
    } else {
      active.push_back(k);
    }
  }
  std::vector<bool> unidentified(static_cast<std::size_t>(p), false);
  for (Eigen::Index k = 0; k < p; ++k) {
    if (std::find(active.begin(), active.end(), k) == active.end()) unidentified[static_cast<std::size_t>(k)] = true;
  }
  if (active.size() >= 2) {
    Eigen::MatrixXd scaled(jac.rows(), static_cast<Eigen::Index>(active.size()));
    for (std::size_t a = 0; a < active.size(); ++a) {
      const auto col = jac.col(active[a]);
      scaled.col(static_cast<Eigen::Index>(a)) = col / col.norm();
    }
    Eigen::JacobiSVD<Eigen::MatrixXd> svd(scaled, Eigen::ComputeThinV);
    const auto& sv = svd.singularValues();
    result->condition_number = sv(sv.size() - 1) > 0.0 ? sv(0) / sv(sv.size() - 1) : INFINITY;
    for (Eigen::Index s = 0; s < sv.size(); ++s) {
      if (sv(s) * kMaxIdentifiableCondition >= sv(0)) continue;  // a direction the data determine
      std::vector<std::string> group;                            // the parameters this null direction mixes
      for (std::size_t a = 0; a < active.size(); ++a) {
        if (std::abs(svd.matrixV()(static_cast<Eigen::Index>(a), s)) > 0.1) {
          group.push_back(result->parameters[static_cast<std::size_t>(active[a])].name);
          unidentified[static_cast<std::size_t>(active[a])] = true;
        }
      }
      if (!group.empty()) result->indistinguishable.push_back(group);
    }
  }
  if (result->no_effect.empty() && result->indistinguishable.empty()) return;
  result->identifiable = false;
  result->status = "not identifiable";
  for (Eigen::Index k = 0; k < p; ++k) {
    if (unidentified[static_cast<std::size_t>(k)]) result->standard_error(k) = INFINITY;
  }
  std::vector<std::string> parts;
  if (!result->no_effect.empty()) {
    parts.push_back(fmt::format(
        "{} {} no effect on the model output in this log (the motion does not excite {}: e.g. no acceleration for a "
        "mass, no velocity for friction); leave {} out of --fit (keep the diagram's value) or record a log that "
        "excites {}",
        fmt::join(result->no_effect, ", "), result->no_effect.size() == 1 ? "has" : "have",
        result->no_effect.size() == 1 ? "it" : "them", result->no_effect.size() == 1 ? "it" : "them",
        result->no_effect.size() == 1 ? "it" : "them"));
  }
  for (const auto& group : result->indistinguishable) {
    parts.push_back(fmt::format(
        "{} cannot be told apart (they change the output alike: condition number {:.3g} of the scaled Jacobian, "
        "above {:g}; e.g. Coulomb friction and an offset when the velocity keeps one sign); fit only one of them, or "
        "record a log that moves them differently (both directions of motion, several speeds)",
        fmt::join(group, " and "), result->condition_number, kMaxIdentifiableCondition));
  }
  result->identifiability_problem = fmt::format("{}", fmt::join(parts, "; "));
}

}  // namespace

FitResult FitParameters(const ModelComparison& comparison, const std::vector<FreeParameter>& params) {
  if (params.empty()) throw std::invalid_argument("nothing to fit: name parameters with --fit block.param,…");
  FitResult result;
  result.parameters = params;
  result.initial = GetParameterValues(comparison.diagram_json(), params);
  const auto outs = comparison.Simulate();
  ResidualFunctor functor{&comparison, &params, Eigen::VectorXd(static_cast<Eigen::Index>(outs.size())),
                          comparison.FitWeights(), 0};
  for (std::size_t o = 0; o < outs.size(); ++o) {
    const Eigen::VectorXd& y = outs[o].measured;
    const double sd = std::sqrt((y.array() - y.mean()).square().mean());
    functor.scale(static_cast<Eigen::Index>(o)) = sd > 0.0 ? sd : 1.0;
    functor.n_values += y.size();
  }
  Eigen::LevenbergMarquardt<ResidualFunctor> lm(functor);
  lm.parameters.maxfev = 200 * static_cast<int>(params.size() + 1);
  lm.parameters.xtol = 1e-10;
  lm.parameters.ftol = 1e-12;
  Eigen::VectorXd x = result.initial;
  const auto status = lm.minimize(x);
  x = WithinBounds(params, x);
  result.estimate = x;
  result.iterations = static_cast<int>(lm.iter);
  switch (status) {
    case Eigen::LevenbergMarquardtSpace::RelativeReductionTooSmall: result.status = "converged (cost)"; break;
    case Eigen::LevenbergMarquardtSpace::RelativeErrorTooSmall: result.status = "converged (parameters)"; break;
    case Eigen::LevenbergMarquardtSpace::RelativeErrorAndReductionTooSmall: result.status = "converged"; break;
    case Eigen::LevenbergMarquardtSpace::TooManyFunctionEvaluation: result.status = "stopped: evaluation limit"; break;
    default: result.status = fmt::format("stopped (Levenberg–Marquardt status {})", static_cast<int>(status));
  }
  // Standard errors from the primary output's Jacobian at the estimate (unscaled units).
  // Over the samples the fit weighed (ModelComparison::FitWeights).
  result.jacobian = OutputJacobian(comparison, params, x);
  const auto at = comparison.Simulate(params, x).front();
  const Eigen::MatrixXd weighed = functor.weight.asDiagonal() * result.jacobian;
  const double n = functor.weight.sum();
  const double sigma2 = functor.weight.cwiseProduct(at.measured - at.model).squaredNorm() /
                        std::max(1.0, n - static_cast<double>(x.size()));
  const Eigen::MatrixXd jtj = weighed.transpose() * weighed;
  const Eigen::VectorXd col_norm = weighed.colwise().norm().transpose().cwiseMax(1e-300);
  const Eigen::MatrixXd scaled = weighed * col_norm.cwiseInverse().asDiagonal();
  Eigen::JacobiSVD<Eigen::MatrixXd> svd(scaled);
  const auto& sv = svd.singularValues();
  result.condition_number = sv(sv.size() - 1) > 0.0 ? sv(0) / sv(sv.size() - 1) : INFINITY;
  const Eigen::MatrixXd cov = sigma2 * jtj.completeOrthogonalDecomposition().pseudoInverse();
  result.standard_error = cov.diagonal().cwiseMax(0.0).cwiseSqrt();
  CheckIdentifiability(at.model.norm(), &result);
  return result;
}

DiagramFit FitDiagram(const json& diagram, const fs::path& base_directory, const std::string& source,
                      const MeasurementLog& log, const std::map<std::string, std::string>& column_map,
                      const std::vector<std::string>& parameter_names, double output_filter_hz) {
  ModelComparison comparison(diagram, base_directory, source, log, column_map);
  comparison.set_output_filter(output_filter_hz);
  const auto params = ResolveFreeParameters(diagram, parameter_names);
  DiagramFit out;
  out.before = comparison.Simulate();
  out.fit = FitParameters(comparison, params);
  out.after = comparison.Simulate(params, out.fit.estimate);
  out.fitted_diagram = diagram;
  SetParameterValues(&out.fitted_diagram, params, out.fit.estimate);
  // A result that is not a number is not a result (issue 30: "RMSE inf → inf", "± -nan", exit 0).
  std::vector<std::string> not_finite;
  if (!std::isfinite(out.before.front().rmse)) not_finite.push_back(fmt::format("RMSE before {}", out.before.front().rmse));
  if (!std::isfinite(out.after.front().rmse)) not_finite.push_back(fmt::format("RMSE after {}", out.after.front().rmse));
  for (std::size_t i = 0; i < params.size(); ++i) {
    const auto k = static_cast<Eigen::Index>(i);
    if (!std::isfinite(out.fit.estimate(k))) not_finite.push_back(fmt::format("{} = {}", params[i].name, out.fit.estimate(k)));
    if (std::isnan(out.fit.standard_error(k)) || (out.fit.identifiable && !std::isfinite(out.fit.standard_error(k)))) {
      not_finite.push_back(fmt::format("the standard error of {} ({})", params[i].name, out.fit.standard_error(k)));
    }
  }
  if (!not_finite.empty()) {
    const Eigen::VectorXd& measured = out.before.front().measured;
    throw NumericalError(fmt::format(
        "{}: the fit of {} to column '{}' is not finite: {}; the largest measured |{}| is {:g} {} (values beyond "
        "about 1e150 overflow when squared): check the column's unit and remove outlier rows",
        log.source(), out.before.front().connector, out.before.front().column, fmt::join(not_finite, ", "),
        out.before.front().column, measured.size() > 0 ? measured.cwiseAbs().maxCoeff() : 0.0, out.before.front().unit));
  }
  return out;
}

namespace {

// The squared correlation of the centred records (0 when either is constant or not finite, or their lengths differ).
double SquaredCorrelation(const Eigen::VectorXd& column, const Eigen::VectorXd& signal) {
  if (signal.size() != column.size() || !signal.allFinite()) return 0.0;
  const Eigen::VectorXd c = column.array() - column.mean();
  const Eigen::VectorXd s = signal.array() - signal.mean();
  const double cc = c.squaredNorm(), ss = s.squaredNorm();
  if (!(cc > 0.0) || !(ss > 0.0)) return 0.0;
  const double cs = c.dot(s);
  return cs * cs / (cc * ss);
}

// The diagram's own signal that `column` follows best (name, squared correlation of the centred records); none when
// no signal varies. Constant signals match nothing.
std::optional<std::pair<std::string, double>> ClosestOwnSignal(
    const Eigen::VectorXd& column, const std::vector<std::pair<std::string, Eigen::VectorXd>>& own) {
  std::optional<std::pair<std::string, double>> best;
  if (!((column.array() - column.mean()).matrix().squaredNorm() > 0.0)) return best;
  for (const auto& [name, signal] : own) {
    const double r2 = SquaredCorrelation(column, signal);
    if (!(r2 > 0.0)) continue;
    if (!best || r2 > best->second) best = {name, r2};
  }
  return best;
}

// Of the diagram's own signals that `column` follows (squared correlation of the centred records ≥ `min_r2`), the one it
// equals best, ‖column − signal‖ least: the controller's output in volts is kv·(velocity error), which it follows as
// closely as the velocity error itself. None when no signal follows it.
std::optional<std::string> SameScaleOwnSignal(const Eigen::VectorXd& column,
                                              const std::vector<std::pair<std::string, Eigen::VectorXd>>& own,
                                              double min_r2) {
  std::optional<std::string> best;
  double least = std::numeric_limits<double>::infinity();
  for (const auto& [name, signal] : own) {
    if (SquaredCorrelation(column, signal) < min_r2) continue;
    const double distance = (column - signal).squaredNorm();
    if (distance < least) {
      least = distance;
      best = name;
    }
  }
  return best;
}

// Simulation mode: the diagram's own signals with its loop opened at the compared output — every element input that
// the output's driver feeds (the plant's position into the controller) reads the measured column instead
// (DiagramDocument::ReadInstead, through an added input connector). The controller then computes what the one that
// ran computed from the same motion, whatever the plant model lacks: the logged command of a drive that saturates
// follows the opened loop's command, not the closed loop's, whose motion differs by the very effect missing. Empty
// when the output's driver feeds no element (nothing to open) or the opened diagram cannot be compared (a note to
// `notes` says why).
std::vector<std::pair<std::string, Eigen::VectorXd>> OpenedLoopSignals(const ModelComparison& comparison,
                                                                       const ComparedOutput& output,
                                                                       std::vector<std::string>* notes) {
  DiagramDocument document(comparison.diagram_json(), comparison.base_directory(), comparison.source());
  const std::optional<Endpoint> driver = document.DriverOf({"", output.connector});
  if (!driver || driver->is_connector()) return {};
  const std::string name = document.UniqueConnectorName(output.connector + "_measured");
  document.AddConnector({name, "input", output.unit, output.column, ""});
  if (document.ReadInstead(*driver, {"", name}) == 0) return {};
  try {
    const ModelComparison opened(document.json(), comparison.base_directory(), comparison.source(), comparison.log(),
                                 comparison.ColumnMap());
    return opened.SimulateBlockOutputs();
  } catch (const std::exception& e) {  // an opened loop that cannot run: no reaction is seen there, and it is said
    notes->push_back(fmt::format("simulation mode: the diagram opened at the measured '{}' could not be simulated "
                                 "({}); a log column is matched against the closed loop's signals only",
                                 output.column, e.what()));
    return {};
  }
}

}  // namespace

DiagnosedComparison CompareAndDiagnose(const json& diagram, const fs::path& base_directory, const std::string& source,
                                       const MeasurementLog& log, const MeasurementSettings& settings,
                                       const std::vector<std::string>& fit_names, bool diagnose) {
  DiagnosedComparison out;
  out.mode = ModeOf(diagram);
  const bool equation_error = out.mode == ExperimentMode::kEquationError;
  ModelComparison comparison(diagram, base_directory, source, log, settings.column_map);
  // The model's outputs get the measured outputs' filter (parallel filtering), else every Coulomb step of the
  // model leaves a spike in the residual that the diagnosis would try to explain.
  if (equation_error) comparison.set_output_filter(settings.derivative_cutoff_hz);
  out.before = comparison.Simulate();
  out.fitted_diagram = diagram;
  if (!fit_names.empty()) {
    out.parameters = ResolveFreeParameters(comparison.diagram_json(), fit_names);
    out.fit = FitParameters(comparison, out.parameters);
    comparison.SetParameterValues(out.parameters, out.fit->estimate);
    SetParameterValues(&out.fitted_diagram, out.parameters, out.fit->estimate);
  }
  out.after = comparison.Simulate();
  out.compared_diagram = comparison.diagram_json();
  out.notes = log.notes();
  if (!diagnose) {
    out.diagnosis_skipped = "no diagnosis asked for";
    return out;
  }
  const std::string velocity_column = DerivedVelocityColumn(settings.position_column);
  if (!log.has_column(settings.position_column) || !log.has_column(velocity_column)) {
    out.diagnosis_skipped = fmt::format("no diagnosis: the log has no position column '{}' (set --position-column)",
                                        settings.position_column);
    return out;
  }
  const ComparedOutput& primary = out.after.front();
  DiagnosisSignals& signals = out.signals;
  signals.time = log.time();
  signals.position = log.column(settings.position_column);
  signals.velocity = log.column(velocity_column);
  signals.acceleration = log.column(DerivedAccelerationColumn(settings.position_column));
  signals.residual = primary.residual();
  signals.model_output = primary.model;
  if (equation_error) signals.logged_command = primary.measured;
  // The grammar's column factor (effects/logged_column.cc): every log column the diagram does not read, by name.
  std::vector<std::string> read = {log.names().front(), settings.position_column, kMetresPositionColumn,
                                   velocity_column, DerivedAccelerationColumn(settings.position_column)};
  for (const auto& [connector, column] : comparison.input_columns()) read.push_back(column);
  for (const ComparedOutput& o : out.after) read.push_back(o.column);
  std::vector<std::string> unread;
  for (const std::string& name : log.names()) {
    if (std::find(read.begin(), read.end(), name) != read.end()) continue;
    // "element.port" columns are a simulation's own internal signals (a motionblocks run's log: the twin's
    // plant.disturbance is the hidden truth itself), not measurements of another physical quantity.
    if (name.find('.') != std::string::npos) continue;
    unread.push_back(name);
  }
  // Simulation mode: a column the loop computes from the very error being explained (a controller's output, a
  // current reference, a following error) is a reaction, not a cause; built into a candidate it would explain the
  // error by itself (issue 46). It is the diagram's own signal under another name — in the closed loop, or in the loop
  // opened at the measured position (OpenedLoopSignals), where the motion lacks nothing: left out, with a note.
  std::vector<std::pair<std::string, Eigen::VectorXd>> own;
  if (!equation_error) own = comparison.SimulateBlockOutputs();
  std::vector<std::pair<std::string, std::string>> reactions;  // log column → the diagram's signal it is
  std::optional<std::vector<std::pair<std::string, Eigen::VectorXd>>> opened;  // computed when first needed
  for (const std::string& name : unread) {
    const Eigen::VectorXd& column = log.column(name);
    const auto match = ClosestOwnSignal(column, own);
    if (match && match->second >= kReactionSquaredCorrelation) {
      reactions.emplace_back(name, match->first);
      out.reactions.emplace_back(name, SameScaleOwnSignal(column, own, kReactionSquaredCorrelation).value_or(match->first));
      out.notes.push_back(fmt::format(
          "log column '{}' is the diagram's own signal '{}' under another name (r² = {:.3f}): the closed loop "
          "computes it from the error being explained, a reaction and not a cause, so no candidate is built from it",
          name, match->first, match->second));
      continue;
    }
    std::optional<std::pair<std::string, double>> opened_match;
    if (!equation_error) {
      if (!opened) opened = OpenedLoopSignals(comparison, primary, &out.notes);
      opened_match = ClosestOwnSignal(column, *opened);
    }
    if (opened_match && opened_match->second >= kReactionSquaredCorrelation) {
      reactions.emplace_back(name, opened_match->first);
      out.reactions.emplace_back(
          name, SameScaleOwnSignal(column, *opened, kReactionSquaredCorrelation).value_or(opened_match->first));
      out.notes.push_back(fmt::format(
          "log column '{}' is the diagram's own signal '{}' computed from the measured '{}' (the loop opened there; "
          "r² = {:.3f}, {:.2f} in the closed loop, whose motion lacks what is missing): the controller computes it "
          "from the error being explained, a reaction and not a cause, so no candidate is built from it",
          name, opened_match->first, primary.column, opened_match->second, match ? match->second : 0.0));
      continue;
    }
    // A force the log holds that no signal of the loop follows, closed or opened at the measured position: the drive's
    // command of a controller the diagram does not reproduce (a clip, an anti-windup, another integrator), or a force
    // from outside the loop. Kept, and said.
    if (match && QuantityOfUnit(ColumnUnit(name)) == MotionQuantity::kForce) {
      out.notes.push_back(fmt::format(
          "log column '{}' is a force that no signal of the diagram follows (closest: '{}', r² = {:.2f} < {}{}): if it "
          "is the drive's command, the diagram's controller is not the one that ran (a clip, an anti-windup, an "
          "integrator or a filter that differs), which this record's position error holds too; it is kept as a "
          "column from outside the loop",
          name, match->first, match->second, kReactionSquaredCorrelation,
          opened_match ? fmt::format("; with the loop opened at the measured '{}': '{}', r² = {:.2f}", primary.column,
                                     opened_match->first, opened_match->second)
                       : std::string()));
    }
    signals.extra_names.push_back(name);
    signals.extra_columns.push_back(column);
  }
  // The fitted parameters' sensitivities are the base regressors: the diagnosis refits them jointly with each
  // candidate (DIAGNOSIS.md step 1).
  BaseRegressors& base = out.base;
  if (out.fit) {
    base.columns = out.fit->jacobian;
    for (const auto& p : out.parameters) base.names.push_back(p.name);
  } else {
    base.columns.resize(log.rows(), 0);
  }
  DiagnosisOptions options;
  if (equation_error) options.regressor_filter_hz = DerivativeCutoffHz(settings, log);  // parallel filtering
  options.position_unit = PositionUnitToken(settings.position_column);
  options.catalogue.every_pair = settings.every_pair;
  if (!equation_error) {  // a candidate force reaches the compared output through the closed loop
    // Plain least squares: the Huber weights are for the spikes a derived motion puts into an equation-error residual
    // (the model's sign(v) flipping while the machine dwells). A position error has none, and where the record dwells
    // it sits at the floor, so its robust scale is the floor's and every sample while the axis moves would be an
    // outlier: a payload picked up halfway, all in the moves, was weighted out (mean weight 0.85) and not named.
    // With the residual's own held-out errors an effect is named only above the floor (relevance_floor_ratio).
    options.huber_k = 0.0;
    options.relevance_floor_ratio = 0.83;
    const DiagramDocument document(comparison.diagram_json(), comparison.base_directory(), comparison.source());
    DriveForce drive = ModelDriveForce(document, out.after, own, reactions);
    out.drive_force_signal = drive.source;
    LoopProbe probe = ProbeLoop(comparison, primary, own, signals.velocity, drive.source);
    options.catalogue.loop = std::move(probe.loop);
    out.notes.push_back(std::move(probe.note));
    if (options.catalogue.loop) {  // the drive force's effects reach the output through the loop, or not at all
      signals.drive_force = std::move(drive.force);
      signals.drive_force_response = std::move(probe.drive_force);
      if (drive.source) signals.simulate_effect = EffectSimulator(comparison, primary, drive.source);

      out.drive_force_source = drive.source;
      out.notes.push_back(std::move(drive.note));
    }
  }
  out.diagnosis = DiagnoseMissingEffects(signals, base, options);
  out.notes.insert(out.notes.end(), out.diagnosis->notes.begin(), out.diagnosis->notes.end());
  return out;
}

json ComparedOutputsJson(const std::vector<ComparedOutput>& before, const std::vector<ComparedOutput>& after) {
  json outputs = json::array();
  for (std::size_t i = 0; i < after.size(); ++i) {
    outputs.push_back({{"connector", after[i].connector},
                       {"column", after[i].column},
                       {"unit", after[i].unit},
                       {"rmse_before", before[i].rmse},
                       {"rmse_after", after[i].rmse},
                       {"fit_percent_before", before[i].fit_percent},
                       {"fit_percent_after", after[i].fit_percent}});
    if (!after[i].tracking_input.empty()) {
      outputs.back()["tracking_input"] = after[i].tracking_input;
      outputs.back()["tracking_fit_percent_before"] = before[i].tracking_fit_percent;
      outputs.back()["tracking_fit_percent_after"] = after[i].tracking_fit_percent;
    }
  }
  return outputs;
}

json DiagramFit::ToJson() const {
  json j = fit.ToJson();
  j["output"] = after.front().connector;
  j["unit"] = after.front().unit;
  j["rmse_before"] = before.front().rmse;
  j["rmse_after"] = after.front().rmse;
  j["fit_percent_before"] = before.front().fit_percent;
  j["fit_percent_after"] = after.front().fit_percent;
  j["outputs"] = ComparedOutputsJson(before, after);
  return j;
}

}  // namespace mb

#include "engine/linearization.h"

#include <cmath>
#include <numbers>
#include <stdexcept>

#include <Eigen/LU>
#include <fmt/format.h>
#include <fmt/ranges.h>

#include "engine/simulator.h"

namespace mb {

namespace {

// linmod's perturbation: relative 1e-5, absolute near zero.
double Perturbation(double value) { return 1e-5 * (1.0 + std::abs(value)); }

nlohmann::json MatrixJson(const Eigen::MatrixXd& m) {
  nlohmann::json rows = nlohmann::json::array();
  for (Eigen::Index i = 0; i < m.rows(); ++i) {
    nlohmann::json row = nlohmann::json::array();
    for (Eigen::Index j = 0; j < m.cols(); ++j) row.push_back(m(i, j));
    rows.push_back(row);
  }
  return rows;
}

nlohmann::json SignalsJson(const std::vector<std::string>& names, const std::vector<std::string>& units,
                           const Eigen::VectorXd& values) {
  nlohmann::json out = nlohmann::json::array();
  for (std::size_t i = 0; i < names.size(); ++i) {
    out.push_back({{"name", names[i]}, {"unit", units[i]}, {"value", values(static_cast<Eigen::Index>(i))}});
  }
  return out;
}

// The input values of `point`, in connector order; throws for a name the diagram does not have.
Eigen::VectorXd OperatingInputs(const Diagram& diagram, const OperatingPoint& point) {
  const auto& inputs = diagram.inputs();
  Eigen::VectorXd u(static_cast<Eigen::Index>(inputs.size()));
  for (std::size_t k = 0; k < inputs.size(); ++k) u(static_cast<Eigen::Index>(k)) = inputs[k].default_value;
  for (const auto& [name, value] : point.inputs) {
    std::size_t k = 0;
    while (k < inputs.size() && inputs[k].name != name) ++k;
    if (k == inputs.size()) {
      std::vector<std::string> known;
      for (const auto& in : inputs) known.push_back(in.name);
      throw std::invalid_argument(fmt::format("linearize: diagram '{}' has no input connector '{}'; its inputs: {}",
                                              diagram.name(), name, known.empty() ? "none" : fmt::format("{}", fmt::join(known, ", "))));
    }
    if (!std::isfinite(value)) {
      throw std::invalid_argument(fmt::format("linearize: input '{}' = {} is not a finite number", name, value));
    }
    u(static_cast<Eigen::Index>(k)) = value;
  }
  return u;
}

}  // namespace

Eigen::VectorXcd LinearModel::FrequencyResponse(int output, int input, const Eigen::VectorXd& frequency_hz) const {
  if (output < 0 || output >= d.rows() || input < 0 || input >= d.cols()) {
    throw std::out_of_range(fmt::format("LinearModel::FrequencyResponse: output {} / input {} outside the {} × {} model",
                                        output, input, d.rows(), d.cols()));
  }
  const Eigen::Index n = a.rows();
  Eigen::VectorXcd h(frequency_hz.size());
  const Eigen::MatrixXcd ac = a.cast<std::complex<double>>();
  const Eigen::VectorXcd bj = b.col(input).cast<std::complex<double>>();
  const Eigen::RowVectorXcd ci = c.row(output).cast<std::complex<double>>();
  for (Eigen::Index k = 0; k < frequency_hz.size(); ++k) {
    std::complex<double> value = d(output, input);
    if (n > 0) {
      const std::complex<double> s(0.0, 2.0 * std::numbers::pi * frequency_hz(k));
      const Eigen::MatrixXcd resolvent = s * Eigen::MatrixXcd::Identity(n, n) - ac;
      value += (ci * resolvent.partialPivLu().solve(bj))(0);
    }
    h(k) = value;
  }
  return h;
}

nlohmann::json LinearModel::ToJson() const {
  return {{"time", time},
          {"states", SignalsJson(state_names, std::vector<std::string>(state_names.size()), x0)},
          {"inputs", SignalsJson(input_names, input_units, u0)},
          {"outputs", SignalsJson(output_names, output_units, y0)},
          {"A", MatrixJson(a)},
          {"B", MatrixJson(b)},
          {"C", MatrixJson(c)},
          {"D", MatrixJson(d)}};
}

LinearModel Linearize(const Diagram& diagram, const OperatingPoint& point) {
  LinearModel model;
  model.u0 = OperatingInputs(diagram, point);
  model.time = point.time.value_or(diagram.experiment().start_time);
  Simulator sim(diagram);
  for (std::size_t k = 0; k < diagram.inputs().size(); ++k) {
    const auto& in = diagram.inputs()[k];
    sim.SetInput(in.name, InputSeries{{model.time}, {model.u0(static_cast<Eigen::Index>(k))}});
    model.input_names.push_back(in.name);
    model.input_units.push_back(in.unit);
  }
  for (const auto& out : diagram.outputs()) {
    model.output_names.push_back(out.name);
    model.output_units.push_back(out.unit);
  }
  sim.Initialize(model.time);
  const int n = sim.num_continuous_states();
  const auto m = static_cast<Eigen::Index>(diagram.inputs().size());
  const auto p = static_cast<Eigen::Index>(diagram.outputs().size());
  for (int i = 0; i < n; ++i) model.state_names.push_back(sim.ContinuousStateName(i));
  const std::vector<double> x0 = sim.continuous_states();
  model.x0 = Eigen::Map<const Eigen::VectorXd>(x0.data(), n);
  model.a.resize(n, n);
  model.b.resize(n, m);
  model.c.resize(p, n);
  model.d.resize(p, m);

  std::vector<double> dx, y, dx_minus, y_minus;
  sim.EvaluateContinuousPart(x0, &dx, &y);
  model.y0 = Eigen::Map<const Eigen::VectorXd>(y.data(), p);
  // Column j of [A; C] and of [B; D] from the central difference of (ẋ, y) in state / input j.
  const auto store = [&](double h, Eigen::MatrixXd* top, Eigen::MatrixXd* bottom, Eigen::Index j) {
    for (int i = 0; i < n; ++i) (*top)(i, j) = (dx[static_cast<std::size_t>(i)] - dx_minus[static_cast<std::size_t>(i)]) / (2 * h);
    for (Eigen::Index i = 0; i < p; ++i) {
      (*bottom)(i, j) = (y[static_cast<std::size_t>(i)] - y_minus[static_cast<std::size_t>(i)]) / (2 * h);
    }
  };
  for (int j = 0; j < n; ++j) {
    std::vector<double> x = x0;
    const double h = Perturbation(x0[static_cast<std::size_t>(j)]);
    x[static_cast<std::size_t>(j)] = x0[static_cast<std::size_t>(j)] - h;
    sim.EvaluateContinuousPart(x, &dx_minus, &y_minus);
    x[static_cast<std::size_t>(j)] = x0[static_cast<std::size_t>(j)] + h;
    sim.EvaluateContinuousPart(x, &dx, &y);
    store(h, &model.a, &model.c, j);
  }
  for (Eigen::Index j = 0; j < m; ++j) {
    const double u = model.u0(j), h = Perturbation(u);
    sim.HoldInput(static_cast<std::size_t>(j), u - h);
    sim.EvaluateContinuousPart(x0, &dx_minus, &y_minus);
    sim.HoldInput(static_cast<std::size_t>(j), u + h);
    sim.EvaluateContinuousPart(x0, &dx, &y);
    sim.HoldInput(static_cast<std::size_t>(j), u);
    store(h, &model.b, &model.d, j);
  }
  return model;
}

BodeData ToBode(const Eigen::VectorXcd& response) {
  BodeData bode{Eigen::VectorXd(response.size()), Eigen::VectorXd(response.size())};
  double previous = 0.0;
  for (Eigen::Index k = 0; k < response.size(); ++k) {
    bode.gain_db(k) = 20.0 * std::log10(std::abs(response(k)));
    double phase = std::arg(response(k)) * 180.0 / std::numbers::pi;
    if (k > 0) phase -= 360.0 * std::round((phase - previous) / 360.0);  // unwrapped along frequency
    bode.phase_deg(k) = phase;
    previous = phase;
  }
  return bode;
}

Eigen::VectorXd LogSpacedFrequencies(double from_hz, double to_hz, int count) {
  if (!(from_hz > 0.0) || !(to_hz > from_hz) || !std::isfinite(to_hz) || count < 2) {
    throw std::invalid_argument(fmt::format("frequencies from {} Hz to {} Hz at {} points: need 0 < from < to (finite) "
                                            "and at least 2 points", from_hz, to_hz, count));
  }
  return Eigen::VectorXd::LinSpaced(count, std::log10(from_hz), std::log10(to_hz)).unaryExpr([](double e) {
    return std::pow(10.0, e);
  });
}

nlohmann::json LinearizationJson(const LinearModel& model, const Eigen::VectorXd& frequency_hz) {
  nlohmann::json out = model.ToJson();
  out["bode"] = nlohmann::json::array();
  const auto list = [](const Eigen::VectorXd& v) { return std::vector<double>(v.begin(), v.end()); };
  for (Eigen::Index o = 0; o < model.d.rows(); ++o) {
    for (Eigen::Index i = 0; i < model.d.cols(); ++i) {
      const BodeData bode = ToBode(model.FrequencyResponse(static_cast<int>(o), static_cast<int>(i), frequency_hz));
      out["bode"].push_back({{"output", model.output_names[static_cast<std::size_t>(o)]},
                             {"input", model.input_names[static_cast<std::size_t>(i)]},
                             {"frequency_hz", list(frequency_hz)},
                             {"gain_db", list(bode.gain_db)},
                             {"phase_deg", list(bode.phase_deg)}});
    }
  }
  return out;
}

}  // namespace mb

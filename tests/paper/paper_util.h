#pragma once
// Helpers for the paper tests: inline diagrams around the linear-motor twin and sinusoid fitting.

#include <cmath>
#include <complex>
#include <numbers>
#include <string>
#include <vector>

#include <Eigen/Dense>
#include <nlohmann/json.hpp>

#include "engine/diagram_loader.h"
#include "engine/simulator.h"

namespace mb::paper_testing {

inline constexpr double kPi = std::numbers::pi;

inline nlohmann::json Connect(const std::string& from, const std::string& to) {
  const auto a = from.find('.'), b = to.find('.');
  return {{"startElement", from.substr(0, a)}, {"startConnector", from.substr(a + 1)},
          {"endElement", to.substr(0, b)}, {"endConnector", to.substr(b + 1)}};
}
inline nlohmann::json FromInput(const std::string& connector, const std::string& to) {
  const auto b = to.find('.');
  return {{"startConnector", connector}, {"endElement", to.substr(0, b)}, {"endConnector", to.substr(b + 1)}};
}

/// A rigid, disturbance-free twin (P = P_n unless mass/damping given), ideal encoder unless resolution given.
inline nlohmann::json RigidPlant(double mass = 0.2621, double damping = 3.0, double resolution = 0.0) {
  return {{"name", "plant"},
          {"type", "linear_motor"},
          {"parameters",
           {{"mass", mass}, {"damping", damping}, {"cogging_amplitude", 0.0}, {"cogging_amplitude_velocity", 0.0},
            {"coulomb_friction", 0.0}, {"static_friction", 0.0}, {"viscous_squared", 0.0},
            {"encoder_resolution", resolution}}}};
}

/// The conventional loop with the reference (position, velocity, acceleration) and an input disturbance d
/// from diagram input connectors, d added to the plant input: x = P(u_c + d). The reference and the encoder are
/// sampled (zero_order_hold) so that the error sum and the gains act on samples, as in the paper's diagrams.
inline nlohmann::json LoopWithInputs(const nlohmann::json& plant, double q_cutoff_hz, double kp, double kd,
                                     double stop_time, double solver_step = 1e-4) {
  const nlohmann::json ts = {0.001, 0.0};
  return {{"schemaVersion", "1.0"},
          {"defaultExperiment", {{"stopTime", stop_time}, {"stepSize", 0.001}}},
          {"solver", {{"type", "rk4"}, {"step", solver_step}}},
          {"connectors",
           {{{"name", "x_d"}, {"kind", "input"}, {"unit", "m"}},
            {{"name", "v_d"}, {"kind", "input"}, {"unit", "m/s"}},
            {{"name", "a_d"}, {"kind", "input"}, {"unit", "m/s^2"}},
            {{"name", "d"}, {"kind", "input"}, {"unit", "N"}}}},
          {"elements",
           {{{"name", "feedforward"}, {"type", "nominal_inverse"}, {"sampleTime", ts}},
            {{"name", "error"}, {"type", "sum"}, {"parameters", {{"signs", "+-"}}}},
            {{"name", "pd_p"}, {"type", "gain"}, {"parameters", {{"gain", kp}}}},
            {{"name", "pd_derivative"}, {"type", "velocity_estimator"}, {"sampleTime", ts},
             {"parameters", {{"cutoff_hz", 300.0}}}},
            {{"name", "pd_d"}, {"type", "gain"}, {"parameters", {{"gain", kd}}}},
            {{"name", "u_c"}, {"type", "sum"}, {"parameters", {{"signs", "+++-"}}}},
            {{"name", "dob"}, {"type", "dob"}, {"sampleTime", ts}, {"parameters", {{"cutoff_hz", q_cutoff_hz}}}},
            {{"name", "force"}, {"type", "sum"}, {"parameters", {{"signs", "++"}}}},
            {{"name", "encoder"}, {"type", "zero_order_hold"}, {"sampleTime", ts}},
            {{"name", "reference"}, {"type", "zero_order_hold"}, {"sampleTime", ts}},
            plant}},
          {"connections",
           {FromInput("v_d", "feedforward.velocity"), FromInput("a_d", "feedforward.acceleration"),
            FromInput("x_d", "reference.u"), Connect("reference.y", "error.u1"), Connect("plant.x", "encoder.u"), Connect("encoder.y", "error.u2"), Connect("error.y", "pd_p.u"),
            Connect("error.y", "pd_derivative.x"), Connect("pd_derivative.velocity", "pd_d.u"),
            Connect("feedforward.y", "u_c.u1"), Connect("pd_p.y", "u_c.u2"), Connect("pd_d.y", "u_c.u3"),
            Connect("dob.d_hat", "u_c.u4"), Connect("encoder.y", "dob.x"), Connect("u_c.y", "dob.u_c"),
            Connect("u_c.y", "force.u1"), FromInput("d", "force.u2"), Connect("force.y", "plant.u")}},
          {"log", {"plant.x", "plant.x_true", "error.y", "dob.d_hat", "u_c.y"}}};
}

/// Samples f(t) on [0, stop] every `dt` as an input series.
template <class F>
InputSeries Series(F f, double stop, double dt = 1e-4) {
  InputSeries s;
  for (double t = 0.0; t <= stop + 1e-12; t += dt) {
    s.time.push_back(t);
    s.values.push_back(f(t));
  }
  return s;
}

/// Least-squares fit y ≈ Re(c·e^{jωt}) + offset over samples with t ≥ t_from; returns c (amplitude and phase).
inline std::complex<double> FitSinusoid(const std::vector<double>& t, const std::vector<double>& y, double omega,
                                        double t_from) {
  std::vector<std::size_t> rows;
  for (std::size_t i = 0; i < t.size(); ++i) {
    if (t[i] >= t_from) rows.push_back(i);
  }
  Eigen::MatrixXd A(static_cast<Eigen::Index>(rows.size()), 3);
  Eigen::VectorXd b(static_cast<Eigen::Index>(rows.size()));
  for (std::size_t r = 0; r < rows.size(); ++r) {
    const auto i = static_cast<Eigen::Index>(r);
    A(i, 0) = std::cos(omega * t[rows[r]]);
    A(i, 1) = -std::sin(omega * t[rows[r]]);
    A(i, 2) = 1.0;
    b(i) = y[rows[r]];
  }
  const Eigen::Vector3d c = A.colPivHouseholderQr().solve(b);
  return {c(0), c(1)};
}

}  // namespace mb::paper_testing

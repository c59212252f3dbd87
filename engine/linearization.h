#pragma once
// A diagram linearised about an operating point: ẋ = A x + B u, y = C x + D u, and its frequency response
// C (jωI − A)⁻¹ B + D — Simulink's `linmod` (numerical perturbation of the continuous states and the inputs; its
// default relative step 1e-5), with `linmod`'s treatment of a hybrid diagram: discrete blocks hold their outputs at
// the operating point, so a path through a discrete block is open (its effect is a constant, not a dynamic).
//
// u holds the diagram's input connectors (diagram.inputs() order, each in its connector's unit), y its output
// connectors (diagram.outputs() order), x its continuous states in block order (Simulator::ContinuousStateName).

#include <complex>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "engine/diagram.h"

namespace mb {

/// Where the diagram is linearised.
struct OperatingPoint {
  /// Input connector values (name → value, in the connector's unit); an input not named holds its connector's
  /// default (0 for a required input).
  std::map<std::string, double> inputs;
  /// The time [s] at which the diagram is initialised (its continuous states are their initial values there, as
  /// linmod's default x0); none: the experiment's start time.
  std::optional<double> time;
};

/// A linear time-invariant model of a diagram's continuous part.
struct LinearModel {
  Eigen::MatrixXd a;  ///< n × n [1/s]
  Eigen::MatrixXd b;  ///< n × m
  Eigen::MatrixXd c;  ///< p × n
  Eigen::MatrixXd d;  ///< p × m (direct feedthrough)
  std::vector<std::string> state_names;                ///< n: "block 'plant' continuous state 0 of 2"
  std::vector<std::string> input_names, input_units;    ///< m: the input connectors
  std::vector<std::string> output_names, output_units;  ///< p: the output connectors
  Eigen::VectorXd x0;                                   ///< the operating point's state (n)
  Eigen::VectorXd u0;                                   ///< the operating point's inputs (m)
  Eigen::VectorXd y0;                                   ///< the outputs there (p)
  double time = 0.0;                                    ///< [s]

  /// The response of output `output` to input `input` at each frequency [Hz] (K values): C (j2πf I − A)⁻¹ B + D,
  /// in output unit per input unit. @throws std::out_of_range for an index outside the model.
  Eigen::VectorXcd FrequencyResponse(int output, int input, const Eigen::VectorXd& frequency_hz) const;
  /// {"time", "states", "inputs" [{name, unit, value}], "outputs" [{name, unit, value}], "A", "B", "C", "D"}
  /// (matrices as arrays of rows).
  nlohmann::json ToJson() const;
};

/// Linearises `diagram` about `point` by central differences of its continuous part (Simulator::
/// EvaluateContinuousPart): each state and input is moved by ±1e-5·(1 + |value|).
/// @throws std::invalid_argument naming an unknown input connector (with the known ones), and what Simulator's
/// Initialize throws (a required input is not named is no error: it holds 0).
LinearModel Linearize(const Diagram& diagram, const OperatingPoint& point = {});

/// K frequencies [Hz] spaced evenly in log between `from` and `to` (0 < from < to, K >= 2).
/// @throws std::invalid_argument otherwise.
Eigen::VectorXd LogSpacedFrequencies(double from_hz, double to_hz, int count);

/// Bode's form of a response: gain [dB] = 20 log10 |H| and phase [deg], unwrapped along frequency.
struct BodeData {
  Eigen::VectorXd gain_db;
  Eigen::VectorXd phase_deg;
};
BodeData ToBode(const Eigen::VectorXcd& response);

/// The model (LinearModel::ToJson) and its Bode data at `frequency_hz`: "bode": [{"output", "input",
/// "frequency_hz", "gain_db", "phase_deg"}], one entry per output–input pair — what `motionblocks linearize` writes.
nlohmann::json LinearizationJson(const LinearModel& model, const Eigen::VectorXd& frequency_hz);

}  // namespace mb

#pragma once
// Model versus measurement (MATLAB System Identification Toolbox's `compare`, DIAGNOSIS.md): drive a diagram's
// input connectors with measured columns, read its output connectors at the measured times, score them (RMSE,
// fit %), refit chosen parameters by nonlinear least squares (Levenberg–Marquardt, Eigen's unsupported
// NonLinearOptimization module) with confidence intervals.
//
// The two modes are the same mechanism with different connectors: equation-error (inverse model: measured
// motion in, model force out, compared with the measured force) and simulation (measured reference in,
// simulated position/force out).

#include <filesystem>
#include <limits>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "engine/diagram.h"
#include "engine/diagram_document.h"
#include "engine/experiment_mode.h"
#include "engine/simulator.h"
#include "models/diagnosis/diagnosis.h"
#include "models/diagnosis/measurement_log.h"
#include "tools/workflow/measurement.h"

namespace mb {


/// One scalar the fit may change: element `block`, parameter `parameter`, entry `index` of a vector (or -1 for
/// a scalar). `name` is "block.param" or "block.param[i]". `unit` is the parameter's SI unit on the diagram's axis
/// (DiagramDocument::ParameterSpec: N·m·s/rad for a friction's viscous coefficient on a rotary diagram in rad and
/// N·m, N·s/m on a linear one; "" for a dimensionless or free one such as a gain).
struct FreeParameter {
  std::string block;
  std::string parameter;
  int index = -1;
  std::string name;
  std::string unit;
  /// The bounds the block declares (ParamSpec::min/max; ±inf without): the fit keeps its trial values within them.
  double lower = -std::numeric_limits<double>::infinity();
  double upper = std::numeric_limits<double>::infinity();
};

/// Expands "block.param" names (a vector parameter gives one FreeParameter per entry) against the diagram JSON.
/// @throws std::invalid_argument naming an unknown block or parameter, or a non-numeric one.
std::vector<FreeParameter> ResolveFreeParameters(const nlohmann::json& diagram, const std::vector<std::string>& names);

/// Reads / writes the current values of free parameters in the diagram JSON (values given as numbers or as
/// {"value", "unit"}; a parameter absent from the JSON reads its block default — pass `defaults`).
Eigen::VectorXd GetParameterValues(const nlohmann::json& diagram, const std::vector<FreeParameter>& params);
void SetParameterValues(nlohmann::json* diagram, const std::vector<FreeParameter>& params,
                        const Eigen::Ref<const Eigen::VectorXd>& values);

/// One output connector compared with its measured column.
struct ComparedOutput {
  std::string connector;
  std::string column;
  std::string unit;
  Eigen::VectorXd measured;
  Eigen::VectorXd model;
  double rmse = 0.0;
  double fit_percent = 0.0;
  /// Simulation mode, an output with an input in its unit (the position and its reference): the model's tracking
  /// error r − ŷ against the measured one r − y, 100 (1 − ‖y − ŷ‖ / ‖(r − y) − mean‖) [%] — what "fit" means for a
  /// closed loop, whose position the reference dominates (its fit is 100.0 % for any model that tracks). NaN when no
  /// input shares the output's unit; `tracking_input` names the input connector ("" then).
  double tracking_fit_percent = std::numeric_limits<double>::quiet_NaN();
  std::string tracking_input{};
  Eigen::VectorXd residual() const { return measured - model; }
};

/// Per compared output, before and after a refit (same order and length): [{"connector", "column", "unit",
/// "rmse_before", "rmse_after", "fit_percent_before", "fit_percent_after"}, and where defined "tracking_input",
/// "tracking_fit_percent_before", "tracking_fit_percent_after"] — the "outputs" of compare.json and
/// fit.json. RMSE in the output's unit, fit in % (FitPercent).
nlohmann::json ComparedOutputsJson(const std::vector<ComparedOutput>& before, const std::vector<ComparedOutput>& after);

/// A diagram bound to a measurement: simulate it with any parameter values along the measured record.
class ModelComparison {
 public:
  /// `column_map` overrides connector → column (default: each connector's "measurement" name). The diagram's
  /// experiment is set to the log's time span and median step. @throws std::invalid_argument if a required
  /// input's or any output's column is missing (listing the columns present) or no output can be compared.
  ModelComparison(nlohmann::json diagram, std::filesystem::path base_directory, std::string source,
                  const MeasurementLog& log, const std::map<std::string, std::string>& column_map);

  /// Simulates with the diagram JSON as it is and returns every compared output.
  std::vector<ComparedOutput> Simulate() const;
  /// Same with the given free-parameter values written in first.
  std::vector<ComparedOutput> Simulate(const std::vector<FreeParameter>& params,
                                       const Eigen::Ref<const Eigen::VectorXd>& values) const;

  /// Every scalar block output of the diagram ("block.port", at most `max_signals` of them, in block order) simulated
  /// along the record and interpolated onto the measured time stamps (each N): the diagram's own signals, against
  /// which a log column computed inside the loop is recognised (UnreadColumnReaction). Throws as Simulate.
  std::vector<std::pair<std::string, Eigen::VectorXd>> SimulateBlockOutputs(std::size_t max_signals = 200) const;

  /// Equation-error parallel filtering (IDIM-LS): pass every simulated output through the same zero-phase
  /// low-pass as the measured outputs (ReadMeasurementWithDerivatives' `filter_columns`), so that both sides of
  /// the residual have the same band — a Coulomb step of the model is smoothed like the measured one instead of
  /// leaving a spike at every reversal. cutoff_hz <= 0: off (the default).
  void set_output_filter(double cutoff_hz) { output_filter_hz_ = cutoff_hz; }
  double output_filter_hz() const { return output_filter_hz_; }
  /// The weight a refit gives each sample (N, the log's rows): InteriorWeights (models/diagnosis/signal_processing.h)
  /// at the output filter's cut-off when it is on — 0 where the derived motion is still the filter's edge transient
  /// (it reads its own reflection; a record that opens with a controller's kick leaves there a spike a hundred times
  /// the noise, which a refit would otherwise bend the model to: a third factor of time, largest at the record's ends,
  /// fitted the kick, not the drift), else 1. All ones when the filter is off. @throws std::invalid_argument as
  /// DerivativeCutoffHz (a cut-off at or above the log's Nyquist frequency). Source: Gustafsson 1996
  /// (FilterEdgeSamples).
  Eigen::VectorXd FitWeights() const;

  const nlohmann::json& diagram_json() const { return diagram_; }
  /// Writes free-parameter values (one per entry of `params`, in the units the diagram stores them in) into the
  /// diagram, as the refit's trial values are written; numbers replace numbers, so the schema check made at
  /// construction still holds. @throws as the free SetParameterValues.
  void SetParameterValues(const std::vector<FreeParameter>& params, const Eigen::Ref<const Eigen::VectorXd>& values);
  const std::map<std::string, std::string>& input_columns() const { return input_columns_; }
  /// Every connector bound to a column (inputs and compared outputs): a column_map that binds a variant of the diagram
  /// (the same connectors) to the log as this one is.
  std::map<std::string, std::string> ColumnMap() const;
  const MeasurementLog& log() const { return log_; }
  const std::filesystem::path& base_directory() const { return base_; }
  const std::string& source() const { return source_; }

 private:
  nlohmann::json diagram_;
  std::filesystem::path base_;
  std::string source_;
  const MeasurementLog& log_;
  std::map<std::string, std::string> input_columns_;
  std::map<std::string, std::string> output_columns_;
  double output_filter_hz_ = 0.0;
  /// Simulates `d` (built from diagram_ or a copy of it) along the record: its logged signals.
  SignalLog Run(const Diagram& d) const;
  // Invariant: diagram_ passed the schema at construction and can since change only through SetParameterValues
  // (numbers for numbers), so each simulation (hundreds per refit) builds it with SchemaCheck::kSkipRevalidation.
};

/// Result of a least-squares refit.
struct FitResult {
  std::vector<FreeParameter> parameters;
  Eigen::VectorXd initial;
  Eigen::VectorXd estimate;
  Eigen::VectorXd standard_error;  ///< sqrt(diag(σ² (JᵀJ)⁻¹)), σ² = SSR/(N − p)
  Eigen::MatrixXd jacobian;        ///< d(model output)/d(parameter) of the primary output at the estimate (N × p)
  double condition_number = 0.0;   ///< of the column-scaled Jacobian
  int iterations = 0;
  std::string status;              ///< Levenberg–Marquardt's ("converged (cost)", …) or "not identifiable"
  /// Identifiability at the estimate (issue 30: a fit on a log without motion reported a huge "converged" mass).
  /// A parameter has no effect when its Jacobian column changes the output by less than kNoEffectRelative of the
  /// output's norm over its whole value; parameters cannot be told apart when the column-scaled Jacobian of the
  /// others has a condition number above kMaxIdentifiableCondition (they lie in the null space of its smallest
  /// singular vectors). Their standard errors are +inf (null in JSON): nothing was estimated.
  bool identifiable = true;
  std::vector<std::string> no_effect;                      ///< parameters the log does not excite
  std::vector<std::vector<std::string>> indistinguishable;  ///< groups that change the output alike
  std::string identifiability_problem;  ///< what is wrong and how to fix it, for messages (empty when identifiable)
  /// {"parameters": [{name, unit, initial, estimate, standard_error, ci95}], iterations, status, condition_number,
  /// identifiable, and when not: "not_identifiable": {no_effect, cannot_be_told_apart}, "warning"}.
  nlohmann::json ToJson() const;
};

/// Above this condition number of the column-scaled Jacobian, parameters cannot be told apart (an identifiable fit
/// of real data is below 1e3: EMPS 4.3; an exact collinearity gives 1e8 and more through the finite differences).
inline constexpr double kMaxIdentifiableCondition = 1e6;
/// A parameter whose whole value moves the output by less than this fraction of the output's norm has no effect.
inline constexpr double kNoEffectRelative = 1e-9;
/// In simulation mode a log column whose centred record matches one of the diagram's own signals
/// (ModelComparison::SimulateBlockOutputs) with at least this squared correlation is that signal under another name —
/// computed inside the loop, a reaction to the error — and is kept out of the diagnosis (CompareAndDiagnose notes it).
/// A controller's logged output against its simulated twin: r² = 0.9 and more where the model is fair (EMPS: see
/// docs/diagnosis.md); an exogenous column (a temperature, another axis) follows no signal of the loop this closely.
inline constexpr double kReactionSquaredCorrelation = 0.8;

/// Minimises Σ over compared outputs of ‖(measured − model)/scale‖², scale = each output's measured standard
/// deviation, over the free parameters (Levenberg–Marquardt, forward-difference Jacobian whose p + 1 simulations run
/// in parallel on TBB's threads). The primary output is
/// the first compared output. Reports parameters it cannot estimate in FitResult::identifiable and its neighbours
/// (it does not throw for them: compare and improve go on and say so in their JSON; `fit` exits 3).
/// @throws std::invalid_argument for an empty parameter list.
FitResult FitParameters(const ModelComparison& comparison, const std::vector<FreeParameter>& params);

/// What `motionblocks fit` computes: the chosen parameters of a diagram refit against a measurement (simulation or
/// equation-error, as the diagram's experiment.mode says), the outputs before and after, and the diagram with the
/// estimates written in.
struct DiagramFit {
  FitResult fit;
  std::vector<ComparedOutput> before, after;  ///< every compared output; the first is the primary
  nlohmann::json fitted_diagram;              ///< the input diagram (its own defaultExperiment) with the estimates
  /// fit.json: rmse/fit % before and after (primary and per output), the estimates with standard errors and 95 %
  /// confidence intervals (estimate ± 1.96·SE, from the Jacobian at the estimate), iterations, status, condition
  /// number of the scaled Jacobian.
  nlohmann::json ToJson() const;
};

/// Refits `parameter_names` ("block.param", vectors expand to each entry) of `diagram` against `log`. In
/// equation-error mode pass the measured outputs' filter cut-off as `output_filter_hz` (parallel filtering, see
/// ModelComparison::set_output_filter; 0 = none). @throws std::invalid_argument as ModelComparison,
/// ResolveFreeParameters and FitParameters (empty list); NumericalError (engine/numerical_error.h) when the RMSE
/// before or after, an estimate or a standard error of an identifiable parameter is not finite (the message names
/// which, and the largest measured value: values near 1e300 overflow).
DiagramFit FitDiagram(const nlohmann::json& diagram, const std::filesystem::path& base_directory,
                      const std::string& source, const MeasurementLog& log,
                      const std::map<std::string, std::string>& column_map,
                      const std::vector<std::string>& parameter_names, double output_filter_hz);

/// One `compare`: the diagram bound to a log, its free parameters refit, its primary output's residual diagnosed.
struct DiagnosedComparison {
  ExperimentMode mode = ExperimentMode::kSimulation;
  std::vector<FreeParameter> parameters;   ///< what was refit (empty: nothing)
  std::optional<FitResult> fit;            ///< set when parameters is not empty
  std::vector<ComparedOutput> before;      ///< every compared output as given; the first is the primary
  std::vector<ComparedOutput> after;       ///< after the refit
  nlohmann::json fitted_diagram;           ///< the input diagram (its own defaultExperiment) with the estimates
  nlohmann::json compared_diagram;         ///< the same, its defaultExperiment set to the log's span and step
  std::optional<DiagnosisResult> diagnosis;
  std::string diagnosis_skipped;           ///< why there is no diagnosis (no position column, or not asked)
  /// The log's intake notes (MeasurementLog::notes), then the diagnosis's (candidates skipped, evidence, caveats).
  std::vector<std::string> notes;
  DiagnosisSignals signals;                ///< what the diagnosis was given (residual = the primary's after the refit)
  /// Simulation mode: the diagram's signal holding the model's drive force (ModelDriveForce, loop_probe.h), which the
  /// blocks of the force constant's effects multiply (SuggestAmendedDiagram); none in equation-error mode.
  std::optional<Endpoint> drive_force_source;
  /// Simulation mode: ModelDriveForce's signal whether or not the loop could be probed (the equation-error view's
  /// drive force, equation_error_view.h).
  std::optional<Endpoint> drive_force_signal;
  /// Simulation mode: each log column recognised as the loop's own signal (a reaction, kept out of the candidates),
  /// with the signal it equals ("element.port"; of those it follows, the closest in scale), in the log's order.
  std::vector<std::pair<std::string, std::string>> reactions;
  BaseRegressors base;                     ///< the fitted parameters' sensitivities (N × p; p = 0 if nothing fit)
};

/// What `motionblocks compare` computes: simulate `diagram` along `log` (equation-error diagrams with the output
/// low-pass of parallel filtering), refit `fit_names` ("block.param"; empty: nothing) by Levenberg–Marquardt, and,
/// if `diagnose` and the log has the position and derived velocity, rank the missing effects of the primary
/// output's residual with the fitted parameters' sensitivities as base regressors (DiagnoseMissingEffects). `log`
/// must come from ReadMeasurementFor with the same settings. @throws std::invalid_argument as ModelComparison
/// (missing columns), ResolveFreeParameters (unknown parameter) and DiagnoseMissingEffects.
DiagnosedComparison CompareAndDiagnose(const nlohmann::json& diagram, const std::filesystem::path& base_directory,
                                       const std::string& source, const MeasurementLog& log,
                                       const MeasurementSettings& settings,
                                       const std::vector<std::string>& fit_names, bool diagnose = true);

/// Jacobian d(primary model output)/d(params) by central differences at `values` (N × p); the 2p simulations run in
/// parallel.
Eigen::MatrixXd OutputJacobian(const ModelComparison& comparison, const std::vector<FreeParameter>& params,
                               const Eigen::Ref<const Eigen::VectorXd>& values);

}  // namespace mb

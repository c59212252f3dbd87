#pragma once
// Runs a Diagram: multi-rate scheduling of discrete blocks at their sample hits, continuous states integrated
// between major steps by the diagram's solver, zero crossings located and modes updated, signals logged.
// The order within a step is documented in engine/block.h and docs/engine.md.

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include "engine/diagram.h"
#include "engine/log_sink.h"
#include "engine/solver.h"

namespace mb {

/// Logged signals on the log grid: time [s] and one column per logged scalar (a width-n signal gives columns
/// "name[0]" … "name[n-1]").
struct SignalLog {
  std::vector<double> time;
  std::vector<std::string> names;
  std::vector<std::vector<double>> columns;
  /// The column named `name`. @throws std::invalid_argument listing the logged names.
  const std::vector<double>& Column(const std::string& name) const;
  bool Has(const std::string& name) const;
};

struct SimulationResult {
  SignalLog log;
  std::map<std::string, double> metrics;  ///< name → value in SI units
  SolverStats solver_stats;
  std::string solver_name;
  double wall_time_s = 0.0;
};

/// A time series fed to a diagram input connector: linear interpolation, held constant outside its range.
struct InputSeries {
  std::vector<double> time;    ///< strictly increasing [s]
  std::vector<double> values;  ///< same length
};

/// What a run may cost before it starts (checked by Simulator::Initialize).
struct SimulationLimits {
  /// Refuse a run estimated to take more major or fixed solver steps than this (the finest of the log interval,
  /// the discrete sample times and a fixed solver step over the run), or to log more values (samples × logged
  /// scalars; 8 bytes each) than this. The command line's --max-steps, which must be finite and lie in
  /// [1, kMaxSimulationSteps]; a Simulator built in code also takes +infinity (no limit: the virtual stage, which
  /// runs until stopped), never NaN (which would turn the check off without a word).
  double max_steps = 1e8;
  /// Refuse more than this many zero-crossing events between two major steps (a Zeno loop: events that do not
  /// let time advance).
  long max_events_per_major_step = 10000;
};

/// One metric (Diagram's metrics: rmse, rms_difference, max_abs, mean, final) accumulated sample by sample over its
/// window [from, to]: what ComputeMetrics computes on a log in memory and StreamLogTo on a streamed one.
struct MetricAccumulator {
  double sum = 0.0, sum_sq = 0.0, max_abs = 0.0, last = 0.0;
  std::size_t n = 0;
  void Add(double x);
  /// The metric of type `type` ("rmse", …). @throws std::invalid_argument without a sample (naming `name` and the
  /// window [from, to] s).
  double Value(MetricType type, const std::string& name, double from, double to) const;
};

/// The ceiling of SimulationLimits::max_steps: 1e13 steps (days of computing at any step rate; 80 TB of one logged
/// signal).
inline constexpr double kMaxSimulationSteps = 1e13;

/// Checks limits: max_steps finite in [1, kMaxSimulationSteps], max_events_per_major_step >= 1.
/// @throws std::invalid_argument "--max-steps nan: the step limit must be a finite number in [1, 1e+13] …".
void CheckSimulationLimits(const SimulationLimits& limits);

/// The limits a Simulator gets when none are given: SimulationLimits{} until SetDefaultSimulationLimits (the
/// command line's --max-steps sets it once, before any run). Thread-safe.
SimulationLimits DefaultSimulationLimits();
/// @throws std::invalid_argument as CheckSimulationLimits (the defaults are then unchanged).
void SetDefaultSimulationLimits(const SimulationLimits& limits);

class Simulator final : private OdeSystem {
 public:
  /// Lays out all signal and state storage (the only allocation). The diagram must outlive the simulator.
  /// @throws std::invalid_argument if limits.max_steps is NaN or below 1 (+infinity: no limit).
  explicit Simulator(const Diagram& diagram, SimulationLimits limits = DefaultSimulationLimits());
  ~Simulator() override;

  /// Feeds diagram input connector `name`. @throws std::invalid_argument for an unknown name, mismatched lengths,
  /// or non-increasing time. Inputs not set read their connector's default value (optional inputs) or throw at
  /// Initialize (required ones).
  void SetInput(const std::string& name, InputSeries series);
  /// Real time (the virtual stage's analog outputs): input connector `index` (diagram.inputs() order), already fed a
  /// one-point series by SetInput, holds `value` from now on — what SetInput(name, {{t}, {value}}) does, without the
  /// name lookup, the allocation or an exception. Returns false, changing nothing, for any other input.
  bool HoldInput(std::size_t index, double value) noexcept;

  /// Streams every logged sample to `sink` (it must outlive the runs) instead of holding the log in memory: log()
  /// then keeps at most `max_samples_in_memory` rows (0 = none) for figures: the envelope of the log, each stretch of
  /// k samples as two rows — its first time with every signal's minimum over the stretch, its latest time with every
  /// maximum — so that no peak is lost however long the run (k = 1: every sample);
  /// the metrics are accumulated sample by sample (StreamedMetrics: the values ComputeMetrics gives on the whole
  /// log), and SimulationLimits' bound on the log's size applies to what stays in memory only (the bound on steps
  /// still applies). Call before Initialize; nullptr returns to the in-memory log.
  void StreamLogTo(LogSink* sink, std::size_t max_samples_in_memory = 0);
  /// The diagram's metrics accumulated over a streamed run so far (empty without StreamLogTo).
  /// @throws std::invalid_argument as ComputeMetrics for a metric window without a sample.
  std::map<std::string, double> StreamedMetrics() const;
  /// How many samples were logged since Initialize (streamed or kept).
  long long logged_samples() const { return logged_samples_; }

  /// Called with (t, t_stop) roughly every 2 % of simulated time.
  void SetProgressCallback(std::function<void(double, double)> callback) { progress_ = std::move(callback); }

  /// Initialises states at the experiment's start time (or `start_time`), computes outputs, makes modes
  /// consistent, and reserves the log (never more than the limits allow).
  /// @throws std::runtime_error if a required input is not set; std::invalid_argument (with the fix) if the log
  /// interval (defaultExperiment.stepSize), a discrete sample time or the fixed solver step is longer than the run
  /// or vanishes next to the run's times (t + dt == t), or the run exceeds the limits (SimulationLimits);
  /// NumericalError if an initial output is NaN/Inf.
  void Initialize();
  void Initialize(double start_time);
  /// Advances through major steps until `t` (logging on the log grid). Requires Initialize.
  /// @throws NumericalError (engine/numerical_error.h) at the step where a block output or a state becomes NaN or
  /// Inf (naming the block, the port or state, and the time), when the solver fails, or when zero-crossing events
  /// repeat without reaching the next major step (SimulationLimits::max_events_per_major_step; names the block).
  void AdvanceTo(double t);
  /// Initialize + AdvanceTo(stop time) + metrics.
  SimulationResult Run();

  double time() const { return time_; }
  /// The diagram's continuous states now, in block order (num_continuous_states() values).
  const std::vector<double>& continuous_states() const { return xc_; }
  int num_continuous_states() const { return num_continuous_; }
  /// "block 'name' continuous state k of n" for continuous state i in [0, num_continuous_states()).
  std::string ContinuousStateName(int i) const { return DescribeState(i); }
  /// The continuous part of the diagram about the current point, for linearisation (engine/linearization.h, as
  /// Simulink's linmod): at time() with continuous state `x` (num_continuous_states() values) and the inputs as held
  /// now (SetInput / HoldInput), every non-discrete block recomputes its outputs (discrete blocks hold theirs: their
  /// paths stay open) and the continuous-state blocks their derivatives. Writes the derivatives to `dx` and the
  /// diagram's output connectors (diagram.outputs() order) to `y`, then restores the simulator's own state.
  /// @throws std::logic_error before Initialize; std::invalid_argument if x has the wrong size.
  void EvaluateContinuousPart(const std::vector<double>& x, std::vector<double>* dx, std::vector<double>* y);
  /// Current value of a signal (first element for a wide signal).
  double SignalValue(const SignalRef& ref) const;
  const SignalLog& log() const { return log_; }
  const SolverStats& solver_stats() const;

  /// Computes the diagram's metrics from a log. @throws std::invalid_argument if a metric's signal is not logged.
  static std::map<std::string, double> ComputeMetrics(const Diagram& diagram, const SignalLog& log);

 private:
  // OdeSystem
  int num_states() const override { return num_continuous_; }
  int num_roots() const override { return num_roots_; }
  void Derivatives(double t, const double* x, double* dx) override;
  void Roots(double t, const double* x, double* g) override;
  std::string DescribeNonFinite(const double* x) const override;

  // Construction's phases, in this order (simulator_setup.cc): signal storage and each context's port pointers;
  // state storage, each context's state pointers and the discrete blocks; minor_step_order_; the inputs' series,
  // the log grid and the logged columns.
  void LayOutSignals();
  void LayOutStates();
  void OrderMinorSteps();
  void LayOutInputsAndLog();
  // Refuses runs that cannot advance or exceed limits_ (Initialize's checks).
  void CheckRunLength(double start_time) const;
  // Throws NumericalError if a block output or state is NaN/Inf at major time t.
  void CheckFinite(double t) const;
  // Integrates to t_next, handling zero crossings before it; returns whether one was located at t_next.
  bool IntegrateTo(double t_next);
  // "block 'name' (continuous state k of n)" for entry i of the continuous states / root functions.
  std::string DescribeState(int i) const;
  std::string DescribeRoot(int i) const;
  void UpdateInputs(double t);
  void GroupInputGrids();  // input_grid_ from the inputs set so far
  void ComputeOutputs(double t, bool major);
  bool MakeModesConsistent(double t, bool major);
  void LogNow();
  void KeepEnvelope();
  void BeginStreaming(double samples);
  double NextMajorTime(double t) const;
  double NextLogTime() const;

  const Diagram& diagram_;
  std::vector<BlockContext> contexts_;
  std::vector<double> signals_;    // all output ports, then external inputs
  std::vector<std::size_t> output_offset_;  // per block, offset of its first output
  std::vector<double> xc_, dxc_, xd_, zc_;
  std::vector<int> discrete_blocks_;
  std::vector<int> continuous_blocks_;  // the blocks with continuous states, in index order (each derivative call)
  // Minor steps (solver stages, root searches) recompute only the non-discrete blocks that feed a block with
  // continuous states or zero crossings, in execution order; the rest only changes at major steps.
  std::vector<int> minor_step_order_;
  std::vector<char> hit_now_;       // per block: discrete hit at the current major time
  std::vector<InputSeries> input_series_;
  std::vector<char> input_set_;
  std::vector<std::size_t> input_cursor_;
  // Inputs read from one log share its time grid: input k interpolates at the interval and weight that the first
  // input with the same time stamps found (input_grid_[k] = that input; itself if none). Set by SetInput.
  std::vector<std::size_t> input_grid_;
  std::vector<double> input_weight_;
  std::size_t external_offset_ = 0;
  int num_continuous_ = 0;
  int num_roots_ = 0;
  std::unique_ptr<ContinuousSolver> solver_;
  double time_ = 0.0;
  double log_step_ = 0.0;
  long long next_log_index_ = 0;
  double start_time_ = 0.0;
  SignalLog log_;
  std::vector<std::pair<SignalRef, int>> logged_refs_;
  std::function<void(double, double)> progress_;
  SimulationLimits limits_;
  // Streaming (StreamLogTo): the sink, the in-memory thinning, a row buffer and the metrics' accumulators with
  // their log columns (signal, reference or -1).
  LogSink* sink_ = nullptr;
  std::size_t max_samples_in_memory_ = 0;
  long long keep_every_ = 0;
  long long logged_samples_ = 0;
  std::vector<double> row_;
  std::vector<MetricAccumulator> metric_sums_;
  std::vector<std::pair<int, int>> metric_columns_;
  bool initialised_ = false;
};

}  // namespace mb

#pragma once
// A loaded, validated diagram: block instances, resolved connections, execution order, and what to log and
// measure. Built from JSON by LoadDiagram (diagram_loader.h); run by Simulator (simulator.h).

#include <filesystem>
#include <map>
#include <memory>
#include <unordered_map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "engine/block.h"
#include "engine/metric_type.h"
#include "engine/parameters.h"
#include "engine/units.h"

namespace mb {

/// Where a signal comes from: an output port of a block, or a diagram-level input connector (block == -1,
/// port = index into Diagram::inputs()).
struct SignalRef {
  int block = -1;
  int port = 0;
  bool is_external() const { return block < 0; }
};

/// How an input connector reads its series between samples (the connector's "interpolation").
enum class InputInterpolation {
  kLinear,  ///< linear, held outside the series (Simulink's From Workspace with "Interpolate data")
  /// Cubic Hermite with centred-difference slopes (Catmull–Rom on a uniform grid; Keys 1981, cubic convolution): for a
  /// smooth signal logged slower than the diagram runs (a reference at 100 Hz into a 1 kHz controller), whose linear
  /// interpolation errs by up to h²·|ẍ|/8 between samples; linear in the first and last intervals.
  kCubic,
};

/// A diagram-level input connector (SSP `connectors` with kind "input"): fed from a measurement or a file by
/// `compare`, `fit` and `run --input`. `measurement` is the default column name in a measurement log.
struct ExternalInput {
  std::string name;
  std::string unit;
  std::string measurement;
  MotionQuantity quantity = MotionQuantity::kOther;  ///< declared "quantity" (units.h QuantityNamed); kOther: none
  bool optional = false;      ///< an optional input absent from the log reads `default_value`
  double default_value = 0.0;
  InputInterpolation interpolation = InputInterpolation::kLinear;  ///< between the series' samples
};

/// A diagram-level output connector: a named signal that `compare` checks against column `measurement`.
struct ExternalOutput {
  std::string name;
  std::string unit;
  std::string measurement;
  MotionQuantity quantity = MotionQuantity::kOther;  ///< declared "quantity" (units.h QuantityNamed); kOther: none
  SignalRef source;
};

/// A logged signal: its name in the CSV ("block.port", or the connector name) and where it comes from.
struct LoggedSignal {
  std::string name;
  SignalRef source;
  int width = 1;
};

/// A scalar figure of merit computed after a run (written to summary.json under "metrics").
struct MetricSpec {
  std::string name;
  MetricType type = MetricType::kRmse;
  std::string signal;
  std::string reference;  ///< only for rms_difference
  std::string unit;
  double from = -1e300;   ///< evaluation window start [s]
  double to = 1e300;      ///< evaluation window end [s]
};

struct SolverSpec {
  std::string type = "rk4";   ///< "euler", "rk4" or "cvode"
  std::string method = "bdf"; ///< CVODE: "bdf" or "adams"
  double step = 1e-4;         ///< fixed-step solvers: the integration step [s]
  double rtol = 1e-6;         ///< CVODE relative tolerance
  double atol = 1e-9;         ///< CVODE absolute tolerance
  double max_step = 0.0;      ///< CVODE maximum step [s], 0 = unlimited
};

struct Experiment {
  double start_time = 0.0;  ///< [s]
  double stop_time = 1.0;   ///< [s]
  double step_size = 0.0;   ///< log/output interval [s]; 0 = the fastest discrete period, else (stop−start)/1000
};

class Diagram {
 public:
  Diagram() = default;
  Diagram(Diagram&&) = default;
  Diagram& operator=(Diagram&&) = default;

  const std::string& name() const { return name_; }
  const std::vector<std::unique_ptr<Block>>& blocks() const { return blocks_; }
  /// sources()[b][i]: what feeds input port i of block b.
  const std::vector<std::vector<SignalRef>>& sources() const { return sources_; }
  const std::vector<ExternalInput>& inputs() const { return inputs_; }
  const std::vector<ExternalOutput>& outputs() const { return outputs_; }
  const std::vector<LoggedSignal>& logged() const { return logged_; }
  const std::vector<MetricSpec>& metrics() const { return metrics_; }
  const SolverSpec& solver() const { return solver_; }
  const Experiment& experiment() const { return experiment_; }
  /// Block indices in an order where every direct-feedthrough input is computed before it is read.
  const std::vector<int>& execution_order() const { return execution_order_; }
  const std::filesystem::path& path() const { return path_; }
  /// The registered type name of block `b` (its element's "type") and its validated parameters (defaults filled
  /// in, units stripped), for analyses of a loop's numbers (tools/workflow/loop_from_diagram.h). To edit a diagram,
  /// use DiagramDocument (engine/diagram_document.h) on its JSON.
  const std::string& block_type(int b) const { return block_types_[static_cast<std::size_t>(b)]; }
  const Parameters& block_parameters(int b) const { return block_parameters_[static_cast<std::size_t>(b)]; }
  /// The diagram's optional "roles" map, role → element name (after subsystem expansion: "plant/body"). The
  /// engine checks only that each names an element; what a role means belongs to the analysis that reads it.
  const std::map<std::string, std::string>& roles() const { return roles_; }
  /// The axis its motion is in, from its connectors (engine/parameters.h DiagramAxis: m and N, rad and N·m, …): its
  /// parameters read in that axis's units (OnAxis(spec, axis()).unit: N·m·s/rad for a rotary viscous coefficient).
  const MotionAxis& axis() const { return axis_; }

  /// Index of the block with this instance name, or -1. O(1) (a hash map: a diagram of 100,000 blocks loads in
  /// linear time).
  int FindBlock(const std::string& block_name) const;
  /// Resolves "block.port", "block" (its only/first output) or an input/output connector name.
  /// @throws std::invalid_argument naming the signal and listing close alternatives.
  SignalRef ResolveSignal(const std::string& signal) const;
  /// Width of a signal.
  int SignalWidth(const SignalRef& ref) const;
  /// "block.port" or the connector's name.
  std::string SignalName(const SignalRef& ref) const;

 private:
  friend class DiagramBuilder;
  std::string name_;
  std::vector<std::unique_ptr<Block>> blocks_;
  std::unordered_map<std::string, int> block_index_;  ///< name → index in blocks_ (the first of a name)
  std::vector<std::vector<SignalRef>> sources_;
  std::vector<ExternalInput> inputs_;
  std::vector<ExternalOutput> outputs_;
  std::vector<LoggedSignal> logged_;
  std::vector<MetricSpec> metrics_;
  SolverSpec solver_;
  Experiment experiment_;
  std::vector<int> execution_order_;
  std::vector<std::string> block_types_;
  std::vector<Parameters> block_parameters_;
  MotionAxis axis_;
  std::map<std::string, std::string> roles_;
  std::filesystem::path path_;
};

}  // namespace mb

#pragma once
// The block interface: what every library block declares and computes. Modelled on Drake's LeafSystem
// (ports, state and sample time declared in the constructor; the block is immutable afterwards; everything
// that changes lives in the engine-owned context) and on Simulink's S-function callbacks (outputs, update,
// derivatives, zero crossings).
//
// Order within one major step at time t (Simulink's, documented in docs/engine.md):
//   1. outputs: every block in sorted order (discrete blocks only at their hits, held otherwise),
//   2. log, metrics,
//   3. discrete update: UpdateDiscrete of every discrete block with a hit at t,
//   4. integrate the continuous states to the next major time (CalcOutput of continuous/inherited blocks and
//      CalcDerivatives inside the solver; zero crossings located by the solver call UpdateModes).
// A sampled input at t therefore reads the value computed in step 1 at the same t (direct feedthrough), and a
// unit delay's output at hit k is its input at hit k−1.

#include <string>
#include <vector>

#include <Eigen/Core>

#include "engine/parameters.h"
#include "engine/sample_time.h"

namespace mb {

/// One input or output port. Inputs declare whether they feed through directly to any output at the same
/// instant (used to sort blocks and to detect algebraic loops).
struct PortSpec {
  std::string name;
  int width = 1;
  std::string unit;  ///< SI unit, "" = any/dimensionless (no check)
  bool direct_feedthrough = false;  ///< inputs only
};

/// The per-call view a block gets of its own signals and states. All storage is owned by the engine and laid
/// out once at setup; the accessors return maps into it and never allocate.
class BlockContext {
 public:
  using ConstVec = Eigen::Map<const Eigen::VectorXd>;
  using Vec = Eigen::Map<Eigen::VectorXd>;

  double time() const { return time_; }

  /// Input port `port` (width as declared). Valid in every callback.
  ConstVec input(int port) const { return ConstVec(inputs_[Idx(port)], widths_in_[Idx(port)]); }
  /// Element k of input port `port` (scalar convenience).
  double u(int port, int k = 0) const { return inputs_[Idx(port)][k]; }
  /// Output port `port`. Written in CalcOutput; read-only (const data) elsewhere by convention.
  Vec output(int port) const { return Vec(outputs_[Idx(port)], widths_out_[Idx(port)]); }
  double& y(int port, int k = 0) const { return outputs_[Idx(port)][k]; }

  /// Continuous state x_c (size as declared) and its derivative (only meaningful in CalcDerivatives).
  Vec continuous_state() const { return Vec(xc_, nxc_); }
  Vec derivatives() const { return Vec(dxc_, nxc_); }
  /// Discrete state x_d, written only in UpdateDiscrete / UpdateModes / Initialize.
  Vec discrete_state() const { return Vec(xd_, nxd_); }
  /// Zero-crossing function values g (written in CalcZeroCrossings).
  Vec zero_crossings() const { return Vec(zc_, nzc_); }

 private:
  friend class Simulator;
  static std::size_t Idx(int i) { return static_cast<std::size_t>(i); }
  double time_ = 0.0;
  std::vector<const double*> inputs_;
  std::vector<Eigen::Index> widths_in_;
  std::vector<double*> outputs_;
  std::vector<Eigen::Index> widths_out_;
  double* xc_ = nullptr;
  double* dxc_ = nullptr;
  double* xd_ = nullptr;
  double* zc_ = nullptr;
  Eigen::Index nxc_ = 0, nxd_ = 0, nzc_ = 0;
};

/// Base class of every block. A block declares its ports, states, zero crossings and sample time in its
/// constructor and is immutable afterwards: all callbacks are const and act on the context.
/// Callbacks must not allocate or throw once the simulation runs (the real-time path runs them too).
class Block {
 public:
  explicit Block(std::string name) : name_(std::move(name)) {}
  virtual ~Block() = default;
  Block(const Block&) = delete;
  Block& operator=(const Block&) = delete;

  /// Sets initial continuous and discrete states (default: zeros, already written by the engine).
  virtual void Initialize(const BlockContext&) const {}
  /// y = h(t, x_c, x_d, u). Discrete blocks: called at their hits only.
  virtual void CalcOutput(const BlockContext& context) const = 0;
  /// ẋ_c = f(t, x_c, x_d, u).
  virtual void CalcDerivatives(const BlockContext&) const {}
  /// x_d ← g(t, x_c, x_d, u) at a sample hit.
  virtual void UpdateDiscrete(const BlockContext&) const {}
  /// Zero-crossing functions g(t, x, u); the solver locates their sign changes. CVODE may return a located
  /// root with g exactly 0 and does not report it again after the restart, so UpdateModes must treat g = 0 as
  /// crossed (switch at g ≥ 0). Fixed-step solvers report a crossing at the end of the step where g went from
  /// > 0 to ≤ 0 or back. A block output that jumps as a plain function of t (not through a mode changed at an
  /// event) makes CVODE fail with repeated error-test failures: keep such jumps in a mode.
  virtual void CalcZeroCrossings(const BlockContext&) const {}
  /// Called at located zero crossings and at every major step: update discrete modes kept in x_d so that they
  /// are consistent with the current states and inputs. Return true if a mode changed (the engine then
  /// recomputes outputs and calls again, up to a bound, until consistent — Modelica's event iteration).
  virtual bool UpdateModes(const BlockContext&) const { return false; }

  const std::string& name() const { return name_; }
  const std::vector<PortSpec>& input_ports() const { return inputs_; }
  const std::vector<PortSpec>& output_ports() const { return outputs_; }
  int num_continuous_states() const { return num_continuous_states_; }
  int num_discrete_states() const { return num_discrete_states_; }
  int num_zero_crossings() const { return num_zero_crossings_; }
  const SampleTime& sample_time() const { return sample_time_; }
  /// Index of the input/output port with this name, or -1.
  int FindInputPort(const std::string& port_name) const;
  int FindOutputPort(const std::string& port_name) const;

 protected:
  int DeclareInputPort(std::string port_name, int width = 1, std::string unit = "", bool direct_feedthrough = true);
  int DeclareOutputPort(std::string port_name, int width = 1, std::string unit = "");
  void DeclareContinuousState(int n) { num_continuous_states_ = n; }
  void DeclareDiscreteState(int n) { num_discrete_states_ = n; }
  void DeclareZeroCrossings(int n) { num_zero_crossings_ = n; }
  void SetSampleTime(SampleTime st) { sample_time_ = st; }

 private:
  std::string name_;
  std::vector<PortSpec> inputs_;
  std::vector<PortSpec> outputs_;
  int num_continuous_states_ = 0;
  int num_discrete_states_ = 0;
  int num_zero_crossings_ = 0;
  SampleTime sample_time_ = SampleTime::Inherited();
};

}  // namespace mb

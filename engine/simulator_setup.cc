// Simulator's set-up: the default limits, construction in named phases (signal and state storage, the minor-step
// order, the inputs and the log) and Initialize's check of the run's length against the limits. The run itself
// is in simulator.cc.
#include "engine/simulator.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>

namespace mb {

namespace {
std::atomic<double> g_default_max_steps{SimulationLimits{}.max_steps};
std::atomic<long> g_default_max_events{SimulationLimits{}.max_events_per_major_step};

// A time step of the run for CheckRunLength: what sets it, for the message.
struct RunGrid {
  std::string what;
  double step;
};
}  // namespace

SimulationLimits DefaultSimulationLimits() { return {g_default_max_steps.load(), g_default_max_events.load()}; }

void CheckSimulationLimits(const SimulationLimits& limits) {
  if (!(limits.max_steps >= 1.0 && limits.max_steps <= kMaxSimulationSteps)) {  // NaN fails too
    throw std::invalid_argument(fmt::format(
        "--max-steps {}: the step limit must be a finite number in [1, {:g}] (default {:g}); give the number of "
        "steps a run may take",
        limits.max_steps, kMaxSimulationSteps, SimulationLimits{}.max_steps));
  }
  if (limits.max_events_per_major_step < 1) {
    throw std::invalid_argument(fmt::format("the limit of zero-crossing events per major step must be >= 1, got {}",
                                            limits.max_events_per_major_step));
  }
}

void SetDefaultSimulationLimits(const SimulationLimits& limits) {
  CheckSimulationLimits(limits);
  g_default_max_steps.store(limits.max_steps);
  g_default_max_events.store(limits.max_events_per_major_step);
}

Simulator::Simulator(const Diagram& diagram, SimulationLimits limits) : diagram_(diagram), limits_(limits) {
  if (!(limits_.max_steps >= 1.0)) {  // NaN would pass every "steps > max_steps" check
    throw std::invalid_argument(fmt::format("the step limit of a run must be >= 1 (or +infinity: none), got {}",
                                            limits_.max_steps));
  }
  LayOutSignals();
  LayOutStates();
  OrderMinorSteps();
  LayOutInputsAndLog();
  if (num_continuous_ > 0) solver_ = MakeSolver(diagram.solver(), this);
}

// Signal storage: every output port, then one slot per external input; each block's context points at its
// inputs' sources and at its own outputs.
void Simulator::LayOutSignals() {
  const auto& blocks = diagram_.blocks();
  const std::size_t nb = blocks.size();
  std::size_t offset = 0;
  output_offset_.resize(nb);
  for (std::size_t b = 0; b < nb; ++b) {
    output_offset_[b] = offset;
    for (const auto& p : blocks[b]->output_ports()) offset += static_cast<std::size_t>(p.width);
  }
  external_offset_ = offset;
  signals_.assign(offset + diagram_.inputs().size(), 0.0);

  contexts_.resize(nb);
  for (std::size_t b = 0; b < nb; ++b) {
    const Block& block = *blocks[b];
    BlockContext& c = contexts_[b];
    for (std::size_t p = 0; p < block.input_ports().size(); ++p) {
      const SignalRef src = diagram_.sources()[b][p];
      const std::size_t at = src.is_external()
                                 ? external_offset_ + static_cast<std::size_t>(src.port)
                                 : output_offset_[static_cast<std::size_t>(src.block)] + [&] {
                                     std::size_t o = 0;
                                     const auto& outs = blocks[static_cast<std::size_t>(src.block)]->output_ports();
                                     for (int k = 0; k < src.port; ++k) o += static_cast<std::size_t>(outs[static_cast<std::size_t>(k)].width);
                                     return o;
                                   }();
      c.inputs_.push_back(signals_.data() + at);
      c.widths_in_.push_back(block.input_ports()[p].width);
    }
    std::size_t o = output_offset_[b];
    for (const auto& p : block.output_ports()) {
      c.outputs_.push_back(signals_.data() + o);
      c.widths_out_.push_back(p.width);
      o += static_cast<std::size_t>(p.width);
    }
  }
}

// State storage: continuous states (and their derivatives), discrete states and zero crossings, block by block;
// each block's context points at its share. Also lists the discrete blocks.
void Simulator::LayOutStates() {
  const auto& blocks = diagram_.blocks();
  const std::size_t nb = blocks.size();
  std::size_t nxc = 0, nxd = 0, nzc = 0;
  for (const auto& b : blocks) {
    nxc += static_cast<std::size_t>(b->num_continuous_states());
    nxd += static_cast<std::size_t>(b->num_discrete_states());
    nzc += static_cast<std::size_t>(b->num_zero_crossings());
  }
  xc_.assign(nxc, 0.0);
  dxc_.assign(nxc, 0.0);
  xd_.assign(nxd, 0.0);
  zc_.assign(nzc, 0.0);
  num_continuous_ = static_cast<int>(nxc);
  num_roots_ = static_cast<int>(nzc);

  hit_now_.assign(nb, 0);
  std::size_t oc = 0, od = 0, oz = 0;
  for (std::size_t b = 0; b < nb; ++b) {
    const Block& block = *blocks[b];
    BlockContext& c = contexts_[b];
    c.nxc_ = block.num_continuous_states();
    c.nxd_ = block.num_discrete_states();
    c.nzc_ = block.num_zero_crossings();
    c.xc_ = xc_.data() + oc;
    c.dxc_ = dxc_.data() + oc;
    c.xd_ = xd_.data() + od;
    c.zc_ = zc_.data() + oz;
    oc += static_cast<std::size_t>(c.nxc_);
    od += static_cast<std::size_t>(c.nxd_);
    oz += static_cast<std::size_t>(c.nzc_);
    if (block.sample_time().is_discrete()) discrete_blocks_.push_back(static_cast<int>(b));
    if (c.nxc_ > 0) continuous_blocks_.push_back(static_cast<int>(b));
  }
}

// Blocks a minor step needs: transitively, the blocks feeding those with continuous states or zero
// crossings — except blocks whose output cannot change between major steps: discrete blocks (held between
// hits) and stateless inherited blocks fed only by such blocks (Simulink would give them the discrete rate
// by sample-time propagation; computing them at major steps only is the same result).
void Simulator::OrderMinorSteps() {
  const Diagram& diagram = diagram_;
  const auto& blocks = diagram.blocks();
  const std::size_t nb = blocks.size();
  std::vector<char> held(nb, 0);
  for (int b : diagram.execution_order()) {
    const auto bi = static_cast<std::size_t>(b);
    const Block& block = *blocks[bi];
    if (block.sample_time().is_discrete()) {
      held[bi] = 1;
      continue;
    }
    const bool stateless = block.num_continuous_states() == 0 && block.num_discrete_states() == 0 &&
                           block.num_zero_crossings() == 0;
    if (!stateless || block.sample_time().kind != SampleTime::Kind::kInherited || diagram.sources()[bi].empty()) {
      continue;
    }
    bool all_held = true;  // a source later in the order is not yet known: not held (conservative)
    for (const SignalRef& src : diagram.sources()[bi]) {
      all_held = all_held && !src.is_external() && held[static_cast<std::size_t>(src.block)];
    }
    held[bi] = all_held ? 1 : 0;
  }
  // CalcDerivatives reads a block's states and inputs, not its own outputs (docs/engine.md), so a block with
  // continuous states is recomputed in minor steps only when another needed block reads it; blocks with zero
  // crossings always are (their mode logic may compare outputs).
  std::vector<char> needed(nb, 0);
  std::vector<int> stack;
  for (std::size_t b = 0; b < nb; ++b) {
    if (blocks[b]->num_zero_crossings() > 0) needed[b] = 1;
    if (blocks[b]->num_continuous_states() > 0 || blocks[b]->num_zero_crossings() > 0) {
      stack.push_back(static_cast<int>(b));
    }
  }
  while (!stack.empty()) {
    const auto b = static_cast<std::size_t>(stack.back());
    stack.pop_back();
    for (const SignalRef& src : diagram.sources()[b]) {
      if (src.is_external()) continue;
      const auto a = static_cast<std::size_t>(src.block);
      if (needed[a] || held[a]) continue;
      needed[a] = 1;
      stack.push_back(src.block);
    }
  }
  for (int b : diagram.execution_order()) {
    if (needed[static_cast<std::size_t>(b)] && !held[static_cast<std::size_t>(b)]) minor_step_order_.push_back(b);
  }
}

// The inputs' series (set later by SetInput), the log grid and the logged columns' names.
void Simulator::LayOutInputsAndLog() {
  const Diagram& diagram = diagram_;
  input_series_.resize(diagram.inputs().size());
  input_set_.assign(diagram.inputs().size(), 0);
  input_cursor_.assign(diagram.inputs().size(), 0);
  input_weight_.assign(diagram.inputs().size(), 0.0);
  input_grid_.resize(diagram.inputs().size());

  // Log grid: the experiment's step size, else the fastest discrete period, else 1000 intervals.
  const auto& ex = diagram.experiment();
  log_step_ = ex.step_size;
  if (log_step_ <= 0.0) {
    for (int b : discrete_blocks_) {
      const double p = diagram.blocks()[static_cast<std::size_t>(b)]->sample_time().period;
      log_step_ = log_step_ <= 0.0 ? p : std::min(log_step_, p);
    }
  }
  if (log_step_ <= 0.0) log_step_ = (ex.stop_time - ex.start_time) / 1000.0;

  for (const auto& l : diagram.logged()) {
    logged_refs_.emplace_back(l.source, l.width);
    if (l.width == 1) {
      log_.names.push_back(l.name);
    } else {
      for (int k = 0; k < l.width; ++k) log_.names.push_back(fmt::format("{}[{}]", l.name, k));
    }
  }
  log_.columns.resize(log_.names.size());
}

void Simulator::CheckRunLength(double start_time) const {
  const Experiment& ex = diagram_.experiment();
  const double span = ex.stop_time - start_time;
  if (!(span > 0.0)) return;  // nothing to run (the loader refuses stopTime <= startTime)
  std::vector<RunGrid> grids;
  if (ex.step_size > 0.0) grids.push_back({"defaultExperiment.stepSize", ex.step_size});
  for (int b : discrete_blocks_) {
    const Block& block = *diagram_.blocks()[static_cast<std::size_t>(b)];
    grids.push_back({fmt::format("the sampleTime of element '{}'", block.name()), block.sample_time().period});
  }
  if (solver_ && diagram_.solver().type != "cvode") grids.push_back({"solver.step", diagram_.solver().step});
  grids.push_back({"the log interval", log_step_});
  const double t_max = std::max(std::abs(start_time), std::abs(ex.stop_time));
  const RunGrid* finest = &grids.front();
  for (const RunGrid& g : grids) {
    if (g.step > span * (1.0 + 1e-9)) {
      throw std::invalid_argument(fmt::format(
          "{}: {} ({} s) is longer than the run ({} s, from startTime {} s to stopTime {} s): the run would log "
          "only its start. Make it at most {} s, or make stopTime later",
          diagram_.name(), g.what, g.step, span, start_time, ex.stop_time, span));
    }
    if (!(t_max + g.step > t_max)) {
      throw std::invalid_argument(fmt::format(
          "{}: {} ({} s) vanishes next to the run's times (t = {} s): t + {} == t in double precision, so time "
          "could never advance. Use a larger step, or start the run nearer t = 0",
          diagram_.name(), g.what, g.step, t_max, g.step));
    }
    if (g.step < finest->step) finest = &g;
  }
  const double steps = span / finest->step;
  if (steps > limits_.max_steps) {
    throw std::invalid_argument(fmt::format(
        "{}: the run from {} s to {} s in steps of {} s ({}) takes about {:.3g} steps, more than the limit of "
        "{:.3g}. Shorten the run (defaultExperiment.stopTime), enlarge the step, or raise the limit with "
        "--max-steps N",
        diagram_.name(), start_time, ex.stop_time, finest->step, finest->what, steps, limits_.max_steps));
  }
  const double samples = sink_ ? std::min(span / log_step_ + 1.0, static_cast<double>(max_samples_in_memory_))
                               : span / log_step_ + 1.0;  // held in memory
  const double values = samples * static_cast<double>(std::max<std::size_t>(1, log_.names.size()));
  if (values > limits_.max_steps) {
    throw std::invalid_argument(fmt::format(
        "{}: the log would hold about {:.3g} values ({:.3g} samples every {} s × {} signals, {:.3g} MB), more than "
        "the limit of {:.3g}. Log fewer signals, a larger defaultExperiment.stepSize or a shorter run, or raise "
        "the limit with --max-steps N",
        diagram_.name(), values, samples, log_step_, log_.names.size(), values * 8e-6,
        limits_.max_steps));
  }
}

}  // namespace mb

#include "engine/simulator.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <fmt/format.h>

#include "engine/numerical_error.h"

namespace mb {

namespace {
constexpr int kMaxEventIterations = 10;  // Modelica-style event iteration bound
constexpr double kTimeTolerance = 1e-12;
constexpr double kLogMergeTolerance = 1e-6;  // in log steps

// The block owning entry i of storage laid out block by block, `count(block)` entries each; *local = its index
// within the block.
template <class Count>
std::size_t OwnerOf(const std::vector<std::unique_ptr<Block>>& blocks, std::size_t i, Count count,
                    std::size_t* local) {
  std::size_t offset = 0;
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    const auto n = static_cast<std::size_t>(count(*blocks[b]));
    if (i < offset + n) {
      *local = i - offset;
      return b;
    }
    offset += n;
  }
  *local = i;
  return 0;
}
}  // namespace

const std::vector<double>& SignalLog::Column(const std::string& name) const {
  for (std::size_t i = 0; i < names.size(); ++i) {
    if (names[i] == name) return columns[i];
  }
  std::string list;
  for (const auto& n : names) list += (list.empty() ? "" : ", ") + n;
  throw std::invalid_argument(fmt::format("signal '{}' is not logged; logged signals: {} (add it to the diagram's "
                                          "\"log\" list)",
                                          name, list));
}

bool SignalLog::Has(const std::string& name) const {
  return std::find(names.begin(), names.end(), name) != names.end();
}

Simulator::~Simulator() = default;

void Simulator::SetInput(const std::string& name, InputSeries series) {
  const auto& inputs = diagram_.inputs();
  for (std::size_t k = 0; k < inputs.size(); ++k) {
    if (inputs[k].name != name) continue;
    if (series.time.size() != series.values.size() || series.time.empty()) {
      throw std::invalid_argument(fmt::format("input '{}': time and values must have the same, non-zero length "
                                              "({} vs {})",
                                              name, series.time.size(), series.values.size()));
    }
    for (std::size_t i = 1; i < series.time.size(); ++i) {
      if (!(series.time[i] > series.time[i - 1])) {
        throw std::invalid_argument(
            fmt::format("input '{}': time must increase strictly (row {}: {} after {})", name, i, series.time[i],
                        series.time[i - 1]));
      }
    }
    input_series_[k] = std::move(series);
    input_set_[k] = 1;
    input_cursor_[k] = 0;
    GroupInputGrids();
    return;
  }
  std::string names;
  for (const auto& in : inputs) names += (names.empty() ? "" : ", ") + in.name;
  throw std::invalid_argument(fmt::format("diagram '{}' has no input connector '{}'; its inputs: {}", diagram_.name(),
                                          name, names.empty() ? "(none)" : names));
}

bool Simulator::HoldInput(std::size_t index, double value) noexcept {
  if (index >= input_series_.size() || !input_set_[index] || input_series_[index].values.size() != 1) return false;
  input_series_[index].values[0] = value;
  return true;
}

void Simulator::GroupInputGrids() {
  for (std::size_t k = 0; k < input_grid_.size(); ++k) {
    input_grid_[k] = k;
    for (std::size_t j = 0; j < k && input_set_[k]; ++j) {
      if (input_set_[j] && input_series_[j].time == input_series_[k].time) {
        input_grid_[k] = j;
        break;
      }
    }
  }
}

void Simulator::UpdateInputs(double t) {
  for (std::size_t k = 0; k < input_series_.size(); ++k) {
    double& slot = signals_[external_offset_ + k];
    if (!input_set_[k]) {
      slot = diagram_.inputs()[k].default_value;
      continue;
    }
    const auto& ts = input_series_[k].time;
    const auto& vs = input_series_[k].values;
    if (t <= ts.front()) {
      slot = vs.front();
      continue;
    }
    if (t >= ts.back()) {
      slot = vs.back();
      continue;
    }
    std::size_t& i = input_cursor_[k];
    double& w = input_weight_[k];
    if (const std::size_t g = input_grid_[k]; g != k) {  // the time grid of an earlier input: its interval
      i = input_cursor_[g];
      w = input_weight_[g];
    } else {
      // Time mostly moves forward: walk the cursor, fall back to bisection on a jump back.
      if (i + 1 >= ts.size() || ts[i] > t) {
        i = static_cast<std::size_t>(std::upper_bound(ts.begin(), ts.end(), t) - ts.begin()) - 1;
      }
      while (ts[i + 1] < t) ++i;
      w = (t - ts[i]) / (ts[i + 1] - ts[i]);
    }
    if (diagram_.inputs()[k].interpolation == InputInterpolation::kCubic && i > 0 && i + 2 < ts.size()) {
      // Cubic Hermite on [t_i, t_i+1] with the centred differences as slopes (scaled by the interval).
      const double h = ts[i + 1] - ts[i];
      const double m0 = (vs[i + 1] - vs[i - 1]) / (ts[i + 1] - ts[i - 1]) * h;
      const double m1 = (vs[i + 2] - vs[i]) / (ts[i + 2] - ts[i]) * h;
      const double w2 = w * w, w3 = w2 * w;
      slot = (2.0 * w3 - 3.0 * w2 + 1.0) * vs[i] + (w3 - 2.0 * w2 + w) * m0 + (3.0 * w2 - 2.0 * w3) * vs[i + 1] +
             (w3 - w2) * m1;
    } else {
      slot = vs[i] + w * (vs[i + 1] - vs[i]);
    }
  }
}

void Simulator::ComputeOutputs(double t, bool major) {
  const auto& blocks = diagram_.blocks();
  for (int b : major ? diagram_.execution_order() : minor_step_order_) {
    const auto bi = static_cast<std::size_t>(b);
    const Block& block = *blocks[bi];
    if (block.sample_time().is_discrete() && !(major && hit_now_[bi])) continue;  // held between hits
    contexts_[bi].time_ = t;
    block.CalcOutput(contexts_[bi]);
  }
}

bool Simulator::MakeModesConsistent(double t, bool major) {
  bool any = false;
  const auto& blocks = diagram_.blocks();
  for (int iteration = 0; iteration < kMaxEventIterations; ++iteration) {
    bool changed = false;
    for (std::size_t b = 0; b < blocks.size(); ++b) {
      if (blocks[b]->num_zero_crossings() == 0) continue;
      contexts_[b].time_ = t;
      changed = blocks[b]->UpdateModes(contexts_[b]) || changed;
    }
    if (!changed) break;
    any = true;
    // At a major step, discrete blocks with a hit now must see the outputs after the mode change.
    ComputeOutputs(t, major);
  }
  return any;
}

void Simulator::Derivatives(double t, const double* x, double* dx) {
  // Element by element, not std::copy: a handful of states, where memmove's call costs more than the copy.
  for (int i = 0; i < num_continuous_; ++i) xc_[static_cast<std::size_t>(i)] = x[i];
  UpdateInputs(t);
  ComputeOutputs(t, /*major=*/false);
  const auto& blocks = diagram_.blocks();
  for (const int b : continuous_blocks_) {
    const auto bi = static_cast<std::size_t>(b);
    contexts_[bi].time_ = t;
    blocks[bi]->CalcDerivatives(contexts_[bi]);
  }
  for (int i = 0; i < num_continuous_; ++i) dx[i] = dxc_[static_cast<std::size_t>(i)];
}

void Simulator::EvaluateContinuousPart(const std::vector<double>& x, std::vector<double>* dx, std::vector<double>* y) {
  if (!initialised_) throw std::logic_error("Simulator::EvaluateContinuousPart before Initialize");
  if (x.size() != xc_.size()) {
    throw std::invalid_argument(fmt::format("EvaluateContinuousPart: diagram '{}' has {} continuous states, got {}",
                                            diagram_.name(), xc_.size(), x.size()));
  }
  const std::vector<double> saved = xc_;
  const auto evaluate = [&](const std::vector<double>& state) {
    std::copy(state.begin(), state.end(), xc_.begin());
    UpdateInputs(time_);
    const auto& blocks = diagram_.blocks();
    for (int b : diagram_.execution_order()) {
      const auto bi = static_cast<std::size_t>(b);
      if (blocks[bi]->sample_time().is_discrete()) continue;
      contexts_[bi].time_ = time_;
      blocks[bi]->CalcOutput(contexts_[bi]);
    }
    for (std::size_t b = 0; b < blocks.size(); ++b) {
      if (blocks[b]->num_continuous_states() == 0) continue;
      contexts_[b].time_ = time_;
      blocks[b]->CalcDerivatives(contexts_[b]);
    }
  };
  evaluate(x);
  dx->assign(dxc_.begin(), dxc_.end());
  y->clear();
  for (const auto& out : diagram_.outputs()) y->push_back(SignalValue(out.source));
  evaluate(saved);
}

void Simulator::Roots(double t, const double* x, double* g) {
  std::copy(x, x + num_continuous_, xc_.begin());
  UpdateInputs(t);
  ComputeOutputs(t, /*major=*/false);
  const auto& blocks = diagram_.blocks();
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    if (blocks[b]->num_zero_crossings() == 0) continue;
    contexts_[b].time_ = t;
    blocks[b]->CalcZeroCrossings(contexts_[b]);
  }
  std::copy(zc_.begin(), zc_.end(), g);
}

// Log times and sample hits come from separate integer grids that nominally coincide but may differ by rounding
// (a log step taken from a measured time column, 0.001 + 1e-16): a log time within kLogMergeTolerance·step of a
// hit is taken at the hit, after the hit's update, so the log never shows a block one sample late. A hit is
// "now" within the same tolerance IsHit uses (1e-9 periods), so no hit is ever skipped.
double Simulator::NextLogTime() const {
  return start_time_ + static_cast<double>(next_log_index_) * log_step_;
}

double Simulator::NextMajorTime(double t) const {
  double next_hit = std::numeric_limits<double>::infinity();
  const SampleTime* previous = nullptr;
  for (int b : discrete_blocks_) {
    const SampleTime& st = diagram_.blocks()[static_cast<std::size_t>(b)]->sample_time();
    // Blocks of one rate mostly come in runs: the same period and offset give the same next hit.
    if (previous && st.period == previous->period && st.offset == previous->offset) continue;
    previous = &st;
    long long k = st.FirstHitIndexAtOrAfter(t);
    if (std::abs(st.HitTime(k) - t) <= 1e-9 * st.period) ++k;  // the hit at t is being handled
    next_hit = std::min(next_hit, st.HitTime(k));
  }
  double next_log = NextLogTime();
  if (next_log <= t + kLogMergeTolerance * log_step_) {
    next_log = start_time_ + static_cast<double>(next_log_index_ + 1) * log_step_;
  }
  if (next_log < next_hit && next_hit - next_log <= kLogMergeTolerance * log_step_) return next_hit;
  return std::min(next_log, next_hit);
}

void Simulator::LogNow() {
  std::size_t col = 0;
  for (const auto& [ref, width] : logged_refs_) {
    const double* v = ref.is_external() ? &signals_[external_offset_ + static_cast<std::size_t>(ref.port)]
                                        : contexts_[static_cast<std::size_t>(ref.block)].outputs_[static_cast<std::size_t>(ref.port)];
    for (int k = 0; k < width; ++k) row_[col++] = v[k];
  }
  const bool keep = !sink_;
  ++logged_samples_;
  if (sink_) {
    sink_->Append(time_, row_);
    const auto& metrics = diagram_.metrics();
    for (std::size_t m = 0; m < metric_sums_.size(); ++m) {
      if (time_ < metrics[m].from || time_ > metrics[m].to) continue;
      const auto [signal, reference] = metric_columns_[m];
      const double x = row_[static_cast<std::size_t>(signal)];
      metric_sums_[m].Add(reference < 0 ? x : x - row_[static_cast<std::size_t>(reference)]);
    }
    if (keep_every_ > 0) KeepEnvelope();
  }
  if (!keep) return;
  log_.time.push_back(time_);
  for (std::size_t c = 0; c < row_.size(); ++c) log_.columns[c].push_back(row_[c]);
}

// A streamed log's in-memory envelope (StreamLogTo): each stretch of keep_every_ samples is two rows, the first
// sample's time with each signal's minimum and the latest time with each maximum, updated in place as samples come.
void Simulator::KeepEnvelope() {
  if (keep_every_ == 1 || (logged_samples_ - 1) % keep_every_ == 0) {
    for (int copy = keep_every_ == 1 ? 1 : 2; copy > 0; --copy) {
      log_.time.push_back(time_);
      for (std::size_t c = 0; c < row_.size(); ++c) log_.columns[c].push_back(row_[c]);
    }
    return;
  }
  const std::size_t lo = log_.time.size() - 2, hi = lo + 1;
  log_.time[hi] = time_;
  for (std::size_t c = 0; c < row_.size(); ++c) {
    log_.columns[c][lo] = std::min(log_.columns[c][lo], row_[c]);
    log_.columns[c][hi] = std::max(log_.columns[c][hi], row_[c]);
  }
}

void Simulator::StreamLogTo(LogSink* sink, std::size_t max_samples_in_memory) {
  sink_ = sink;
  max_samples_in_memory_ = max_samples_in_memory;
}

// Streaming's set-up at Initialize: the sink's header, the metrics' columns, the thinning of the in-memory log.
void Simulator::BeginStreaming(double samples) {
  metric_sums_.clear();
  metric_columns_.clear();
  keep_every_ = 0;
  if (!sink_) return;
  sink_->Begin(log_.names);
  auto column = [&](const std::string& name) {
    const auto it = std::find(log_.names.begin(), log_.names.end(), name);
    if (it == log_.names.end()) (void)log_.Column(name);  // throws, listing the logged names
    return static_cast<int>(it - log_.names.begin());
  };
  for (const auto& m : diagram_.metrics()) {
    metric_columns_.emplace_back(column(m.signal), m.reference.empty() ? -1 : column(m.reference));
  }
  metric_sums_.assign(metric_columns_.size(), MetricAccumulator{});
  if (max_samples_in_memory_ > 0) {
    // Two rows per stretch (KeepEnvelope) unless every sample fits.
    const double every = samples <= static_cast<double>(max_samples_in_memory_)
                             ? 1.0
                             : std::ceil(2.0 * samples / static_cast<double>(max_samples_in_memory_));
    keep_every_ = std::max(1LL, static_cast<long long>(every));
  }
}

std::map<std::string, double> Simulator::StreamedMetrics() const {
  std::map<std::string, double> out;
  const auto& metrics = diagram_.metrics();
  for (std::size_t m = 0; m < metric_sums_.size(); ++m) {
    out[metrics[m].name] = metric_sums_[m].Value(metrics[m].type, metrics[m].name, metrics[m].from, metrics[m].to);
  }
  return out;
}

void Simulator::Initialize() { Initialize(diagram_.experiment().start_time); }

void Simulator::Initialize(double start_time) {
  for (std::size_t k = 0; k < input_set_.size(); ++k) {
    const auto& in = diagram_.inputs()[k];
    if (!input_set_[k] && !in.optional) {
      throw std::runtime_error(fmt::format("diagram '{}': input connector '{}' has no data; feed it from a "
                                           "measurement (compare/fit map column '{}') or mark it optional",
                                           diagram_.name(), in.name, in.measurement));
    }
  }
  start_time_ = start_time;
  time_ = start_time;
  std::fill(xc_.begin(), xc_.end(), 0.0);
  std::fill(xd_.begin(), xd_.end(), 0.0);
  std::fill(signals_.begin(), signals_.end(), 0.0);
  for (auto& c : input_cursor_) c = 0;
  log_ = SignalLog{{}, log_.names, std::vector<std::vector<double>>(log_.names.size())};
  row_.assign(log_.names.size(), 0.0);
  logged_samples_ = 0;
  CheckRunLength(start_time);
  // The whole log (the real-time loop must not allocate), never beyond the limit CheckRunLength enforced; a streamed
  // log keeps at most max_samples_in_memory_.
  const double samples = std::max(0.0, (diagram_.experiment().stop_time - start_time) / log_step_) + 2.0;
  BeginStreaming(samples);
  const double in_memory = sink_ ? std::min(samples, static_cast<double>(max_samples_in_memory_) + 2.0) : samples;
  const auto expected = static_cast<std::size_t>(std::min(in_memory, limits_.max_steps));
  log_.time.reserve(expected);
  for (auto& c : log_.columns) c.reserve(expected);
  next_log_index_ = 0;

  const auto& blocks = diagram_.blocks();
  for (std::size_t b = 0; b < blocks.size(); ++b) {
    contexts_[b].time_ = start_time;
    blocks[b]->Initialize(contexts_[b]);
  }
  // Every block computes an initial output (discrete ones from their initial state), then the hits at t0.
  std::fill(hit_now_.begin(), hit_now_.end(), 1);
  UpdateInputs(time_);
  ComputeOutputs(time_, /*major=*/true);
  for (int b : discrete_blocks_) {
    hit_now_[static_cast<std::size_t>(b)] = blocks[static_cast<std::size_t>(b)]->sample_time().IsHit(time_) ? 1 : 0;
  }
  MakeModesConsistent(time_, /*major=*/true);
  CheckFinite(time_);
  LogNow();
  ++next_log_index_;
  if (solver_) solver_->Reset(time_, xc_.data());
  initialised_ = true;
}

void Simulator::AdvanceTo(double t_end) {
  if (!initialised_) throw std::logic_error("Simulator::AdvanceTo before Initialize");
  const auto& blocks = diagram_.blocks();
  const double t_stop = diagram_.experiment().stop_time;
  double next_progress = time_;
  while (time_ < t_end - kTimeTolerance * std::max(1.0, std::abs(t_end))) {
    // Finish the current major step: discrete updates of the blocks with a hit now.
    bool need_reset = false;
    for (int b : discrete_blocks_) {
      const auto bi = static_cast<std::size_t>(b);
      if (!hit_now_[bi]) continue;
      contexts_[bi].time_ = time_;
      blocks[bi]->UpdateDiscrete(contexts_[bi]);
    }
    const double t_next = std::min(NextMajorTime(time_), t_end);
    if (solver_) need_reset = IntegrateTo(t_next);
    time_ = t_next;
    // Start the next major step: hits, outputs, modes, log.
    bool any_hit = false;
    const SampleTime* previous = nullptr;  // a run of blocks of one rate: one IsHit
    char previous_hit = 0;
    for (int b : discrete_blocks_) {
      const auto bi = static_cast<std::size_t>(b);
      const SampleTime& st = blocks[bi]->sample_time();
      if (!previous || st.period != previous->period || st.offset != previous->offset) {
        previous = &st;
        previous_hit = st.IsHit(time_) ? 1 : 0;
      }
      hit_now_[bi] = previous_hit;
      any_hit = any_hit || previous_hit;
    }
    UpdateInputs(time_);
    ComputeOutputs(time_, /*major=*/true);
    need_reset = MakeModesConsistent(time_, /*major=*/true) || need_reset || any_hit;
    CheckFinite(time_);
    if (std::abs(time_ - NextLogTime()) <= kLogMergeTolerance * log_step_) {
      LogNow();
      ++next_log_index_;
    }
    if (solver_ && need_reset) solver_->Reset(time_, xc_.data());
    if (progress_ && time_ >= next_progress) {
      progress_(time_, t_stop);
      next_progress = time_ + 0.02 * (t_stop - start_time_);
    }
  }
}

// Integrates the continuous states to the next major time, stopping at zero crossings (modes updated, solver
// restarted); more than limits_.max_events_per_major_step of them before t_next is a Zeno loop.
bool Simulator::IntegrateTo(double t_next) {
  bool root_at_end = false;
  double t = time_;
  long events = 0;
  while (t < t_next) {
    bool root = false;
    t = solver_->Integrate(t_next, xc_.data(), &root);
    if (root && t < t_next) {
      if (++events > limits_.max_events_per_major_step) {
        throw NumericalError(fmt::format(
            "{} zero-crossing events between t = {:.9g} s and t = {:.9g} s without reaching the next major step at "
            "{:.9g} s: {} fires again and again (a Zeno loop — e.g. friction with stick_model \"none\" at rest "
            "under a force below Coulomb). Give the block a way to rest (friction: stick_model \"karnopp\" with "
            "its f_applied input) or change the model so that the event does not repeat",
            events - 1, time_, t, t_next, DescribeRoot(solver_->last_root())));
      }
      UpdateInputs(t);
      ComputeOutputs(t, /*major=*/false);
      MakeModesConsistent(t, /*major=*/false);
      solver_->Reset(t, xc_.data());
    } else if (root) {
      root_at_end = true;
    }
  }
  return root_at_end;
}

std::string Simulator::DescribeState(int i) const {
  std::size_t local = 0;
  const std::size_t b = OwnerOf(diagram_.blocks(), static_cast<std::size_t>(i),
                                [](const Block& block) { return block.num_continuous_states(); }, &local);
  const Block& block = *diagram_.blocks()[b];
  return fmt::format("block '{}' continuous state {} of {}", block.name(), local, block.num_continuous_states());
}

std::string Simulator::DescribeRoot(int i) const {
  if (i < 0) return "a zero crossing";
  std::size_t local = 0;
  const std::size_t b = OwnerOf(diagram_.blocks(), static_cast<std::size_t>(i),
                                [](const Block& block) { return block.num_zero_crossings(); }, &local);
  return fmt::format("the zero crossing {} of block '{}'", local, diagram_.blocks()[b]->name());
}

std::string Simulator::DescribeNonFinite(const double* x) const {
  const auto& blocks = diagram_.blocks();
  for (int b : diagram_.execution_order()) {
    const auto bi = static_cast<std::size_t>(b);
    const auto& ports = blocks[bi]->output_ports();
    for (std::size_t p = 0; p < ports.size(); ++p) {
      for (int k = 0; k < ports[p].width; ++k) {
        const double v = contexts_[bi].outputs_[p][k];
        if (std::isfinite(v)) continue;
        return fmt::format("block '{}' output '{}'{} is {}", blocks[bi]->name(), ports[p].name,
                           ports[p].width > 1 ? fmt::format("[{}]", k) : "", v);
      }
    }
  }
  for (int i = 0; x && i < num_continuous_; ++i) {
    if (!std::isfinite(x[i])) return fmt::format("{} is {}", DescribeState(i), x[i]);
  }
  for (std::size_t i = 0; i < xd_.size(); ++i) {
    if (std::isfinite(xd_[i])) continue;
    std::size_t local = 0;
    const std::size_t b = OwnerOf(blocks, i, [](const Block& block) { return block.num_discrete_states(); }, &local);
    return fmt::format("block '{}' discrete state {} is {}", blocks[b]->name(), local, xd_[i]);
  }
  return "";
}

void Simulator::CheckFinite(double t) const {
  // The fast path of every major step: all signals (outputs and external inputs) and states in three flat scans;
  // only a failure walks the blocks to name the first non-finite value.
  const auto finite = [](const std::vector<double>& v) {
    return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
  };
  if (finite(signals_) && finite(xc_) && finite(xd_)) return;
  const std::string where = DescribeNonFinite(xc_.data());
  if (where.empty()) return;
  throw NumericalError(fmt::format("{}: at t = {:.9g} s {} (the first NaN/Inf, in execution order). The model "
                                   "diverged or the block computed an invalid value: check its parameters and "
                                   "inputs{}",
                                   diagram_.name(), t, where,
                                   solver_ ? ", or try a smaller solver step or the cvode solver" : ""));
}

SimulationResult Simulator::Run() {
  const auto start = std::chrono::steady_clock::now();
  Initialize();
  AdvanceTo(diagram_.experiment().stop_time);
  SimulationResult result;
  result.log = log_;
  result.metrics = sink_ ? StreamedMetrics() : ComputeMetrics(diagram_, log_);
  if (solver_) {
    result.solver_stats = solver_->stats();
    result.solver_name = solver_->name();
  } else {
    result.solver_name = "discrete";
  }
  result.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return result;
}

double Simulator::SignalValue(const SignalRef& ref) const {
  if (ref.is_external()) return signals_[external_offset_ + static_cast<std::size_t>(ref.port)];
  return contexts_[static_cast<std::size_t>(ref.block)].outputs_[static_cast<std::size_t>(ref.port)][0];
}

const SolverStats& Simulator::solver_stats() const {
  static const SolverStats kNone;
  return solver_ ? solver_->stats() : kNone;
}

std::map<std::string, double> Simulator::ComputeMetrics(const Diagram& diagram, const SignalLog& log) {
  std::map<std::string, double> out;
  for (const auto& m : diagram.metrics()) {
    const auto& v = log.Column(m.signal);
    const std::vector<double>* ref = m.reference.empty() ? nullptr : &log.Column(m.reference);
    MetricAccumulator sums;
    for (std::size_t i = 0; i < log.time.size(); ++i) {
      if (log.time[i] < m.from || log.time[i] > m.to) continue;
      sums.Add(ref ? v[i] - (*ref)[i] : v[i]);
    }
    out[m.name] = sums.Value(m.type, m.name, m.from, m.to);
  }
  return out;
}

void MetricAccumulator::Add(double x) {
  sum += x;
  sum_sq += x * x;
  max_abs = std::max(max_abs, std::abs(x));
  last = x;
  ++n;
}

double MetricAccumulator::Value(MetricType type, const std::string& name, double from, double to) const {
  if (n == 0) {
    throw std::invalid_argument(fmt::format("metric '{}': no logged sample in the window [{}, {}] s", name, from, to));
  }
  const double nd = static_cast<double>(n);
  switch (type) {
    case MetricType::kRmse:
    case MetricType::kRmsDifference: return std::sqrt(sum_sq / nd);
    case MetricType::kMaxAbs: return max_abs;
    case MetricType::kMean: return sum / nd;
    case MetricType::kFinal: break;
  }
  return last;
}

}  // namespace mb

#include "tests/diagnosis/grammar_draws.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdio>
#include <numbers>
#include <optional>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include <Eigen/Dense>

namespace mb::grammar {
namespace {

constexpr double kTwoPi = 2.0 * std::numbers::pi;
constexpr double kSubStep = 2.5e-5;        // the plant's RK4 step at most [s]
constexpr int kMaxSamples = 25'000;        // a record's samples at most (compare in about a second, Release)
constexpr int kShapeRedraws = 8;           // Draw: a shape that vanishes on the record drawn again at most this often
constexpr int kNoiseRefinements = 4;      // Calibrate: the sensing made finer at most this many times
constexpr double kRatioTolerance = 0.95;   //   until the effect reaches this share of its drawn ratio,
constexpr double kFinestSensing = 0.01;    //   its force noise and encoder step at least this share of the drawn ones
constexpr double kEdgeShare = 0.02;        // NoiseFloor leaves this share of the record out at either end

using Rng = std::mt19937_64;

double Uniform(Rng& rng, double low, double high) { return std::uniform_real_distribution<double>(low, high)(rng); }
double LogUniform(Rng& rng, double low, double high) { return std::exp(Uniform(rng, std::log(low), std::log(high))); }
bool Chance(Rng& rng, double p) { return Uniform(rng, 0.0, 1.0) < p; }
int Index(Rng& rng, std::size_t n) {
  return static_cast<int>(std::uniform_int_distribution<std::size_t>(0, n - 1)(rng));
}

// A stream of its own for each part of a record, so that a twin and its draw consume the same numbers.
enum class Stream : unsigned { kTrajectory = 1, kNoise = 2, kActiveColumn = 3, kThirdColumn = 4, kIdleColumn = 5 };
Rng StreamRng(unsigned seed, Run run, Stream stream) {
  std::seed_seq seq{seed, static_cast<unsigned>(run) + 7U, static_cast<unsigned>(stream), 0x67726d72U};
  return Rng(seq);
}

const std::vector<std::string> kMultipliers = {"one",          "slip",         "velocity",
                                               "speed",        "velocity_speed", "acceleration",
                                               "model_force",  "model_force_abs", "load_slip"};
const std::vector<std::string> kModulators = {"constant",    "position_periodic", "position_local", "position_smooth",
                                              "column",      "column_rate",       "time_ramp",      "time_step",
                                              "time_window", "time_warm_up",      "time_periodic"};

bool IsPosition(const std::string& modulator) { return modulator.rfind("position_", 0) == 0; }
bool IsColumn(const std::string& modulator) { return modulator == "column" || modulator == "column_rate"; }

// ---------------------------------------------------------------------------------------------------------------
// Log columns of the draw's own: values and rates at any instant of a record.

// A column as one record sees it: the temperature's duty pattern is drawn per record; the column's nominal value and
// half-range (Column::Reference, Column::HalfRange) are the machine's, the same on every record.
class ColumnSignal {
 public:
  ColumnSignal() = default;
  ColumnSignal(const Column* column, double duration, Rng rng) : column_(column) {
    if (column_ == nullptr || column_->name.empty()) {
      column_ = nullptr;
      return;
    }
    if (column_->kind == Column::Kind::kTemperature) {  // the duty cycle's pattern and θ at each switch
      double t = 0.0, theta = column_->ambient + column_->rise * Uniform(rng, 0.0, 0.5);
      bool high = Chance(rng, 0.5);
      while (t < duration + 1.0) {
        const double duty = high ? 1.0 : column_->duty_low;
        const double dwell = Uniform(rng, column_->dwell_min, column_->dwell_max);
        start_.push_back(t);
        duty_.push_back(duty);
        theta_.push_back(theta);
        const double target = column_->ambient + column_->rise * duty;
        theta = target + (theta - target) * std::exp(-dwell / column_->lag);
        t += dwell;
        high = !high;
      }
    }
  }

  bool present() const { return column_ != nullptr; }
  double reference() const { return column_->Reference(); }
  double half_range() const { return column_->HalfRange(); }

  double Value(double t) const {
    if (column_->kind == Column::Kind::kTemperature) {
      const std::size_t i = Segment(t);
      const double target = column_->ambient + column_->rise * duty_[i];
      return target + (theta_[i] - target) * std::exp(-(t - start_[i]) / column_->lag);
    }
    return Sines(t, column_->kind == Column::Kind::kOtherAxisVelocity       ? 1
                    : column_->kind == Column::Kind::kOtherAxisAcceleration ? 2
                                                                             : 0) +
           (column_->kind == Column::Kind::kBusVoltage ? column_->offset : 0.0);
  }

  double Rate(double t) const {
    if (column_->kind == Column::Kind::kTemperature) {  // the first-order lag: (target − θ)/T
      const std::size_t i = Segment(t);
      return (column_->ambient + column_->rise * duty_[i] - Value(t)) / column_->lag;
    }
    return Sines(t, column_->kind == Column::Kind::kOtherAxisVelocity       ? 2
                    : column_->kind == Column::Kind::kOtherAxisAcceleration ? 3
                                                                             : 1);
  }

 private:
  std::size_t Segment(double t) const {
    const auto it = std::upper_bound(start_.begin(), start_.end(), t);
    return it == start_.begin() ? 0 : static_cast<std::size_t>(it - start_.begin() - 1);
  }
  // The `order`-th time derivative of Σ A·sin(2πft + φ).
  double Sines(double t, int order) const {
    double sum = 0.0;
    for (std::size_t k = 0; k < column_->amplitude.size(); ++k) {
      const double w = kTwoPi * column_->frequency[k], arg = w * t + column_->phase[k];
      const double wave = order % 4 == 0 ? std::sin(arg) : order % 4 == 1 ? std::cos(arg)
                          : order % 4 == 2                 ? -std::sin(arg)
                                                           : -std::cos(arg);
      sum += column_->amplitude[k] * std::pow(w, order) * wave;
    }
    return sum;
  }

  const Column* column_ = nullptr;
  std::vector<double> start_, duty_, theta_;
};

// ---------------------------------------------------------------------------------------------------------------
// The reference trajectory of one record.

class Reference {
 public:
  Reference(const GrammarDraw& d, Rng rng) : d_(d) {
    const double travel = d.travel(), middle = 0.5 * (d.travel_low + d.travel_high);
    if (d.trajectory == Trajectory::kSweep) {
      amplitude_phase_ = Uniform(rng, 0.0, kTwoPi);
      frequency_phase_ = Uniform(rng, 0.0, kTwoPi);
      start_phase_ = Uniform(rng, 0.0, kTwoPi);
      amplitude_period_ = Uniform(rng, 2.5, 5.0);
      middle_ = middle;
      return;
    }
    // Point-to-point: minimum-jerk moves x0 + D·(10s³ − 15s⁴ + 6s⁵), peak speed 1.875·|D|/T, to targets uniform over
    // the travel at least 15 % of it away, peak speeds 50–100 % of the top speed, rests between the draw's dwells.
    double t = Uniform(rng, 0.1, 0.4), x = middle;
    while (t < d.duration + 1.0) {
      double goal = Uniform(rng, d.travel_low, d.travel_high);
      while (std::abs(goal - x) < 0.15 * travel) goal = Uniform(rng, d.travel_low, d.travel_high);
      const double peak = d.top_speed * Uniform(rng, 0.5, 1.0);
      const double length = 1.875 * std::abs(goal - x) / peak;
      moves_.push_back({t, length, x, goal - x});
      t += length + Uniform(rng, d.dwell_min, d.dwell_max);
      x = goal;
    }
    rest_ = middle;
  }

  /// Position, velocity and acceleration of the reference at t.
  std::array<double, 3> At(double t) const {
    if (d_.trajectory == Trajectory::kSweep) return Sweep(t);
    const auto it = std::upper_bound(moves_.begin(), moves_.end(), t,
                                     [](double q, const Move& m) { return q < m.start; });
    if (it == moves_.begin()) return {rest_, 0.0, 0.0};
    const Move& m = *(it - 1);
    const double s = std::min((t - m.start) / m.length, 1.0);
    if (s >= 1.0) return {m.from + m.distance, 0.0, 0.0};
    const double p = s * s * s * (10.0 + s * (-15.0 + 6.0 * s));
    const double dp = s * s * (30.0 + s * (-60.0 + 30.0 * s));
    const double ddp = s * (60.0 + s * (-180.0 + 120.0 * s));
    return {m.from + m.distance * p, m.distance * dp / m.length, m.distance * ddp / (m.length * m.length)};
  }

 private:
  struct Move {
    double start, length, from, distance;
  };

  // x = x̄ + A(t)·sin φ(t): the amplitude wanders over 60–100 % of the half-travel, the frequency f̄ ± Δf.
  std::array<double, 3> Sweep(double t) const {
    const double h = 0.5 * d_.travel();
    const double wa = kTwoPi / amplitude_period_, wf = kTwoPi / d_.sweep_wander_period;
    const double amp = h * (0.8 + 0.2 * std::sin(wa * t + amplitude_phase_));
    const double damp = h * 0.2 * wa * std::cos(wa * t + amplitude_phase_);
    const double ddamp = -h * 0.2 * wa * wa * std::sin(wa * t + amplitude_phase_);
    const double f = d_.sweep_frequency + d_.sweep_deviation * std::sin(wf * t + frequency_phase_);
    const double df = d_.sweep_deviation * wf * std::cos(wf * t + frequency_phase_);
    const double phase = start_phase_ + kTwoPi * (d_.sweep_frequency * t - d_.sweep_deviation / wf *
                                                                                (std::cos(wf * t + frequency_phase_) -
                                                                                 std::cos(frequency_phase_)));
    const double dphase = kTwoPi * f, ddphase = kTwoPi * df;
    const double s = std::sin(phase), c = std::cos(phase);
    return {middle_ + amp * s, damp * s + amp * c * dphase,
            ddamp * s + 2.0 * damp * c * dphase - amp * s * dphase * dphase + amp * c * ddphase};
  }

  const GrammarDraw& d_;
  std::vector<Move> moves_;
  double rest_ = 0.0, middle_ = 0.0;
  double amplitude_phase_ = 0.0, frequency_phase_ = 0.0, start_phase_ = 0.0, amplitude_period_ = 1.0;
};

// ---------------------------------------------------------------------------------------------------------------
// The effect.

// What one record needs to evaluate the effect: its columns.
struct RunContext {
  ColumnSignal active, third;
};

RunContext MakeContext(const GrammarDraw& d, Run run) {
  RunContext c;
  c.active = ColumnSignal(&d.active_column, d.duration, StreamRng(d.seed, run, Stream::kActiveColumn));
  c.third = ColumnSignal(&d.third_column, d.duration, StreamRng(d.seed, run, Stream::kThirdColumn));
  return c;
}

// What the effects with memory carry along the motion (Simulate and EffectForce): the hysteresis element's state
// z ∈ [−1, 1], the load behind the play's position and velocity.
struct Memory {
  double z = 0.0, load_x = 0.0, load_v = 0.0;
};

// The shaft's force on the load behind the play per unit of the load's mass [m/s² or rad/s²] with the motor at (x, v):
// nothing inside the play, a spring on the twist beyond it and a damper on its rate while in contact.
double PlayShaft(const Shape& s, double x, double v, const Memory& m) {
  const double twist = x - m.load_x, half = 0.5 * s.gap, w = kTwoPi * s.load_hz;
  if (std::abs(twist) <= half) return 0.0;
  return w * w * (twist - std::copysign(half, twist)) + 2.0 * s.load_zeta * w * (v - m.load_v);
}

// The modulator's value at (t, x) and its derivative in x (for a mass along the position's ½M′(x)·v²).
std::pair<double, double> Modulator(const GrammarDraw& d, const RunContext& c, double t, double x, double v = 0.0,
                                    const Memory& memory = {}) {
  const Shape& s = d.shape;
  const std::string& m = d.modulator;
  if (m == "constant") return {1.0, 0.0};
  if (m == "position_periodic") {
    const double k = kTwoPi / s.period;
    return {std::sin(k * x + s.phase) + s.second_harmonic * std::sin(2.0 * k * x + s.second_phase),
            k * std::cos(k * x + s.phase) + 2.0 * k * s.second_harmonic * std::cos(2.0 * k * x + s.second_phase)};
  }
  if (m == "position_local") {
    const double z = (x - s.center) / s.half_width;
    if (!s.trapezoid) return {std::exp(-z * z), -2.0 * z / s.half_width * std::exp(-z * z)};
    const double a = std::abs(z);
    if (a <= 0.5) return {1.0, 0.0};
    if (a >= 1.5) return {0.0, 0.0};
    return {1.5 - a, -(z > 0.0 ? 1.0 : -1.0) / s.half_width};
  }
  if (m == "position_smooth") {
    const double z = (x - s.smooth_middle) / s.smooth_scale;
    if (s.smooth_kind == 0) return {std::tanh(z), (1.0 - std::tanh(z) * std::tanh(z)) / s.smooth_scale};
    if (s.smooth_kind == 1) return {z * z, 2.0 * z / s.smooth_scale};
    return {std::exp(z), std::exp(z) / s.smooth_scale};
  }
  if (m == "column") return {c.active.Value(t) - c.active.reference(), 0.0};
  if (m == "column_rate") return {c.active.Rate(t), 0.0};
  if (m == "time_ramp") return {2.0 * t / d.duration - 1.0, 0.0};
  if (m == "time_step") return {t >= s.change_time ? 1.0 : 0.0, 0.0};
  if (m == "time_window") return {t >= s.on_time && t < s.off_time ? 1.0 : 0.0, 0.0};
  if (m == "time_warm_up") return {-std::expm1(-t / s.time_constant), 0.0};
  if (m == "time_periodic") return {std::sin(kTwoPi * s.frequency_hz * t + s.phase), 0.0};
  if (m == "time_chirp") {
    return {std::sin(kTwoPi * (s.frequency_hz * t + 0.5 * s.drift_rate * t * t) + s.phase), 0.0};
  }
  if (m == "hysteresis") return {memory.z, 0.0};
  if (m == "play_load") return {PlayShaft(s, x, v, memory), 0.0};
  throw std::logic_error("grammar_draws: unknown modulator " + m);
}

// The third factor: 1, or 1 + β·(a linear function of time or the third column, each scaled to ±1).
double ThirdFactor(const GrammarDraw& d, const RunContext& c, double t) {
  if (d.third_factor == "time") return 1.0 + d.third_depth * (2.0 * t / d.duration - 1.0);
  if (d.third_factor == "column") {
    return 1.0 + d.third_depth * (c.third.Value(t) - c.third.reference()) / std::max(c.third.half_range(), 1e-12);
  }
  return 1.0;
}

// The effect as a mass and a force: effect = mass·a + force (the model_force multipliers read the held command u).
struct EffectTerms {
  double mass = 0.0, force = 0.0;
};

EffectTerms Effect(const GrammarDraw& d, const RunContext& c, double t, double x, double v, double u,
                   const Memory& memory = {}) {
  if (d.noise_only || d.amplitude == 0.0) return {};
  const auto [mod, slope] = Modulator(d, c, t, x, v, memory);
  const double gain = d.amplitude * ThirdFactor(d, c, t);
  const std::string& m = d.multiplier;
  const double slip = d.shape.slip_velocity > 0.0 ? std::tanh(v / d.shape.slip_velocity) : 0.0;
  if (m == "acceleration") {  // a mass M(x) acts by Lagrange as M(x)·a + ½M′(x)·v²; in time or a column as M·a
    return {gain * mod, IsPosition(d.modulator) ? 0.5 * gain * slope * v * v : 0.0};
  }
  double factor = 0.0;
  if (m == "one") factor = 1.0;
  else if (m == "slip") factor = slip;
  else if (m == "velocity") factor = v;
  else if (m == "speed") factor = std::abs(v);
  else if (m == "velocity_speed") factor = v * std::abs(v);
  else if (m == "model_force") factor = u;
  else if (m == "load_slip") {  // a friction share of the transmitted force: within ±50 % of it, as above
    return {0.0, std::abs(u) * slip * std::clamp(gain * mod, -0.5, 0.5)};
  }
  else if (m == "model_force_abs") {
    // The force constant's share that the force changes saturates too: within ±50 % (Calibrate keeps it within ±30 %
    // on the twin's record; a loop that the effect drives harder must not run away on an unbounded u·|u|).
    return {0.0, u * std::clamp(gain * std::abs(u) * mod, -0.5, 0.5)};
  }
  else throw std::logic_error("grammar_draws: unknown multiplier " + m);
  return {0.0, gain * factor * mod};
}

// ---------------------------------------------------------------------------------------------------------------
// The closed loop.

// PD or PID on the encoder with feedforward of the (imperfectly known) mass and friction; the velocity from a
// first-order-filtered difference of the encoder.
class Controller {
 public:
  explicit Controller(const GrammarDraw& d) : d_(d) {
    const double w = kTwoPi * d.bandwidth_hz, mass = d.plant.mass * d.feedforward_error[0];
    kp_ = mass * w * w;
    kd_ = 2.0 * 0.7 * w * mass;
    ki_ = d.integral_action ? kp_ * w / 8.0 : 0.0;
    const double dt = 1.0 / d.sample_rate;
    alpha_ = dt / (dt + 1.0 / (kTwoPi * std::min(200.0, 0.2 * d.sample_rate)));
  }
  void Start(double x_measured, double v) {
    x_prev_ = x_measured;
    v_est_ = v;
  }
  double Update(double x_measured, const std::array<double, 3>& ref) {
    const double dt = 1.0 / d_.sample_rate;
    v_est_ += alpha_ * ((x_measured - x_prev_) / dt - v_est_);
    x_prev_ = x_measured;
    const double e = ref[0] - x_measured;
    integral_ += e * dt;
    const Plant& p = d_.plant;
    const double feedforward = p.mass * d_.feedforward_error[0] * ref[2] + p.viscous * d_.feedforward_error[1] * ref[1] +
                               p.coulomb * d_.feedforward_error[2] * std::tanh(ref[1] / (4.0 * p.coulomb_velocity));
    return kp_ * e + kd_ * (ref[1] - v_est_) + ki_ * integral_ + feedforward;
  }

 private:
  const GrammarDraw& d_;
  double kp_ = 0.0, kd_ = 0.0, ki_ = 0.0, alpha_ = 1.0;
  double x_prev_ = 0.0, v_est_ = 0.0, integral_ = 0.0;
};

// The Dahl element's state after a displacement dx, exact for a displacement of one direction: z moves toward sign(dx)
// by the share 1 − exp(−|dx|/λ), λ = stroke/ln 10.
double DahlStep(const GrammarDraw& d, double z, double dx) {
  if (d.modulator != "hysteresis" || dx == 0.0) return z;
  const double target = dx > 0.0 ? 1.0 : -1.0;
  return target - (target - z) * std::exp(-std::abs(dx) * std::log(10.0) / d.shape.stroke);
}

// The load behind the play's acceleration with the motor at (x, v) (0 for any other draw).
double LoadAcceleration(const GrammarDraw& d, double x, double v, const Memory& m) {
  if (d.modulator != "play_load") return 0.0;
  return PlayShaft(d.shape, x, v, m) - d.shape.load_damping * m.load_v;
}

// The body's acceleration at (t, x, v) under the held command u, with the effects' memory.
double Acceleration(const GrammarDraw& d, const RunContext& c, bool with_effect, double t, double x, double v,
                    double u, const Memory& memory = {}) {
  const Plant& p = d.plant;
  const double base = p.viscous * v + p.coulomb * std::tanh(v / p.coulomb_velocity) + p.offset;
  const EffectTerms e = with_effect ? Effect(d, c, t, x, v, u, memory) : EffectTerms{};
  return (u - base - e.force) / (p.mass + e.mass);
}

Eigen::Index SampleCount(const GrammarDraw& d) {
  return std::min<Eigen::Index>(kMaxSamples, static_cast<Eigen::Index>(std::lround(d.duration * d.sample_rate)));
}

// ---------------------------------------------------------------------------------------------------------------
// The generator's own view of a record as an equation-error comparison sees it (NoiseFloor).

// Zero-phase 2nd-order Butterworth (bilinear, pre-warped), forward and backward, odd-reflection padding and a
// steady-state start.
Eigen::VectorXd ZeroPhase(const Eigen::VectorXd& x, double cutoff_hz, double sample_rate) {
  const double k = std::tan(std::numbers::pi * cutoff_hz / sample_rate), r2 = std::sqrt(2.0);
  const double norm = 1.0 / (1.0 + r2 * k + k * k);
  const double b0 = k * k * norm, b1 = 2.0 * b0, b2 = b0;
  const double a1 = 2.0 * (k * k - 1.0) * norm, a2 = (1.0 - r2 * k + k * k) * norm;
  const Eigen::Index n = x.size();
  const Eigen::Index pad = std::min<Eigen::Index>(n - 1, static_cast<Eigen::Index>(3.0 * sample_rate / cutoff_hz));
  std::vector<double> y(static_cast<std::size_t>(n + 2 * pad));
  for (Eigen::Index i = 0; i < pad; ++i) {
    y[static_cast<std::size_t>(i)] = 2.0 * x(0) - x(pad - i);
    y[static_cast<std::size_t>(n + pad + i)] = 2.0 * x(n - 1) - x(n - 2 - i);
  }
  for (Eigen::Index i = 0; i < n; ++i) y[static_cast<std::size_t>(pad + i)] = x(i);
  const auto pass = [&](auto begin, auto end) {
    double z1 = (1.0 - b0) * *begin, z2 = (b2 - a2) * *begin;
    for (auto it = begin; it != end; ++it) {
      const double in = *it, out = b0 * in + z1;
      z1 = b1 * in - a1 * out + z2;
      z2 = b2 * in - a2 * out;
      *it = out;
    }
  };
  pass(y.begin(), y.end());
  pass(y.rbegin(), y.rend());
  return Eigen::Map<const Eigen::VectorXd>(y.data() + pad, n);
}

Eigen::VectorXd Difference(const Eigen::VectorXd& x, double sample_rate) {
  const Eigen::Index n = x.size();
  Eigen::VectorXd d(n);
  for (Eigen::Index i = 1; i + 1 < n; ++i) d(i) = 0.5 * (x(i + 1) - x(i - 1)) * sample_rate;
  d(0) = (x(1) - x(0)) * sample_rate;
  d(n - 1) = (x(n - 1) - x(n - 2)) * sample_rate;
  return d;
}

// ---------------------------------------------------------------------------------------------------------------
// Drawing.

Column DrawColumn(Rng& rng, Column::Kind kind, const std::string& name) {
  Column c;
  c.kind = kind;
  c.name = name;
  if (kind == Column::Kind::kTemperature) {  // θ lags a duty cycle: 5–20 K rise, 1–4 s thermal lag, 0.5–3 s dwells
    c.ambient = Uniform(rng, 20.0, 35.0);
    c.rise = Uniform(rng, 5.0, 20.0);
    c.lag = Uniform(rng, 1.0, 4.0);
    c.duty_low = Uniform(rng, 0.0, 0.3);
    c.dwell_min = Uniform(rng, 0.5, 1.0);
    c.dwell_max = c.dwell_min + Uniform(rng, 0.5, 2.0);
    return c;
  }
  const bool axis = kind != Column::Kind::kBusVoltage;
  // Another axis: three sines of 0.3–3 Hz, 5–30 mm each; a bus voltage: 48 V with two slow ripples of 0.3–1.5 V.
  const int count = axis ? 3 : 2;
  for (int k = 0; k < count; ++k) {
    c.amplitude.push_back(axis ? Uniform(rng, 0.005, 0.03) : Uniform(rng, 0.3, 1.5));
    c.frequency.push_back(axis ? LogUniform(rng, 0.3, 3.0) : LogUniform(rng, 0.05, 0.5));
    c.phase.push_back(Uniform(rng, 0.0, kTwoPi));
  }
  c.offset = axis ? 0.0 : 48.0;
  return c;
}

// The active column of a column modulator: a temperature, the other axis' velocity or acceleration, a bus voltage.
Column DrawActiveColumn(Rng& rng) {
  switch (Index(rng, 4)) {
    case 0: return DrawColumn(rng, Column::Kind::kTemperature, "oil_temperature_C");
    case 1: return DrawColumn(rng, Column::Kind::kOtherAxisVelocity, "vel_y_m_s");
    case 2: return DrawColumn(rng, Column::Kind::kOtherAxisAcceleration, "accel_y_m_s2");
    default: return DrawColumn(rng, Column::Kind::kBusVoltage, "bus_voltage_V");
  }
}

// The machine, the record's format, the trajectory and the controller.
void DrawMachine(Rng& rng, GrammarDraw* d) {
  d->rotary = Chance(rng, 0.5);
  Plant& p = d->plant;
  if (d->rotary) {  // rad, N·m, kg·m²
    p.mass = LogUniform(rng, 0.01, 0.1);
    p.viscous = LogUniform(rng, 0.005, 0.1);
    p.coulomb = LogUniform(rng, 0.05, 0.5);
    p.offset = Uniform(rng, -0.05, 0.05);
    const double travel = Uniform(rng, 2.0, 6.0), low = Uniform(rng, -3.0, 3.0 - travel * 0.5);
    d->travel_low = low;
    d->travel_high = low + travel;
    d->top_speed = LogUniform(rng, 1.0, 6.0);
    p.coulomb_velocity = std::max(2e-3, LogUniform(rng, 0.001, 0.005) * d->top_speed);
    d->encoder_step = kTwoPi / std::pow(2.0, Uniform(rng, 16.0, 20.0));
    d->force_noise = LogUniform(rng, 0.005, 0.02);
  } else {  // m, N, kg
    p.mass = LogUniform(rng, 15.0, 150.0);
    p.viscous = LogUniform(rng, 20.0, 250.0);
    p.coulomb = LogUniform(rng, 3.0, 30.0);
    p.offset = Uniform(rng, -1.0, 1.0);
    const double travel = Uniform(rng, 0.08, 0.4), low = Uniform(rng, 0.0, 0.1);
    d->travel_low = low;
    d->travel_high = low + travel;
    d->top_speed = LogUniform(rng, 0.05, 0.4);
    p.coulomb_velocity = std::max(2e-4, LogUniform(rng, 0.001, 0.005) * d->top_speed);
    d->encoder_step = LogUniform(rng, 1e-7, 1e-6);
    d->force_noise = LogUniform(rng, 0.2, 1.0);
  }
  d->sample_rate = LogUniform(rng, 200.0, 5000.0);
  d->duration = std::min(Uniform(rng, 8.0, 12.0), static_cast<double>(kMaxSamples) / d->sample_rate);
  d->trajectory = Chance(rng, 0.5) ? Trajectory::kPointToPoint : Trajectory::kSweep;
  d->dwell_min = Uniform(rng, 0.1, 0.4);
  d->dwell_max = d->dwell_min + Uniform(rng, 0.1, 0.6);
  // A sweep's mean speed 2·A·f̄ ≈ the top speed over the mean amplitude 0.8·h; its frequency wanders by 20–45 %.
  d->sweep_frequency = d->top_speed / (kTwoPi * 0.4 * d->travel());
  d->sweep_deviation = Uniform(rng, 0.2, 0.45) * d->sweep_frequency;
  d->sweep_wander_period = Uniform(rng, 3.0, 6.0);
  d->integral_action = Chance(rng, 0.5);
  d->bandwidth_hz = std::min(LogUniform(rng, 4.0, 20.0), d->sample_rate / 30.0);
  for (double& e : d->feedforward_error) e = Uniform(rng, 0.8, 1.2);
}

// The modulator's shape and its key parameter's truth and tolerance.
// The band a vibration of time is drawn from [Hz], away from the motion: a sweep's harmonics k·f for k ≤ 8 over its
// whole range lie below 8·(f̄ + Δf); above 1.2 × that, or, point to point, from 2 Hz; at most 40 Hz and a tenth of the
// sample rate.
std::pair<double, double> VibrationBand(const GrammarDraw& d) {
  const double low =
      d.trajectory == Trajectory::kSweep ? std::max(2.0, 9.6 * (d.sweep_frequency + d.sweep_deviation)) : 2.0;
  return {low, std::min(40.0, 0.1 * d.sample_rate)};
}

void DrawShape(Rng& rng, GrammarDraw* d) {
  Shape& s = d->shape;
  const double travel = d->travel(), duration = d->duration;
  s.slip_velocity = std::max(d->plant.coulomb_velocity, LogUniform(rng, 0.001, 0.01) * d->top_speed);
  const std::string& m = d->modulator;
  if (m == "position_periodic") {  // 3–40 cycles in the travel, log-uniform; half with a 20–50 % second harmonic
    s.period = travel / LogUniform(rng, 3.0, 40.0);
    s.phase = Uniform(rng, 0.0, kTwoPi);
    if (Chance(rng, 0.5)) {
      s.second_harmonic = Uniform(rng, 0.2, 0.5);
      s.second_phase = Uniform(rng, 0.0, kTwoPi);
    }
    d->key_parameter = "period";
    d->key_value = s.period;
    d->key_tolerance = 0.03 * s.period;
  } else if (m == "position_local") {  // half-width 2–10 % of the travel, centred inside it (Shape's comment)
    s.half_width = Uniform(rng, 0.02, 0.10) * travel;
    s.trapezoid = Chance(rng, 0.5);
    const double margin =
        std::max({2.0 * s.half_width, 0.15 * travel, d->trajectory == Trajectory::kSweep ? 0.22 * travel : 0.0});
    s.center = Uniform(rng, d->travel_low + margin, d->travel_high - margin);
    d->key_parameter = "center";
    d->key_value = s.center;
    d->key_tolerance = 0.03 * travel;
  } else if (m == "position_smooth") {  // tanh, a parabola or an exponential over the travel
    s.smooth_kind = Index(rng, 3);
    s.smooth_middle = d->travel_low + Uniform(rng, 0.3, 0.7) * travel;
    s.smooth_scale = Uniform(rng, 0.2, 0.6) * travel;
  } else if (m == "time_step") {  // in the middle 70 % of the record
    s.change_time = Uniform(rng, 0.15, 0.85) * duration;
    d->key_parameter = "change_time";
    d->key_value = s.change_time;
    d->key_tolerance = 0.05 * duration;
  } else if (m == "time_window") {  // on and off in the middle 70 %, on for 15–50 % of the record
    const double length = Uniform(rng, 0.15, 0.5);
    s.on_time = Uniform(rng, 0.15, 0.85 - length) * duration;
    s.off_time = s.on_time + length * duration;
    d->key_parameter = "on_time";
    d->key_value = s.on_time;
    d->key_tolerance = 0.05 * duration;
    d->second_parameter = "off_time";
    d->second_value = s.off_time;
  } else if (m == "time_warm_up") {  // from the record's start, T = 5–40 % of the record
    s.time_constant = Uniform(rng, 0.05, 0.4) * duration;
    d->key_parameter = "time_constant";
    d->key_value = s.time_constant;
    d->key_tolerance = 0.2 * s.time_constant;
  } else if (m == "time_periodic") {
    const auto [low, high] = VibrationBand(*d);
    s.frequency_hz = LogUniform(rng, std::min(low, 0.8 * high), high);
    s.phase = Uniform(rng, 0.0, kTwoPi);
    d->key_parameter = "frequency_hz";
    d->key_value = s.frequency_hz;
    d->key_tolerance = 0.03 * s.frequency_hz;
  }
  if (IsColumn(m)) d->active_column = DrawActiveColumn(rng);
}

// An effect with memory, a third of the draws each: hysteresis over a stroke of 1–6 % of the travel (log-uniform); a
// load behind a play of 0.5–3 % of the travel, its shaft's mode 5 Hz … a tenth of the sample rate (at most 60 Hz), ζ
// 0.05–0.3, its bearing 0.5–20 /s; or a multiplier (uniform) × a vibration whose frequency drifts by a factor 1.5–3
// over the record, up or down, within the band time_periodic draws from (away from the motion's harmonics).
void DrawMemoryEffect(Rng& rng, GrammarDraw* d) {
  Shape& s = d->shape;
  s.slip_velocity = std::max(d->plant.coulomb_velocity, LogUniform(rng, 0.001, 0.01) * d->top_speed);
  const int kind = Index(rng, 3);
  if (kind == 1) {
    d->multiplier = "one";
    d->modulator = "play_load";
    d->effect = "backlash_load";
    s.gap = LogUniform(rng, 0.005, 0.03) * d->travel();
    s.load_hz = LogUniform(rng, 5.0, std::min(60.0, 0.1 * d->sample_rate));
    s.load_zeta = Uniform(rng, 0.05, 0.3);
    s.load_damping = LogUniform(rng, 0.5, 20.0);
    d->key_parameter = "backlash";
    d->key_value = s.gap;
    d->key_tolerance = 0.25 * s.gap;
    return;
  }
  if (kind == 0) {
    d->multiplier = "one";
    d->modulator = "hysteresis";
    d->effect = "hysteresis";
    s.stroke = LogUniform(rng, 0.01, 0.06) * d->travel();
    d->key_parameter = "stroke";
    d->key_value = s.stroke;
    d->key_tolerance = 0.25 * s.stroke;
    return;
  }
  d->multiplier = kMultipliers[static_cast<std::size_t>(Index(rng, kMultipliers.size()))];
  d->modulator = "time_chirp";
  const auto [low, high] = VibrationBand(*d);
  const double bottom = std::min(low, high / 1.5);
  const double ratio = std::min(Uniform(rng, 1.5, 3.0), high / bottom);
  const double f_low = LogUniform(rng, bottom, high / ratio), f_high = f_low * ratio;
  const bool up = Chance(rng, 0.5);
  s.frequency_hz = up ? f_low : f_high;
  s.drift_rate = ((up ? f_high : f_low) - s.frequency_hz) / d->duration;
  s.phase = Uniform(rng, 0.0, kTwoPi);
  d->key_parameter = "drift_rate";
  d->key_value = s.drift_rate;
  d->key_tolerance = 0.1 * std::abs(s.drift_rate);
}

// The sign of the effect: a friction of a one-signed modulator dissipates (positive), else either.
double DrawSign(Rng& rng, const GrammarDraw& d) {
  const bool dissipative = d.multiplier == "slip" || d.multiplier == "velocity" || d.multiplier == "velocity_speed" ||
                           d.multiplier == "load_slip";
  const bool one_signed = d.modulator == "constant" || d.modulator == "position_local" || d.modulator == "time_step" ||
                          d.modulator == "time_window" || d.modulator == "time_warm_up" ||
                          (d.modulator == "position_smooth" && d.shape.smooth_kind != 0);
  if (dissipative && one_signed) return 1.0;
  if (d.modulator == "hysteresis") return 1.0;  // a Dahl element resists the motion
  if (d.modulator == "play_load") return 1.0;   // a mass
  return Chance(rng, 0.5) ? 1.0 : -1.0;
}

// The largest amplitude the machine's physical limits allow for target_ratio × the floor: a mass along the record at
// least 60 % of the body's, a force constant within ±30 %, a Coulomb level or viscous coefficient at least 10 % of the
// plant's own (Effect bounds a friction of the transmitted force within 50 % of it). Sets noise_floor; returns the
// amplitude's magnitude and the ratio it reaches, or nullopt where the effect vanishes on the record (all of it in the
// base's span: a bump the motion never reaches, or one flat over all it reaches).
std::optional<std::pair<double, double>> LimitedAmplitude(GrammarDraw* d, double sign) {
  const Record twin = Simulate(*d, Run::kTraining, false);
  d->noise_floor = NoiseFloor(*d, twin);
  const auto rms_at = [&](double amplitude) {
    GrammarDraw at = *d;
    at.amplitude = amplitude;
    return RmsBeyondBase(*d, twin, EffectForce(at, Run::kTraining, twin.time, twin.true_position, twin.velocity,
                                                twin.acceleration, twin.command));
  };
  // Per unit of amplitude, measured where Effect's ±50 % bounds do not bind (a force constant's share A·|u| at most
  // 0.1 %): at A = 1 they bind on any force beyond 0.5 N, and u·|u| bounded is u·0.5, the base's own column.
  const double small = 1e-3 / std::max(1.0, twin.command.cwiseAbs().maxCoeff());
  const double rms = rms_at(small) / small;
  if (!(rms > 0.0)) return std::nullopt;
  double amplitude = d->target_ratio * d->noise_floor / rms;
  const RunContext c = MakeContext(*d, Run::kTraining);
  double peak = 0.0;    // of the unit effect's mass or force-constant share
  double lowest = 0.0;  // of the signed unit modulator: where a friction of the plant's own law is lowered most
  double pushing = 0.0;  // of the unit effect's slope along the motion, ∂f/∂v where it pushes (negative damping)
  for (Eigen::Index i = 0; i < twin.time.size(); ++i) {
    const double mod = Modulator(*d, c, twin.time(i), twin.true_position(i), twin.velocity(i)).first *
                       ThirdFactor(*d, c, twin.time(i));
    if (d->multiplier == "acceleration" || d->multiplier == "model_force") peak = std::max(peak, std::abs(mod));
    if (d->multiplier == "model_force_abs") peak = std::max(peak, std::abs(mod * twin.command(i)));
    lowest = std::min(lowest, sign * mod);
    if (d->multiplier == "speed") pushing = std::max(pushing, std::abs(mod));  // ±|v|: one direction always pushes
    if (d->multiplier == "velocity_speed") pushing = std::max(pushing, -sign * mod * 2.0 * std::abs(twin.velocity(i)));
  }
  // A force of the speed, or a quadratic drag that turns negative, pushes along the motion: a negative damping, which
  // the loop's own (the plant's viscous friction and the controller's derivative gain) must outweigh twice over, or the
  // loop runs away (seed 214: |v| times a ramp, the arm at 1.8e11 rad by the record's end).
  if (pushing > 0.0) {
    const double derivative_gain = 2.0 * 0.7 * kTwoPi * d->bandwidth_hz * d->plant.mass * d->feedforward_error[0];
    const double own = d->plant.viscous + derivative_gain;  // as Controller sets its kd
    amplitude = std::min(amplitude, 0.5 * own / pushing);
  }
  if (d->multiplier == "acceleration") amplitude = std::min(amplitude, 0.4 * d->plant.mass / peak);
  if (d->modulator == "play_load") amplitude = std::min(amplitude, d->plant.mass);  // a load at most the motor's mass
  if (d->multiplier == "model_force" || d->multiplier == "model_force_abs") amplitude = std::min(amplitude, 0.3 / peak);
  // A Coulomb level or a viscous coefficient that changes keeps at least 10 % of the plant's own: a friction that turns
  // negative (pushing along the motion) is no machine, and the model's friction block, bounded at 0, cannot follow it
  // (seed 16: a Coulomb drift from −A to +A about a smaller level left improve 3.5 × above the floor).
  if (lowest < 0.0 && (d->multiplier == "slip" || d->multiplier == "velocity")) {
    const double own = d->multiplier == "slip" ? d->plant.coulomb : d->plant.viscous;
    amplitude = std::min(amplitude, 0.9 * own / -lowest);
  }
  return std::pair{amplitude, rms_at(sign * amplitude) / d->noise_floor};  // with Effect's bounds, as the record has it
}

// Sets the amplitude: the effect's RMS beyond the base on the training twin's motion = target_ratio × its floor. Where
// the machine's physical limits (LimitedAmplitude) hold it lower, the machine's sensing is drawn finer instead — its
// force noise and encoder step scaled down together, up to kNoiseRefinements times — so that the effect stands at the
// drawn ratio over a lower floor: a force constant saturating by 30 % at most is shown by a quieter record, not by a
// stronger saturation. The sensing is made at most 100 × finer, and no finer once the floor stops falling with it; the
// ratio reached, which may then stay below the drawn one, is kept in target_ratio.
// Returns false, d unchanged but for its noise floor, where the effect vanishes on the record.
bool Calibrate(GrammarDraw* d, double sign) {
  const double wanted = d->target_ratio;
  const std::optional<std::pair<double, double>> first = LimitedAmplitude(d, sign);
  if (!first) return false;
  std::pair<double, double> limited = *first;  // amplitude, ratio
  for (int i = 0; i < kNoiseRefinements && limited.second < kRatioTolerance * wanted; ++i) {
    const double finer = std::max(limited.second / wanted, kFinestSensing / d->noise_scale);
    if (!(finer < 1.0)) break;
    d->force_noise *= finer;
    d->encoder_step *= finer;
    d->noise_scale *= finer;
    const double before = limited.second;
    limited = LimitedAmplitude(d, sign).value_or(limited);
    // The floor no longer falls with the sensors' noise: what is left of it is the record's own (the controller's held
    // command between samples, the derived motion's lag), which no sensor lowers.
    if (!(limited.second > 1.1 * before)) break;
  }
  d->amplitude = sign * limited.first;
  d->target_ratio = limited.second;
  return true;
}

}  // namespace

const std::vector<std::string>& MultiplierIds() { return kMultipliers; }
const std::vector<std::string>& ModulatorIds() { return kModulators; }

bool IsDrawnPair(const std::string& multiplier, const std::string& modulator) {
  if (modulator != "constant") return true;
  return !(multiplier == "one" || multiplier == "slip" || multiplier == "velocity" || multiplier == "acceleration" ||
           multiplier == "model_force");
}

GrammarDraw Draw(unsigned seed) {
  GrammarDraw d;
  d.seed = seed;
  d.noise_only = seed >= kNoiseOnlySeedBase && seed < kMemorySeedBase;
  d.memory = seed >= kMemorySeedBase;
  Rng rng(seed);
  DrawMachine(rng, &d);
  if (d.memory) {
    DrawMemoryEffect(rng, &d);
    d.target_ratio = LogUniform(rng, 4.0, 30.0);
  } else if (!d.noise_only) {
    std::vector<std::pair<std::string, std::string>> pairs;
    for (const auto& mu : kMultipliers) {
      for (const auto& mo : kModulators) {
        if (IsDrawnPair(mu, mo)) pairs.emplace_back(mu, mo);
      }
    }
    std::tie(d.multiplier, d.modulator) = pairs[static_cast<std::size_t>(Index(rng, pairs.size()))];
    DrawShape(rng, &d);
    if (Chance(rng, 0.25)) {  // a third factor: time or a further column, ±20–50 %
      d.third_factor = Chance(rng, 0.5) ? "time" : "column";
      d.third_depth = Uniform(rng, 0.2, 0.5);
      if (d.third_factor == "column") d.third_column = DrawColumn(rng, Column::Kind::kTemperature, "winding_temperature_C");
    }
    d.target_ratio = LogUniform(rng, 4.0, 30.0);
  }
  if (Chance(rng, 1.0 / 3.0)) {  // an idle column: the hall's temperature or an auxiliary supply
    d.idle_column = Chance(rng, 0.5) ? DrawColumn(rng, Column::Kind::kTemperature, "hall_temperature_C")
                                     : DrawColumn(rng, Column::Kind::kBusVoltage, "aux_voltage_V");
  }
  if (d.noise_only) {
    d.noise_floor = NoiseFloor(d, Simulate(d, Run::kTraining, false));
    return d;
  }
  // A shape the record cannot show is drawn again (seed 752: a bump of one × a stretch of the travel that the
  // point-to-point moves never left flat), the rest of the draw kept; the draws that show theirs are as they were.
  for (int attempt = 0; !Calibrate(&d, DrawSign(rng, d)); ++attempt) {
    if (d.memory || attempt == kShapeRedraws) {
      throw std::logic_error("grammar_draws: the effect of " + d.Describe() + " vanishes on the record");
    }
    DrawShape(rng, &d);
  }
  return d;
}

Record Simulate(const GrammarDraw& d, Run run, bool with_effect) {
  const Eigen::Index n = SampleCount(d);
  const double dt = 1.0 / d.sample_rate;
  const int sub = std::max(1, static_cast<int>(std::ceil(dt / kSubStep - 1e-9)));
  const double h = dt / sub;
  const Reference reference(d, StreamRng(d.seed, run, Stream::kTrajectory));
  const RunContext context = MakeContext(d, run);
  const ColumnSignal idle(&d.idle_column, d.duration, StreamRng(d.seed, run, Stream::kIdleColumn));
  Rng noise_rng = StreamRng(d.seed, run, Stream::kNoise);
  std::normal_distribution<double> noise(0.0, d.force_noise);

  Record r;
  r.rotary = d.rotary;
  for (Eigen::VectorXd* v : {&r.time, &r.position, &r.force, &r.command, &r.true_position, &r.velocity,
                             &r.acceleration, &r.effect_force, &r.reference}) {
    v->resize(n);
  }
  const std::vector<std::pair<const Column*, const ColumnSignal*>> logged = {
      {&d.active_column, &context.active}, {&d.third_column, &context.third}, {&d.idle_column, &idle}};
  for (const auto& [column, signal] : logged) {
    if (signal->present()) {
      r.column_names.push_back(column->name);
      r.columns.emplace_back(n);
    }
  }
  const bool effect = with_effect && !d.noise_only;
  const bool load = effect && d.modulator == "play_load";  // a load behind a play to carry along
  const std::array<double, 3> start = reference.At(0.0);
  double x = start[0], v = start[1];
  Memory memory{0.0, x, v};  // the hysteresis element relaxed, the load centred in its play
  const auto quantise = [&](double q) { return std::floor(q / d.encoder_step) * d.encoder_step; };
  Controller controller(d);
  controller.Start(quantise(x), v);
  for (Eigen::Index k = 0; k < n; ++k) {
    const double t = static_cast<double>(k) * dt;
    const std::array<double, 3> ref = reference.At(t);
    const double measured = quantise(x);
    const double u = controller.Update(measured, ref);
    r.time(k) = t;
    r.position(k) = measured;
    r.force(k) = u + noise(noise_rng);
    r.command(k) = u;
    r.true_position(k) = x;
    r.velocity(k) = v;
    r.reference(k) = ref[0];
    const EffectTerms e = effect ? Effect(d, context, t, x, v, u, memory) : EffectTerms{};
    r.acceleration(k) = Acceleration(d, context, effect, t, x, v, u, memory);
    r.effect_force(k) = e.mass * r.acceleration(k) + e.force;
    std::size_t j = 0;
    for (const auto& [column, signal] : logged) {
      if (signal->present()) r.columns[j++](k) = signal->Value(t);
    }
    for (int i = 0; i < sub; ++i) {  // RK4 on the sub-step of the body and the load, the command held
      const double s = t + i * h;
      using State = std::array<double, 4>;  // x, v, the load's x and v
      const auto f = [&](double tt, const State& q) {
        const Memory m{memory.z, q[2], q[3]};
        return State{q[1], Acceleration(d, context, effect, tt, q[0], q[1], u, m), q[3],
                     load ? LoadAcceleration(d, q[0], q[1], m) : 0.0};
      };
      const auto add = [](const State& a, const State& b, double w) {
        return State{a[0] + w * b[0], a[1] + w * b[1], a[2] + w * b[2], a[3] + w * b[3]};
      };
      const State q{x, v, memory.load_x, memory.load_v};
      const State k1 = f(s, q), k2 = f(s + 0.5 * h, add(q, k1, 0.5 * h)), k3 = f(s + 0.5 * h, add(q, k2, 0.5 * h));
      const State k4 = f(s + h, add(q, k3, h));
      State next = q;
      for (std::size_t c = 0; c < next.size(); ++c) next[c] += h / 6.0 * (k1[c] + 2.0 * k2[c] + 2.0 * k3[c] + k4[c]);
      memory.z = DahlStep(d, memory.z, next[0] - x);  // held over the sub-step, as the command is
      x = next[0];
      v = next[1];
      memory.load_x = next[2];
      memory.load_v = next[3];
    }
  }
  return r;
}

Eigen::VectorXd EffectForce(const GrammarDraw& d, Run run, const Eigen::VectorXd& time, const Eigen::VectorXd& position,
                            const Eigen::VectorXd& velocity, const Eigen::VectorXd& acceleration,
                            const Eigen::VectorXd& command) {
  const RunContext c = MakeContext(d, run);
  Eigen::VectorXd f(time.size());
  if (time.size() == 0) return f;
  // The hysteresis element along the positions (DahlStep); the load behind the play from the motor's motion, RK4 on
  // sub-steps of at most kSubStep with the motor between the samples on a straight line.
  Memory memory{0.0, position(0), velocity(0)};
  for (Eigen::Index i = 0; i < time.size(); ++i) {
    if (i > 0) {
      memory.z = DahlStep(d, memory.z, position(i) - position(i - 1));
      if (d.modulator == "play_load") {
        const double dt = time(i) - time(i - 1);
        const int sub = std::max(1, static_cast<int>(std::ceil(dt / kSubStep - 1e-9)));
        const double h = dt / sub;
        const auto motor = [&](double q) {
          return std::pair{position(i - 1) + q * (position(i) - position(i - 1)),
                           velocity(i - 1) + q * (velocity(i) - velocity(i - 1))};
        };
        const auto load = [&](double q, double lx, double lv) {
          const auto [mx, mv] = motor(q);
          return LoadAcceleration(d, mx, mv, Memory{0.0, lx, lv});
        };
        for (int j = 0; j < sub; ++j) {
          const double qa = static_cast<double>(j) / sub, qb = (j + 0.5) / sub, qc = (j + 1.0) / sub;
          const double lx = memory.load_x, lv = memory.load_v;
          const double a1 = load(qa, lx, lv), a2 = load(qb, lx + 0.5 * h * lv, lv + 0.5 * h * a1);
          const double a3 = load(qb, lx + 0.5 * h * (lv + 0.5 * h * a1), lv + 0.5 * h * a2);
          const double a4 = load(qc, lx + h * (lv + 0.5 * h * a2), lv + h * a3);
          memory.load_x += h / 6.0 * (lv + 2.0 * (lv + 0.5 * h * a1) + 2.0 * (lv + 0.5 * h * a2) + (lv + h * a3));
          memory.load_v += h / 6.0 * (a1 + 2.0 * a2 + 2.0 * a3 + a4);
        }
      }
    }
    const EffectTerms e = Effect(d, c, time(i), position(i), velocity(i), command(i), memory);
    f(i) = e.mass * acceleration(i) + e.force;
  }
  return f;
}

Eigen::VectorXd BaseForce(const Plant& p, const Eigen::VectorXd& velocity, const Eigen::VectorXd& acceleration) {
  return (p.mass * acceleration.array() + p.viscous * velocity.array() +
          p.coulomb * (velocity.array() / p.coulomb_velocity).tanh() + p.offset)
      .matrix();
}

double RmsBeyondBase(const GrammarDraw& d, const Record& record, const Eigen::VectorXd& force) {
  const Eigen::Index n = force.size();
  Eigen::MatrixXd x(n, 4);
  x.col(0) = record.acceleration;
  x.col(1) = record.velocity;
  x.col(2) = (record.velocity.array() / d.plant.coulomb_velocity).tanh().matrix();
  x.col(3).setOnes();
  const Eigen::VectorXd beta = x.colPivHouseholderQr().solve(force);
  return std::sqrt((force - x * beta).squaredNorm() / static_cast<double>(n));
}

double NoiseFloor(const GrammarDraw& d, const Record& record) {
  const double fs = d.sample_rate, cutoff = std::min(100.0, 0.2 * fs);
  const Eigen::VectorXd x = ZeroPhase(record.position, cutoff, fs);
  const Eigen::VectorXd v = Difference(x, fs), a = Difference(v, fs);
  const Eigen::Index n = record.force.size();
  Eigen::VectorXd held(n);  // the held command's mean over the sample period centred on each instant
  held(0) = record.force(0);
  for (Eigen::Index i = 1; i < n; ++i) held(i) = 0.5 * (record.force(i - 1) + record.force(i));
  const Eigen::VectorXd residual = ZeroPhase(held, cutoff, fs) - ZeroPhase(BaseForce(d.plant, v, a), cutoff, fs);
  const auto edge = static_cast<Eigen::Index>(kEdgeShare * static_cast<double>(n));
  return std::sqrt(residual.segment(edge, n - 2 * edge).squaredNorm() / static_cast<double>(n - 2 * edge));
}

void WriteCsv(const Record& record, const std::string& path) {
  std::FILE* f = std::fopen(path.c_str(), "w");
  if (f == nullptr) throw std::runtime_error("grammar_draws WriteCsv: cannot write " + path);
  std::fprintf(f, "%s", record.rotary ? "time_s,angle_rad,torque_Nm" : "time_s,position_m,force_N");
  for (const auto& name : record.column_names) std::fprintf(f, ",%s", name.c_str());
  std::fprintf(f, "\n");
  for (Eigen::Index i = 0; i < record.time.size(); ++i) {
    std::fprintf(f, "%.17g,%.17g,%.17g", record.time(i), record.position(i), record.force(i));
    for (const auto& column : record.columns) std::fprintf(f, ",%.17g", column(i));
    std::fprintf(f, "\n");
  }
  if (std::fclose(f) != 0) throw std::runtime_error("grammar_draws WriteCsv: cannot write " + path);
}

std::string GrammarDraw::Describe() const {
  std::string text = "seed " + std::to_string(seed) + ": " + pair();
  if (!active_column.name.empty()) text += " (" + active_column.name + ")";
  if (!third_factor.empty()) text += " × " + third_factor;
  if (!idle_column.name.empty()) text += ", idle " + idle_column.name;
  char numbers[256];
  std::snprintf(numbers, sizeof numbers, ", %s = %.5g, ratio %.1f, %s, %.0f Hz, %.1f s, %s, %s",
                key_parameter.empty() ? "—" : key_parameter.c_str(), key_value, target_ratio,
                rotary ? "rotary" : "linear", sample_rate, duration,
                trajectory == Trajectory::kSweep ? "sweep" : "point to point", integral_action ? "PID" : "PD");
  text += numbers;
  if (!second_parameter.empty()) {
    std::snprintf(numbers, sizeof numbers, ", %s = %.5g", second_parameter.c_str(), second_value);
    text += numbers;
  }
  if (multiplier == "slip" || multiplier == "load_slip") {
    std::snprintf(numbers, sizeof numbers, ", slip velocity %.3g", shape.slip_velocity);
    text += numbers;
  }
  if (modulator == "play_load") {
    std::snprintf(numbers, sizeof numbers, ", load %.3g at %.3g Hz, ζ %.2f, bearing %.2g /s", amplitude, shape.load_hz,
                  shape.load_zeta, shape.load_damping);
    text += numbers;
  }
  if (noise_scale < 1.0) {
    std::snprintf(numbers, sizeof numbers, ", sensing ×%.2g", noise_scale);
    text += numbers;
  }
  return text;
}

}  // namespace mb::grammar

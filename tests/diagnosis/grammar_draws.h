#pragma once
// Random draws from the diagnosis' grammar (issue 45, item 6: "proof on random draws, not on a list";
// DIAGNOSIS.md "Generated, not listed"). Each draw is a machine with one hidden product effect, multiplier ×
// modulator (docs/diagnosis.md, "The grammar"), drawn from a seed alone, and the closed-loop records of it. The data
// are made by code that shares nothing with the diagnosis: its own rigid body integrated by RK4 on a fixed sub-step,
//   M·a = u_applied − F_v·v − F_c·tanh(v/v_c) − offset − effect,
// its own friction law, PD or PID controller with feedforward, trajectories, encoder quantisation, force noise and log
// columns (a temperature lagging a duty cycle, another axis' motion, a bus voltage). Only the standard library and
// Eigen are used; nothing of models/ or the diagnosis' regressors.
//
// What a draw draws (std::mt19937_64 seeded with the seed; every distribution is stated where it is drawn,
// grammar_draws.cc):
//  - the pair, uniformly among the 9 × 11 multiplier × modulator pairs less the five that are the base model itself
//    (constant × {one, slip, velocity, acceleration, model_force}: an offset, a Coulomb level, a viscous coefficient,
//    a mass, a force constant the base refit takes): 94 pairs;
//  - the modulator's shape: a position period of 3–40 cycles in the travel (log-uniform; half the draws with a second
//    harmonic of 20–50 %), a bump (Gaussian or trapezoid, not the diagnosis' cos²) centred inside the travel with a
//    half-width of 2–10 % of it, a smooth profile of its own kind (tanh step, quadratic or exponential over the
//    travel; not the diagnosis' cubic), a column of its own (the temperature θ lagging a duty cycle through a
//    first-order thermal lag, another axis' velocity or acceleration, a bus voltage), a step or a window at times in
//    the middle 70 % of the record, a warm-up from the record's start with a time constant of 5–40 % of the record, a
//    vibration whose frequency is kept away from the motion's harmonics;
//  - the term's amplitude: its RMS along the record, less what the base model's columns (a, v, tanh(v/v_c), 1) take,
//    4–30 × the draw's noise floor (log-uniform; NoiseFloor below), with a sign that dissipates when the modulator is
//    one-signed and the multiplier a friction. The machine's physical limits cap it (a mass at least 60 % of the
//    body's, a force constant within ±30 %, a friction at least 10 % of the plant's own); where they hold it below the
//    drawn ratio, the force noise and encoder step are scaled down until the capped effect reaches it (noise_scale);
//  - a quarter of the draws a third factor: the amplitude follows time linearly, or a further logged column, by
//    ±20–50 %; a third of the draws an idle column that does not act;
//  - a linear (m, N, kg) or a rotary (rad, N·m, kg·m²) axis, its mass, friction and offset; a sample rate of
//    200 Hz–5 kHz (log-uniform); a record of 8–12 s capped at 25,000 samples; point-to-point moves with dwell or a
//    sinusoidal sweep whose frequency and amplitude wander, both travelling both ways; a PD or PID with feedforward,
//    its gains from a drawn bandwidth; an encoder step and the force's noise.
// Noise-only draws (seeds from kNoiseOnlySeedBase) are machines of the same kind with no effect.
//
// The records: the controller runs at the log's rate and its command is held (ZOH) until the next sample; the
// logged force is that command plus noise. A training and a validation record share the machine and differ in the
// trajectory's instance, the duty cycle's pattern and the noise. The effect-free twin of a record (with_effect false)
// is the same record, the same trajectory and noise draws, without the effect.

#include <cmath>
#include <numbers>
#include <string>
#include <vector>

#include <Eigen/Core>

namespace mb::grammar {

/// Seeds from here on are noise-only draws (no effect).
inline constexpr unsigned kNoiseOnlySeedBase = 1'000'000;
/// Seeds from here draw an effect with memory (issue 47, item 5): hysteresis over a drawn stroke (1–6 % of the travel),
/// a load behind a play (0.5–3 % of the travel) or a vibration whose frequency drifts (by a factor 1.5–3 over the
/// record, up or down), with their own physics.
inline constexpr unsigned kMemorySeedBase = 2'000'000;

/// The multiplier ids (what the effect's force is proportional to) and the modulator ids (what it varies with), as
/// the diagnosis names its factors (models/diagnosis/effect_registry.h, EffectType::multiplier and ::modulator).
const std::vector<std::string>& MultiplierIds();
const std::vector<std::string>& ModulatorIds();

/// Whether multiplier × modulator is drawn: every pair but constant × {one, slip, velocity, acceleration,
/// model_force}, which the base model holds.
bool IsDrawnPair(const std::string& multiplier, const std::string& modulator);

enum class Trajectory { kPointToPoint, kSweep };

/// The machine: a rigid body with viscous and tanh-regularised Coulomb friction and an offset. Linear: kg, N·s/m, N,
/// m/s, N; rotary: kg·m², N·m·s/rad, N·m, rad/s, N·m.
struct Plant {
  double mass = 0.0, viscous = 0.0, coulomb = 0.0, coulomb_velocity = 0.0, offset = 0.0;
};

/// A log column of the draw's own (what it logs and, for the active one, what the effect follows).
struct Column {
  enum class Kind { kTemperature, kOtherAxisVelocity, kOtherAxisAcceleration, kBusVoltage };
  Kind kind = Kind::kTemperature;
  std::string name;  ///< the CSV header ("winding_temperature_C", "vel_y_m_s", …)
  // kTemperature: θ = ambient + rise·(first-order lag, time constant lag [s], of a duty cycle switching between
  // duty_low and 1 after dwells of dwell_min..dwell_max [s]; the pattern is drawn per record).
  double ambient = 0.0, rise = 0.0, lag = 0.0, duty_low = 0.0, dwell_min = 0.0, dwell_max = 0.0;
  // The other axis / the bus voltage: Σ amplitude_k·sin(2π·frequency_k·t + phase_k) (the axis' position [m], the
  // voltage's ripple [V] about offset).
  std::vector<double> amplitude, frequency, phase;
  double offset = 0.0;
  /// The column's nominal value, what a factor of it is measured from: the middle of a temperature's range, the bus
  /// voltage's offset, the other axis at rest (0). Fixed for the machine: a mass or a friction that follows a
  /// temperature does not know a record's mean (each record's own mean made the effect differ between the training and
  /// the validation record by more than physics would).
  double Reference() const {
    return kind == Kind::kTemperature ? ambient + 0.5 * rise : kind == Kind::kBusVoltage ? offset : 0.0;
  }
  /// How far the column strays from Reference at most, what a third factor of it is scaled by: half a temperature's
  /// rise, the sines' summed amplitudes (of the derivative logged). Fixed for the machine, as Reference is: scaled by
  /// each record's own range, a drag following a winding temperature was 5 % steeper on the validation record than on
  /// the training one (seed 4), and no model of the machine could reach the floor on both.
  double HalfRange() const {
    if (kind == Kind::kTemperature) return 0.5 * rise;
    const int order = kind == Kind::kOtherAxisVelocity ? 1 : kind == Kind::kOtherAxisAcceleration ? 2 : 0;
    double sum = 0.0;  // of |A_k|·(2πf_k)^order: the sines' derivative that the column logs
    for (std::size_t k = 0; k < amplitude.size(); ++k) {
      sum += std::abs(amplitude[k]) * std::pow(2.0 * std::numbers::pi * frequency[k], order);
    }
    return sum;
  }
};

/// The modulator's shape (only the fields of the drawn modulator are set).
struct Shape {
  // position_periodic: sin(2πx/P + φ) + h2·sin(4πx/P + φ2)
  double period = 0.0, phase = 0.0, second_harmonic = 0.0, second_phase = 0.0;
  // position_local: a Gaussian exp(−((x − c)/w)²) or a trapezoid (flat over |x − c| < w/2, to 0 at |x − c| = 3w/2);
  // half_width w is the half-width at half-height's order: the bump's half-width as drawn (2–10 % of the travel)
  double center = 0.0, half_width = 0.0;
  bool trapezoid = false;
  // position_smooth: kind 0 tanh((x − x_m)/s), 1 ((x − x_m)/s)², 2 exp((x − x_m)/s); x_m in the travel, s 20–60 % of it
  int smooth_kind = 0;
  double smooth_middle = 0.0, smooth_scale = 0.0;
  // time_step: change_time; time_window: on_time..off_time; time_warm_up: time_constant from t = 0 [s]
  double change_time = 0.0, on_time = 0.0, off_time = 0.0, time_constant = 0.0;
  // time_periodic: sin(2πft + φ); time_chirp: sin(2π(f₀t + ½ḟt²) + φ), f₀ = frequency_hz, ḟ = drift_rate [Hz/s]
  double frequency_hz = 0.0, drift_rate = 0.0;
  // hysteresis: a Dahl element, z' = (1 − z·sign(ẋ))/λ per unit of stroke, λ = stroke/ln 10: after a reversal the
  // force makes 90 % of its swing over `stroke` [m or rad], whatever the speed (Dahl 1968; not the diagnosis' stop
  // operators)
  double stroke = 0.0;
  // play_load: a load behind a play of full width `gap` [m or rad], joined when engaged by a shaft of mode load_hz [Hz]
  // and damping ratio load_zeta, its bearing dragging load_damping [1/s] per unit of its mass (the amplitude is the
  // load's mass); the generator's own two-mass model with a dead zone (Nordin & Gutman 2002)
  double gap = 0.0, load_hz = 0.0, load_zeta = 0.0, load_damping = 0.0;
  // slip and load_slip multipliers: tanh(v/slip_velocity)
  double slip_velocity = 0.0;
};

/// One draw: the machine, the hidden effect and everything a record needs, from the seed alone.
struct GrammarDraw {
  unsigned seed = 0;
  bool noise_only = false;
  std::string multiplier, modulator;  ///< ids (MultiplierIds, ModulatorIds); "" for a noise-only draw
  /// A draw with memory (seeds from kMemorySeedBase): hysteresis ("one" × "hysteresis") or a load behind a play
  /// ("one" × "play_load"), each judged by the effect's name `effect`, or a vibration of drifting frequency (a
  /// multiplier × "time_chirp", a pair of the grammar).
  bool memory = false;
  std::string effect;
  Shape shape;
  /// The key shape parameter as the diagnosis reports it ("period", "center", "change_time", "on_time",
  /// "time_constant", "frequency_hz"; "" when the modulator has none: constant, position_smooth, time_ramp, column,
  /// column_rate), its truth [SI] and its tolerance (absolute, SI): period and frequency 3 % of the value, a centre
  /// 3 % of the travel, times 5 % of the record's duration, a time constant 20 %.
  std::string key_parameter;
  double key_value = 0.0, key_tolerance = 0.0;
  /// A second shape parameter judged with the key one (time_window: "off_time"), "" = none.
  std::string second_parameter;
  double second_value = 0.0;
  Column active_column;              ///< the column a column / column_rate modulator follows (name "" = none)
  /// The third factor: "" none, "time" (1 + β·(2t/T − 1)), "column" (1 + β·the third column scaled to ±1).
  std::string third_factor;
  double third_depth = 0.0;          ///< β
  Column third_column;               ///< name "" = none
  Column idle_column;                ///< logged, acts on nothing; name "" = none
  double amplitude = 0.0;            ///< the effect's coefficient A [force per unit of multiplier × modulator]
  double target_ratio = 0.0;         ///< drawn: the effect's RMS (less the base's share) over NoiseFloor
  double noise_floor = 0.0;          ///< NoiseFloor of the training record's effect-free twin [N or N·m]
  double noise_scale = 1.0;          ///< Calibrate's scale of the drawn force noise and encoder step (1: as drawn)

  bool rotary = false;
  Plant plant;
  double travel_low = 0.0, travel_high = 0.0;  ///< the reference's range [m or rad]
  double sample_rate = 0.0;                    ///< [Hz]
  double duration = 0.0;                       ///< [s]
  Trajectory trajectory = Trajectory::kPointToPoint;
  double top_speed = 0.0;                      ///< the moves' peak speed, or the sweep's mean one [m/s or rad/s]
  double dwell_min = 0.0, dwell_max = 0.0;     ///< point-to-point: rest between moves [s]
  double sweep_frequency = 0.0, sweep_deviation = 0.0, sweep_wander_period = 0.0;  ///< sweep: f̄ ± Δf over [s]
  bool integral_action = false;                ///< PID (else PD), both with feedforward
  double bandwidth_hz = 0.0;                   ///< the loop's: kp = M̂ω², kd = 2·0.7·M̂ω, ki = kp·ω/8
  double feedforward_error[3] = {1.0, 1.0, 1.0};  ///< the feedforward's mass, viscous and Coulomb over the truth's
  double encoder_step = 0.0;                   ///< [m or rad]
  double force_noise = 0.0;                    ///< standard deviation of the logged force's noise [N or N·m]

  double travel() const { return travel_high - travel_low; }
  std::string pair() const {
    return noise_only ? "nothing" : !effect.empty() ? effect : multiplier + "×" + modulator;
  }
  /// One line: seed, pair, key parameter, ratio, axis, rate, trajectory.
  std::string Describe() const;
};

/// The draw of `seed` (a noise-only draw from kNoiseOnlySeedBase on). Deterministic. Simulates the training record's
/// effect-free twin once to set the amplitude (4–30 × its NoiseFloor); a shape the record cannot show (its effect all
/// in the base's span) is drawn again, at most 8 times. Throws std::logic_error naming the draw when it still vanishes,
/// or when a draw with memory does.
GrammarDraw Draw(unsigned seed);

enum class Run { kTraining, kValidation };

/// A simulated record: the log as written, and the truth at the logged instants.
struct Record {
  bool rotary = false;
  Eigen::VectorXd time;      ///< [s], regular at the draw's sample rate
  Eigen::VectorXd position;  ///< [m or rad], on the encoder's grid
  Eigen::VectorXd force;     ///< the logged command with noise [N or N·m]
  std::vector<std::string> column_names;    ///< further logged columns (active, third, idle, as drawn)
  std::vector<Eigen::VectorXd> columns;
  // The truth at the logged instants (not written):
  Eigen::VectorXd command;        ///< the controller's command u (held until the next sample)
  Eigen::VectorXd true_position, velocity, acceleration;  ///< the body's state and its acceleration
  Eigen::VectorXd effect_force;   ///< the effect's force at those instants (0 in a twin)
  Eigen::VectorXd reference;      ///< the reference position
};

/// Simulates `run` of the draw; `with_effect` false: its effect-free twin (same trajectory, pattern and noise).
Record Simulate(const GrammarDraw& draw, Run run, bool with_effect = true);

/// The effect's force at the given instants and states (A·multiplier·modulator·third factor, with a mass along the
/// position's ½M′(x)·v²; the model_force multipliers read `command`): what the record's effect_force holds.
Eigen::VectorXd EffectForce(const GrammarDraw& draw, Run run, const Eigen::VectorXd& time,
                            const Eigen::VectorXd& position, const Eigen::VectorXd& velocity,
                            const Eigen::VectorXd& acceleration, const Eigen::VectorXd& command);

/// RMS of `force` less its least-squares projection on the base model's columns (a, v, tanh(v/v_c), 1) of `record`.
double RmsBeyondBase(const GrammarDraw& draw, const Record& record, const Eigen::VectorXd& force);

/// The base (effect-free) truth's force M·a + F_v·v + F_c·tanh(v/v_c) + offset on the given motion.
Eigen::VectorXd BaseForce(const Plant& plant, const Eigen::VectorXd& velocity, const Eigen::VectorXd& acceleration);

/// The generator's own estimate of the floor an equation-error comparison of `record` can reach, computed as such a
/// comparison sees the record (not with the project's code): the position low-passed by a zero-phase 2nd-order
/// Butterworth at min(100 Hz, 0.2 × the sample rate), differentiated twice by central differences; the logged force
/// averaged over each held sample ((u[k−1] + u[k])/2) and low-passed alike; the RMS of that force less BaseForce on the
/// derived motion, also low-passed, over the record less 2 % at either end.
double NoiseFloor(const GrammarDraw& draw, const Record& record);

/// Writes time_s, position_m / angle_rad, force_N / torque_Nm and the further columns (17 significant digits).
/// @throws std::runtime_error if it cannot write.
void WriteCsv(const Record& record, const std::string& path);

}  // namespace mb::grammar

// The catalogue of candidate missing physical effects (DIAGNOSIS.md step 3, SINDy's candidate library):
// each effect, given its parameters, turns the measured signals into regressor columns; a linear
// least-squares fit of the residual on those columns (jointly with the base model's regressors) says how
// much of the residual the effect explains. ProposeCandidateEffects finds the effects' nonlinear
// parameters (periods, frequencies, delay, ...) from the data: periodograms, spectrum, correlation.
//
// The effects themselves are registered one per file in models/diagnosis/effects/ (effect_registry.h: name,
// physics, regressors, proposal rule, traits, block); the functions below go through that registry.
// Units: SI (period [m], frequency_hz [Hz], delay [s], velocities [m/s], step [unit of the output]).
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>

#include "models/diagnosis/loop_response.h"
#include "models/diagnosis/periodogram.h"

namespace mb {

struct EffectInstance;

// The measured signals the diagnosis works on; all of length N (optional ones: length 0 = absent).
struct DiagnosisSignals {
  Eigen::VectorXd time;          // t [s], strictly increasing
  Eigen::VectorXd position;      // x [m]
  Eigen::VectorXd velocity;      // v [m/s]
  Eigen::VectorXd acceleration;  // a [m/s²]
  Eigen::VectorXd residual;      // r = measured − model output [unit of the output, e.g. N]
  Eigen::VectorXd model_output;  // ŷ (optional; needed by time_delay and quantization)
  Eigen::VectorXd input;         // u (optional; excitation of a resonance, input–residual correlation)
  Eigen::VectorXd logged_command;  // equation-error mode: the measured output, the command the drive was given
                                   // (optional; needed by drive_saturation)
  // The model's drive force, which the force constant multiplies (the grammar's multiplier ŷ, factors.h). Simulation
  // mode: the force the simulated controller gives the plant, since the compared output is then the position.
  // Optional: absent, ŷ is model_output (equation-error mode, where the compared output is the force).
  Eigen::VectorXd drive_force;
  // Equation-error mode, while JointRefinement scans the shapes: per pair of ŷ by its effect name, the command the
  // model predicts with that effect in, ŷ (corrected by the base's refit) + its own fitted part [the output's unit]. A
  // force constant, its saturation and a friction of the transmitted force act on the force the drive gives: the
  // machine is K(t)·u = ŷ, the residual u − ŷ = −δ(t)·u is linear in u and not in ŷ, and beside ŷ a warm-up or a ramp
  // fitted to it comes out distorted by 1/(1 + δ). The measured command cannot stand in for u: it holds the residual
  // (u × 1 beside the base would explain all of it). Only the shape scans read it (the term stays ŷ times its shape, as
  // its block computes it). Absent for an effect: ŷ is drive_force or model_output.
  std::map<std::string, Eigen::VectorXd> command_with;
  // Simulation mode: the drive force's response to a load at the plant (the controller's reaction, per unit of load;
  // loop_response.h), through which a command-path effect's load is iterated (CommandPathLoad); optional.
  std::shared_ptr<const LoopResponse> drive_force_response;
  // Simulation mode: the compared output's change, N samples [its unit], when the effect's block goes into the diagram
  // as `improve` adds it, with the effect's parameters and its physical coefficient — the output-error model itself,
  // where a command-path effect's load through the linearised loop (CommandPathLoad) is a first-order approximation
  // (Ljung, System Identification, 2nd ed., §7.3). Used for command-path effects (EffectSimulatedInTheDiagram);
  // empty: not available (equation-error mode, another record). May throw what building or simulating the amended
  // diagram throws (std::invalid_argument, std::runtime_error); costs one simulation of the diagram per call.
  std::function<Eigen::VectorXd(const EffectInstance&)> simulate_effect;
  // The log's columns that the diagram does not read (another axis, a temperature, a bus voltage, a second sensor),
  // each of length N, with their names in extra_names (optional: both empty). The logged_column factor reads them by
  // index, so a record carried to another (PredictCorrection) must list the same columns in the same order.
  std::vector<std::string> extra_names;
  std::vector<Eigen::VectorXd> extra_columns;

  // Throws std::invalid_argument naming the signal when a length differs, N < 64, a value is NaN/Inf or
  // time does not increase.
  void Validate() const;
  Eigen::Index size() const { return time.size(); }
};

// One effect with its parameters: enough to rebuild its regressors on new data.
struct EffectInstance {
  std::string name;                          // a registered effect's stable name (effect_registry.h)
  std::map<std::string, double> parameters;  // SI
};

// Regressor columns of one effect.
struct EffectRegressors {
  Eigen::MatrixXd columns;                // N × k
  std::vector<std::string> column_names;  // k names, e.g. "position_periodic.cos1"
};

// The registered effects' names, in catalogue order (the order candidates are proposed in).
std::vector<std::string> EffectNames();

// One sentence on the physics of an effect and how to add it to a model (for reports).
// Throws std::invalid_argument for an unknown name ("did you mean", listing the known ones).
std::string EffectPhysics(std::string_view name);

// The regressors of an effect on the signals. Throws std::invalid_argument for an unknown name (listing
// the known ones), a missing or invalid parameter (naming it), or a needed optional signal that is absent.
EffectRegressors BuildEffectRegressors(const EffectInstance& effect, const DiagnosisSignals& signals);

struct CatalogueOptions {
  // Dead band of sign(v) as a fraction of max |v|.
  double dead_band_fraction = 0.01;
  // Harmonics of a periodic effect: 1 + the highest harmonic order flagged in the periodogram, at most this.
  int max_harmonics = 4;
  // Distinct position periods proposed (strongest non-harmonic periodogram peaks).
  int max_position_periods = 3;
  // Stribeck velocities tried, as fractions of max |v|; the one best correlated with the residual wins.
  std::vector<double> stribeck_fractions{0.02, 0.05, 0.1, 0.2, 0.4};
  // Resonance: Welch segment length, the damping ratio proposed when the peak is too close to 0 or Nyquist
  // for the search of ζ, and how far the spectral peak must stand above the median density of the bins
  // within ±50 % of its frequency (at least ±10 bins, its own main lobe left out) to be proposed; peaks
  // below 4 frequency resolutions are ignored (they are drift, not a mode).
  Eigen::Index welch_segment = 1024;
  double resonance_damping_ratio = 0.05;
  double resonance_prominence = 20.0;
  // Periodogram settings for the position- and time-domain searches. When position_periodogram's
  // max_period is automatic (<= 0), the search stops at travel/min_position_cycles: a "period" that fits
  // fewer cycles into the travel cannot be told from a smooth position dependence — unless its harmonics say
  // so: periods of min_position_cycles_with_harmonics to min_position_cycles cycles in the travel are searched in
  // a periodogram of their own and proposed when the main periodogram holds a peak at one of their harmonics P/k,
  // k = 2..8 (a 7-per-revolution cogging on one revolution: DIAGNOSIS.md, "Few cycles").
  PeriodogramOptions position_periodogram{};
  PeriodogramOptions time_periodogram{};
  double min_position_cycles = 8.0;
  double min_position_cycles_with_harmonics = 3.0;
  // Quantization when the measured output is not on exact levels: periodogram of the residual against ŷ
  // (max_period automatic: ŷ's range / min_quantization_levels); its strongest independent peak is proposed
  // when significant and explaining at least min_quantization_power of the residual variance.
  PeriodogramOptions output_periodogram{};
  double min_quantization_levels = 20.0;  // a step above 5 % of the output's range is no sensor resolution
  double min_quantization_power = 0.02;
  // A time delay shorter than this many sample periods is not proposed: the data do not resolve it.
  double min_delay_samples = 0.1;
  // A residual time period within 1 % of k × the motion's own repetition frequency (k = 1..this) is
  // "motion-locked": any effect of x, v or a repeats there too, so it is not proposed as time_periodic.
  int motion_harmonics = 8;
  /// Propose every pair of the grammar (models/diagnosis/factors.h); false: only the products the catalogue named
  /// before the grammar (friction_ripple, local_damping, column_damping, …; effects/factor_products.cc kAliases). Off
  /// by default until the shipped demo and its figures are measured again with every pair (MeasurementSettings::
  /// every_pair turns it on for compare and improve; bench_grammar does).
  bool every_pair = false;
  // The band the motion signals carry [Hz] (0 = up to Nyquist): with parallel filtering (DiagnosisOptions::
  // regressor_filter_hz, which sets it) nothing above the cut-off is a property of the motion — a resonance peak up
  // there is the controller's noise leaking through the filter's skirt, and is not proposed.
  double band_limit_hz = 0.0;
  // One revolution in the position's unit on a rotary axis (2π for rad, 1 for rev, 360 for deg), 0 on a linear one:
  // the period of a force of the angle such as gravity on an unbalanced arm (DiagnosisOptions::position_unit sets it).
  double revolution = 0.0;
  // Simulation mode (issue 46): the closed loop's response from a force at the plant's input to the compared output
  // (loop_response.h). When set, every candidate built from the motion is a force passed through it before it is
  // fitted (FilterCandidateColumns, JointFitResidual), so that its coefficient is a force; null in equation-error
  // mode, where the residual is itself a force.
  std::shared_ptr<const LoopResponse> loop;
};

// What the proposal found on the way (for reports): the periodograms searched.
struct CandidateSearch {
  std::vector<EffectInstance> candidates;
  Periodogram position_periodogram;
  Periodogram time_periodogram;
  double motion_frequency_hz = 0.0;  // strongest periodicity of the position in time
  std::vector<std::string> notes;    // e.g. why a time-periodic peak was not proposed
};

// Proposes every applicable effect with parameters estimated from the signals and `residual` (pass the
// residual after the base model's refit): every registered effect's proposal rule (EffectType::propose, described
// in its file in effects/) runs in catalogue order on one ProposalContext (effect_proposal.h) that holds the
// analyses they share — the position and time periodograms of the residual and the motion's own frequency.
// Effects whose signals are absent (those built from ŷ without it) or that have nothing to fit are left out.
// Throws std::invalid_argument as DiagnosisSignals::Validate, or when residual or base_columns has the
// wrong number of rows.
// base_columns: the base model's regressors (N × p, p may be 0), refit jointly when the delay is estimated.
CandidateSearch ProposeCandidateEffects(const DiagnosisSignals& signals,
                                        const Eigen::Ref<const Eigen::VectorXd>& residual,
                                        const Eigen::Ref<const Eigen::MatrixXd>& base_columns,
                                        const CatalogueOptions& options = {});

}  // namespace mb

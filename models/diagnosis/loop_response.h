#pragma once
// Simulation mode's candidates through the closed loop (issue 46, item 1). In simulation mode the residual is an
// output error (the measured position minus the closed-loop diagram's), while every candidate is a force at the
// plant's input: a missing force reaches the output only through the loop, y = G·d with G = P/(1 + P·C) for a plant P
// under a controller C. Each candidate column is therefore passed through the loop's impulse response from a force at
// the plant's input to the compared output before it is fitted — the first Gauss–Newton step of the prediction-error
// method's output-error model (Ljung, System Identification, 2nd ed., §4.2 and §7.3), with the loop linearised along
// the record (the response measured on the diagram itself: tools/workflow/loop_probe.h). The fitted coefficients
// are then in the force's own unit, and a force the loop rejects (above its bandwidth) is weighed as little as the
// position shows it.

#include <atomic>
#include <complex>
#include <functional>
#include <memory>
#include <vector>

#include <Eigen/Core>

namespace mb {

class LoopResponse {
 public:
  /// `impulse_response`: h[k], k = 0..L−1, the compared output's change at sample n + k per unit of load force at
  /// sample n alone [output unit per force unit], at the record's sample period — a load: a force the drive must
  /// supply beyond the model's, the sign a missing effect's force has in equation-error mode (measured force minus
  /// the model's), so that coefficients keep their sign across the two modes; `samples`: the record's length N
  /// (the columns filtered later). @throws std::invalid_argument when h is empty, not finite or all zero, or N < 1.
  LoopResponse(Eigen::VectorXd impulse_response, Eigen::Index samples);

  /// Each column of `columns` (N × k) filtered causally by h: out[n] = Σ_{k ≤ n} h[k]·in[n − k] (zero before the
  /// record), by FFT (Eigen's kissfft) over a power-of-two length ≥ N + L − 1. @throws std::invalid_argument when
  /// the columns do not have N rows.
  Eigen::MatrixXd Apply(const Eigen::Ref<const Eigen::MatrixXd>& columns) const;

  /// The compared output's exact response to loads: each column of an N × k matrix of load forces simulated through
  /// the full, nonlinear diagram along the record (its tangent, by a small perturbation), N × k [output unit per
  /// force unit] — the output-error model's sensitivity itself (Ljung, §7.3), where Apply is its convolution with
  /// the loop linearised at one stretch. A column the diagram gives no tangent for (it switches within the push: a
  /// stick–slip law), or whose pushed run fails to simulate, is NaN (LoadSimulator, tools/workflow/loop_probe.cc).
  /// Costs a few simulations per column; may throw what building the simulation throws.
  using Simulator = std::function<Eigen::MatrixXd(const Eigen::MatrixXd& loads)>;
  /// Attaches the simulator (the caller that holds the diagram: tools/workflow/loop_probe.h). Throws nothing.
  void set_simulator(Simulator simulator) { simulator_ = std::move(simulator); }
  bool can_simulate() const { return static_cast<bool>(simulator_); }
  /// `columns` through the attached simulator; a column it gives no tangent for (NaN), and every column without a
  /// simulator, through Apply. @throws std::invalid_argument when the columns do not have N rows, and what the
  /// simulation throws.
  Eigen::MatrixXd Simulate(const Eigen::Ref<const Eigen::MatrixXd>& columns) const;
  /// How many columns Simulate has given so far, and how many of them through Apply because the diagram gave no
  /// tangent (shared by the copies of this loop; thread-safe). For the notes.
  struct SimulatedCount {
    Eigen::Index columns = 0, linearised = 0;
  };
  SimulatedCount simulated_count() const {
    return {simulated_->columns.load(), simulated_->linearised.load()};
  }

  const Eigen::VectorXd& impulse_response() const { return h_; }
  /// |H(f)|: the loop's gain from a sinusoidal load at `frequency_hz` to the output, the DTFT of h at the record's
  /// `sample_period` [s] (output unit per force unit). Throws nothing.
  double GainAt(double frequency_hz, double sample_period) const;
  /// The force an output record is: `output` (N) deconvolved by h with Wiener's regularisation, F = R·H*/(|H|² + λ),
  /// λ = `regularisation` × max |H|² (Wiener 1949; Hansen, "Deblurring Images", 2006, ch. 5): where the loop passes
  /// little, the force is damped rather than the noise blown up. For the spectra the proposals read in simulation
  /// mode; fits stay on the output. @throws std::invalid_argument when output does not have N samples.
  Eigen::VectorXd ForceOf(const Eigen::Ref<const Eigen::VectorXd>& output, double regularisation) const;
  /// Σ h[k]: the loop's static gain from a constant load to the output [output unit per force unit] (−1/K for a PD
  /// of stiffness K, 0 with integral action).
  double static_gain() const { return h_.sum(); }

 private:
  Eigen::VectorXd h_;
  Eigen::Index samples_ = 0;
  Eigen::Index padded_ = 0;
  std::vector<std::complex<double>> h_spectrum_;  // FFT of h zero-padded to padded_
  Simulator simulator_;
  struct Counters {
    std::atomic<Eigen::Index> columns{0}, linearised{0};
  };
  std::shared_ptr<Counters> simulated_ = std::make_shared<Counters>();
};

}  // namespace mb

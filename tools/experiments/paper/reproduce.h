#pragma once
// `motionblocks reproduce`: the seed paper's experiments (reference/paper-tisogpr-dob.txt, sections 3.2, 4.2, 5)
// rebuilt from the shipped diagrams and sweeps in diagrams/paper/ on the linear-motor twin:
//   1. training scans: the list sweep sweeps/training_scans.json over training_scan.json (one constant-velocity
//      stroke per velocity over the 700 mm travel), run in parallel (tools/batch/sweep.h);
//   2. windows D(1), D(2), D(3) of L = 125, 225, 325 mm around each scan's centre (eq. 25–26), constant-velocity
//      samples only; inputs x and the scan's constant velocity v_i ("the position samples inside W_k(i) and the
//      constant velocity are paired to form the training data", section 3.2), target the DOB estimate d̂_d;
//   3. DS (eq. 27) and PS (eq. 19) fitted by MAP on each window with every sample, and, for the record, on a
//      paper-size downsample (N ≈ 1590, 2096, 2460);
//   4. Table 1: each model's RMSE against the twin's true disturbance (and against the DOB estimate) along the
//      Fig. 9 run of the conventional loop (its full operating range, 0 … 600 mm, mostly outside the windows);
//   5. Table 2: tracking RMSE on Fig. 9 for conventional.json and gp_loop.json with the DS and PS models of D(2),
//      controller fixed;
//   6. section 5.3: the same three with a payload equal to the moving mass (doubles it), models not retrained;
//   7. stability (models/stability/stability.h) for the α of gp_loop.json with each model; the GPR's cost per
//      control step (posterior mean, as the gpr block evaluates it);
//   8. an ablation a real stage cannot run: PS of D(2) trained on the true disturbance instead of the DOB estimate
//      (how much of the gap to the paper the DOB's lag explains).
// Writes <out>/results.json, <out>/report.html with the paper's numbers beside ours and the figures (gnuplot),
// the fitted models (<out>/models/{ds,ps}_d{1,2,3}.json) and the scan sweep (<out>/scans/runs.csv).

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include <Eigen/Core>
#include <nlohmann/json.hpp>

#include "engine/simulator.h"

namespace mb {

struct ReproduceOptions {
  std::filesystem::path diagrams = "diagrams/paper";  ///< folder with the paper's diagrams and sweeps/
  std::filesystem::path out = "out/reproduce";
  /// Quick: every other scan velocity (5 of 10), one MAP start per fit, a shorter timing loop (under a minute
  /// on 2 cores). Full: all ten velocities, 3 MAP starts (prior median + 2 draws).
  bool quick = false;
  int jobs = 0;           ///< parallel simulations and fits; 0 = all hardware threads
  bool progress = true;   ///< progress lines on stderr
  /// The ODrive records of the "real motor" step, a folder laid out as the shipped diagrams/odrive/data
  /// (slow2_nocomp_{0,1,2}.csv, slow2_slower_nocomp_0.csv, coggingmap_0_a_16.csv); empty: that folder, found from
  /// `diagrams` (diagrams/paper → ../odrive/data), skipped (the step says so) when absent. A folder named here must
  /// hold the five records, each valid and at least 100 rows long: Reproduce refuses it before its first step
  /// otherwise (std::invalid_argument naming the file and the reason).
  std::filesystem::path odrive_data;
  /// Step messages ("[3/8] fitting …"); the command prints them on stdout. May be empty.
  std::function<void(const std::string&)> message;
};

/// Training data of one window (eq. 25–26): inputs x [m] and the constant scan velocity v_i [m/s], target d̂_d [N].
struct GprTrainingSet {
  Eigen::VectorXd x;
  Eigen::VectorXd xdot;
  Eigen::VectorXd d;
};

/// The samples of the scans' constant-velocity sections (logged flag `reference.constant_velocity` = 1) whose
/// position lies in [x_c − L/2, x_c + L/2], x_c = the midpoint of that scan's constant-velocity positions
/// (eq. 25), every `downsample`-th kept. The velocity input is the commanded constant velocity
/// (reference.velocity), as in the paper: the estimated velocity F_ẋ{x} carries the ripple the disturbance itself
/// causes, and an SE kernel on it then fits that ripple (ℓ_ẋ at its lower bound, a velocity part of several N
/// between the scan velocities). Each log needs the columns plant.x, reference.velocity, dob.d_hat and
/// reference.constant_velocity. @throws std::invalid_argument for a missing column (SignalLog::Column),
/// window_length ≤ 0, downsample < 1, or a scan without a constant-velocity section.
/// `target` names the regression target's column: the DOB estimate (the paper's, default) or, for an ablation only
/// a simulation allows, the true disturbance "plant.disturbance".
GprTrainingSet SelectTrainingWindow(const std::vector<SignalLog>& scans, double window_length, int downsample = 1,
                                    const std::string& target = "dob.d_hat");

/// Root mean square of a − b. @throws std::invalid_argument for different or zero lengths.
double RootMeanSquareDifference(const std::vector<double>& a, const std::vector<double>& b);

/// Runs everything above and returns results.json's content: keys "table1" (model RMSE [N]), "table2" (tracking
/// RMSE [µm]), "payload" ([µm]), "stability", "timing", plus "paper" (the paper's numbers), "configuration" and
/// "findings" (where ours differ and why). @throws what the steps throw (DiagramError for a broken diagram,
/// std::runtime_error if a scan fails or an output cannot be written).
nlohmann::json Reproduce(const ReproduceOptions& options);

}  // namespace mb

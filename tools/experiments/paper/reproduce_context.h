#pragma once
// What the steps of `motionblocks reproduce` (reproduce.h) share: the options, the parallel arena, the paths of
// the paper's diagrams, and each step's results, which later steps read. One file per step (docs/architecture.md):
//   reproduce_scans.cc      1. training scans (the list sweep)
//   reproduce_windows.cc    2. windows D(1..3)
//   reproduce_fits.cc       3. MAP fits of DS and PS, and the ablation's fit on the true disturbance
//   reproduce_table1.cc     4. Table 1 along the Fig. 9 run
//   reproduce_table2.cc     5–6. Table 2 and the payload case, the payload study as sweeps
//   reproduce_stability.cc  7. stability; 8. the GPR's cost per control step
//   reproduce_confidence.cc 7. variance-aware compensation (the confidence weight of blocks/gpr.h)
//   reproduce_online.cc     7. learning online (the gpr block's learning "online"): the payload case, a payload picked up
//   reproduce_real_motor.cc 8. DS and PS on a real motor's cogging (the ODrive records)
//   reproduce_findings.cc   where ours differ from the paper, from the numbers
//   reproduce_report.cc     9. report.html: tables and figures
// reproduce.cc runs them in order.

#include <chrono>
#include <filesystem>
#include <map>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>
#include <tbb/task_arena.h>

#include "engine/diagram.h"
#include "engine/simulator.h"
#include "models/gpr/gpr_model.h"
#include "tools/experiments/paper/reproduce.h"
#include "tools/report/report.h"

namespace mb::paper {

// The paper's numbers (Table 1 [N], Table 2 [µm], section 3.2 dataset sizes).
inline const std::map<std::string, std::vector<double>> kPaperTable1 = {{"DS", {0.3789, 0.2840, 0.1550}},
                                                                        {"PS", {0.1516, 0.1506, 0.1493}}};
inline const std::map<std::string, double> kPaperTable2 = {{"conventional", 42.048}, {"DS", 29.228}, {"PS", 22.408}};
inline constexpr int kPaperDatasetSize[3] = {1590, 2096, 2460};
inline constexpr double kWindowLength[3] = {0.125, 0.225, 0.325};  // L_k of eq. 26 [m]
inline constexpr const char* kWindowName[3] = {"D1", "D2", "D3"};
inline constexpr const char* kKernelName[2] = {"DS", "PS"};
inline constexpr GprKernel kKernel[2] = {GprKernel::kSeSe, GprKernel::kPeriodicSe};
inline constexpr double kPayloadMass = 0.2621;  // = M: doubles the moving mass (docs/paper.md on the paper's 21 kg)
inline constexpr int kSteps = 9;
/// The scans' column of the smoothed (non-causal) disturbance estimate (models/gpr/disturbance_target.h) and its
/// zero-phase cut-off [Hz] (above the cogging's third harmonic at 500 mm/s, 67 Hz).
inline constexpr const char* kSmoothedTarget = "smoothed_disturbance";
inline constexpr double kSmoothedTargetCutoffHz = 200.0;                // the "[k/9]" step messages

using Assignments = std::vector<std::pair<std::string, nlohmann::json>>;

/// One MAP fit of step 3: kernel (0 DS, 1 PS) × window (0..2) × every sample or paper-size.
struct PaperFit {
  int kernel;
  int window;
  bool paper_size;
  std::unique_ptr<GprModel> model;
  double seconds = 0.0;
};

/// The closed-loop Fig. 9 runs of steps 5–6, in ReproduceContext::cases' order: conventional, DS, PS (D(2)); the
/// three with the payload; PS trained on the true disturbance (the ablation); PS trained on the smoothed estimate,
/// without and with the payload.
enum class PaperCase {
  kConventional,
  kDs,
  kPs,
  kConventionalPayload,
  kDsPayload,
  kPsPayload,
  kPsTrueDisturbance,
  kPsSmoothed,
  kPsSmoothedPayload,
};
inline constexpr std::size_t kPaperCaseCount = 9;

/// The runs of step 7, learning online, in ReproduceContext::online_cases' order: Table 2's Fig. 9 runs with the
/// gpr block learning online (from the PS model of D(2), with the payload, from the prior), with the adaptive mass
/// feedforward (the PS model, the PS model trained on the smoothed estimate, the mass alone; each without and with
/// the payload); then the endless-track runs, from kTrackConventional on (the conventional loop, the fixed PS model,
/// the learner from it and from the prior, the PS model with the mass, the smoothed PS model without and with it).
enum class OnlineCase {
  kPsOnline,
  kPsOnlinePayload,
  kPsOnlineFromPrior,
  kPsMass,
  kPsMassPayload,
  kPsSmoothedMass,
  kPsSmoothedMassPayload,
  kMassOnly,
  kMassOnlyPayload,
  kTrackConventional,  ///< the first track run
  kTrackPs,
  kTrackPsOnline,
  kTrackOnlineFromPrior,
  kTrackPsMass,
  kTrackPsSmoothed,
  kTrackPsSmoothedMass,
};
inline constexpr std::size_t kOnlineCaseCount = 16;

/// One closed-loop Fig. 9 run (PaperCase).
struct ClosedLoopCase {
  std::string name;
  std::filesystem::path diagram;
  Assignments assignments;
  SimulationResult result;
};

struct ReproduceContext {
  explicit ReproduceContext(const ReproduceOptions& o);

  const ReproduceOptions& options;
  const std::chrono::steady_clock::time_point start;
  const int jobs;              ///< parallel simulations and fits
  tbb::task_arena arena;       ///< of `jobs` threads
  const std::filesystem::path conventional, gp_loop, gp_loop_online, gp_loop_adaptive_mass, training_scan, scans_sweep;
  nlohmann::json results;      ///< results.json as the steps fill it

  // 1. training scans
  std::vector<SignalLog> scans;
  std::vector<double> scan_velocities;  ///< [m/s], one per scan
  // 2. windows: every sample, and the paper-size downsample
  GprTrainingSet full[3], paper_size[3];
  // 3. fits
  std::vector<PaperFit> fits;
  std::map<std::string, std::filesystem::path> model_paths;  ///< "DS_D2" → the saved model (absolute)
  std::unique_ptr<GprModel> ps_true_target;                   ///< the ablation: PS on D(2), target the true d
  std::filesystem::path ps_true_target_path;
  std::unique_ptr<GprModel> ps_smoothed_target;  ///< PS on D(2), target the smoothed estimate (measured signals only)
  std::filesystem::path ps_smoothed_target_path;
  // 4. Table 1
  SimulationResult conv;  ///< the Fig. 9 run of the conventional loop
  nlohmann::json table1;
  std::map<std::string, std::vector<double>> table1_ours;  ///< kernel → RMSE against the true d per window [N]
  double d_rms = 0.0;               ///< RMS of the true disturbance along Fig. 9 [N]
  double window_centre = 0.0;       ///< the D(2) window's centre [m]
  double fraction_inside_d2 = 0.0;  ///< share of the Fig. 9 run inside D(2)
  // 5–6. Table 2, the payload case and study
  std::vector<ClosedLoopCase> cases;  ///< kPaperCaseCount runs, in PaperCase's order
  nlohmann::json table2, payload_json;
  // 7–8. stability and timing
  nlohmann::json stability, timing;
  // 7. variance-aware compensation
  std::vector<ClosedLoopCase> confidence_cases;
  nlohmann::json confidence;
  // 7. learning online
  std::vector<ClosedLoopCase> online_cases;  ///< kOnlineCaseCount runs, in OnlineCase's order
  nlohmann::json online;
  // 8. real motor
  nlohmann::json real_motor;
  std::map<std::string, std::vector<double>> real_motor_curves;  ///< D(2) posterior means over the map's angles
  std::vector<std::string> findings;

  /// A step message (ReproduceOptions::message).
  void Say(const std::string& text) const;
  /// Seconds since the reproduction started.
  double Elapsed() const;
  /// The model of a fit of step 3. @throws std::logic_error if there is none.
  const GprModel& ModelOf(int kernel, int window, bool paper_sized) const;
  /// The run of a paper case (cases, in PaperCase's order). @throws std::logic_error before step 5 has run.
  const ClosedLoopCase& Case(PaperCase which) const;
  /// A paper case's tracking RMSE [µm].
  double RmseUm(PaperCase which) const;
  /// A run of step 7 (online_cases, in OnlineCase's order). @throws std::logic_error before step 7 has run.
  const ClosedLoopCase& Online(OnlineCase which) const;
  /// A run of step 7's tracking RMSE [µm].
  double OnlineRmseUm(OnlineCase which) const;
};

// The steps, in order (reproduce.cc).
void RunTrainingScans(ReproduceContext& c);
void SelectWindows(ReproduceContext& c);
void FitModels(ReproduceContext& c);
void ComputeTable1(ReproduceContext& c);
void RunClosedLoopCases(ReproduceContext& c);
void RunPayloadSweeps(ReproduceContext& c);
void AnalyseStabilityOfModels(ReproduceContext& c);
void CompareConfidenceWeighting(ReproduceContext& c);
void LearnOnline(ReproduceContext& c);
void TimePosteriorMean(ReproduceContext& c);
void RunRealMotor(ReproduceContext& c);
/// A folder the user named (ReproduceOptions::odrive_data) read now, before step 1: its five records must be there and
/// valid. @throws std::invalid_argument "--odrive-data DIR: <file>: <reason>" (issue 41: it was skipped, exit 0).
void CheckOdriveData(const ReproduceOptions& options);
void StateFindings(ReproduceContext& c);
void WriteReproduceReport(ReproduceContext& c);

// Helpers the steps share.
/// Runs `diagram` with sweep-style assignments ("block.param" → value) applied.
SimulationResult Simulate(const std::filesystem::path& diagram, const Assignments& assignments);
/// Builds `diagram` with the assignments applied.
Diagram BuildWith(const std::filesystem::path& diagram, const Assignments& assignments);
/// Posterior mean along a log's position and velocity columns.
std::vector<double> PredictAlong(const GprModel& model, const SignalLog& log, const std::string& position,
                                 const std::string& velocity);

}  // namespace mb::paper

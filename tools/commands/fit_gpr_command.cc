// motionblocks fit-gpr LOG.csv --disturbance-column COL [--position-column COL] [--velocity-column COL] [--kernel PS|DS]
//   [--period τ] [--solver weight_space|exact] [--window xmin,xmax] [--downsample N] -o MODEL.json
// motionblocks fit-gpr LOG.csv --target smoothed --force-column COL (--nominal-mass M_n --nominal-damping B_n |
//   --diagram LOOP.json) [--time-column COL] [--smoothing-cutoff-hz F] ... -o MODEL.json
// Fits the TISO-GPR disturbance model (paper §3, MAP) to a DOB log — or to the smoothed (zero-phase) inverse-model
// estimate computed from the log's time, position and force (models/gpr/disturbance_target.h) — and writes the model
// file that the `gpr` block loads (docs/gpr.md).

#include <algorithm>
#include <filesystem>
#include <optional>
#include <iostream>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "engine/table.h"
#include "models/gpr/gpr_io.h"
#include "models/gpr/gpr_log.h"
#include "tools/commands/cli_options.h"
#include "tools/commands/command_registry.h"
#include "tools/report/output_files.h"
#include "tools/workflow/gpr_training.h"

namespace mb {

namespace {

// The output's folder, created if missing (as `run --out` does).
void CreateParentDirectory(const std::string& path) {
  const std::filesystem::path parent = std::filesystem::path(path).parent_path();
  if (!parent.empty()) std::filesystem::create_directories(parent);
}

struct FitGprOptions {
  std::string log;
  GprTrainingSelection selection;
  std::vector<double> window;  // empty or {xmin, xmax} [m]
  std::string kernel = "PS";
  std::string solver = "weight_space";
  double period = 0.0225;
  bool estimate_period = false;
  int restarts = 2;
  std::uint64_t seed = 1;
  std::string output;
  std::string target = "dob";       // or "smoothed": the estimate of `smoothed`
  SmoothedTargetSettings smoothed;  // --time-column, --force-column, --diagram, --nominal-*, --smoothing-cutoff-hz
};

void RunFitGpr(const FitGprOptions& o) {
  RefuseOutputsOverInputs({{"LOG", o.log}, {"--diagram", o.smoothed.diagram}}, {{"-o", o.output}});
  GprTrainingSelection selection = o.selection;
  if (!o.window.empty()) selection.window = GprRange{o.window[0], o.window[1]};
  GprFitOptions fit;
  fit.kernel = ParseGprKernel(o.kernel);
  fit.solver = ParseGprSolver(o.solver);
  fit.period = o.period;
  fit.estimate_period = o.estimate_period;
  fit.restarts = o.restarts;
  fit.seed = o.seed;

  // The regression ignores time: no time column needed, rows in any order, scans concatenated, a pandas index.
  const Table log = ReadGprTrainingTable(o.log, &selection,
                                         o.target == "smoothed" ? std::optional(o.smoothed) : std::nullopt);
  CreateParentDirectory(o.output);  // before the fit, so that a bad path fails at once
  const GprModel model = FitGprToLog(log, selection, fit);
  SaveGprModel(model, o.output);

  const GprModelData& m = model.data();
  const GprHyperparameters& h = m.hyperparameters;
  std::cout << fmt::format(
      "fit {} ({} solver) to {} samples: {} features, log marginal likelihood {:.6g}, {:.2f} s\n"
      "  signal_variance_x {:.6g}, length_scale_x {:.6g}, signal_variance_xdot {:.6g}, "
      "length_scale_xdot {:.6g} m/s, noise_variance {:.6g}, period {:.6g} m, mean {:.6g}\n"
      "  trained ranges: x [{:.6g}, {:.6g}] m, xdot [{:.6g}, {:.6g}] m/s\n"
      "wrote {}\n",
      GprKernelName(m.kernel), m.provenance.solver, m.provenance.sample_count, model.feature_count(),
      m.provenance.log_marginal_likelihood, m.provenance.fit_seconds, h.signal_variance_x, h.length_scale_x,
      h.signal_variance_xdot, h.length_scale_xdot, h.noise_variance, h.period, m.mean, m.x_range.min,
      m.x_range.max, m.xdot_range.min, m.xdot_range.max, o.output);
}

void SetupFitGprCommand(CLI::App& app) {
  auto o = std::make_shared<FitGprOptions>();
  auto* cmd = app.add_subcommand("fit-gpr", "Fit the TISO-GPR disturbance model (MAP) to a DOB log; writes the "
                                            "model file the gpr block loads");
  cmd->add_option("log", o->log, "CSV training table (any column order; time not needed)")->required()->check(CLI::ExistingFile);
  cmd->add_option("--position-column", o->selection.position_column, "position column x [m]")->capture_default_str();
  cmd->add_option("--velocity-column", o->selection.velocity_column, "velocity column xdot [m/s]")
      ->capture_default_str();
  cmd->add_option("--disturbance-column", o->selection.disturbance_column,
                  "disturbance column d (the DOB estimate; required)");
  AddDeprecatedAlias(cmd, "--position", "--position-column", &o->selection.position_column);
  AddDeprecatedAlias(cmd, "--velocity", "--velocity-column", &o->selection.velocity_column);
  AddDeprecatedAlias(cmd, "--disturbance", "--disturbance-column", &o->selection.disturbance_column);
  cmd->add_option("--kernel", o->kernel, "PS (periodic + SE, eq. 19) or DS (SE + SE, eq. 27)")
      ->check(CLI::IsMember({"PS", "DS"}))
      ->capture_default_str();
  cmd->add_option("--period", o->period, "spatial period tau [m] of the periodic kernel (pole pitch)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_flag("--estimate-period", o->estimate_period, "let tau vary under its prior (PS only)");
  cmd->add_option("--solver", o->solver, "weight_space (every sample, O(N M^2)) or exact (Cholesky, N <= 10000)")
      ->check(CLI::IsMember({"weight_space", "exact"}))
      ->capture_default_str();
  cmd->add_option("--window", o->window, "train on xmin <= x <= xmax only: xmin,xmax [m]")
      ->delimiter(',')
      ->expected(2);
  cmd->add_option("--downsample", o->selection.downsample, "keep every N-th sample (after the window)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--restarts", o->restarts, "extra optimiser starts drawn from the priors")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_option("--seed", o->seed, "seed of the restart draws (a whole number below 10^18)")
      ->capture_default_str()
      ->check([](const std::string& text) {  // the raw text: an overflowing number was read as 2^64 − 1
        const bool digits = !text.empty() && text.size() <= 18 &&
                            std::all_of(text.begin(), text.end(), [](char c) { return c >= '0' && c <= '9'; });
        return digits ? std::string() : std::string("give a whole number from 0 to 999999999999999999");
      });
  cmd->add_option("--target", o->target,
                  "what the GP learns: dob (the --disturbance-column, e.g. the DOB estimate) or smoothed (the "
                  "zero-phase inverse-model estimate M_n*xddot + B_n*xdot - u from --time-column, --position-column "
                  "and --force-column: no Q-filter lag)")
      ->check(CLI::IsMember({"dob", "smoothed"}))
      ->capture_default_str();
  cmd->add_option("--time-column", o->smoothed.time_column, "time column [s] (--target smoothed; one scan after another)")
      ->capture_default_str();
  cmd->add_option("--force-column", o->smoothed.force_column, "force the plant received u [N] (--target smoothed)");
  cmd->add_option("--nominal-mass", o->smoothed.nominal_mass, "nominal mass M_n [kg] (--target smoothed)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--nominal-damping", o->smoothed.nominal_damping, "nominal damping B_n [N*s/m] (--target smoothed)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--diagram", o->smoothed.diagram, "read M_n, B_n from this loop's dob block (--target smoothed)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--smoothing-cutoff-hz", o->smoothed.cutoff_hz,
                  "zero-phase low-pass cut-off of --target smoothed [Hz] (above the disturbance's band)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("-o,--output", o->output, "model file to write (JSON)")->required();
  cmd->callback([o] { RunFitGpr(*o); });
}

}  // namespace

MB_REGISTER_COMMAND(fit_gpr, {"fit-gpr", CommandGroup::kLearnedCompensation, &SetupFitGprCommand, false})

}  // namespace mb

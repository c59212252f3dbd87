// motionblocks fit-gpr LOG.csv --disturbance-column COL [--position-column COL] [--velocity-column COL] [--kernel PS|DS]
//   [--period τ] [--solver weight_space|exact] [--window xmin,xmax] [--downsample N] -o MODEL.json
// motionblocks fit-gpr LOG.csv --target smoothed --force-column COL (--nominal-mass M_n --nominal-damping B_n |
//   --diagram LOOP.json) [--time-column COL] [--smoothing-cutoff-hz F] ... -o MODEL.json
// Fits the TISO-GPR disturbance model (paper §3, MAP) to a DOB log — or to the smoothed (zero-phase) inverse-model
// estimate computed from the log's time, position and force (models/gpr/disturbance_target.h) — and writes the model
// file that the `gpr` block loads (docs/gpr.md).

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

struct FitGprOptions {
  std::string log;
  GprTrainingSelection selection;
  std::vector<double> window;  // empty or {xmin, xmax} [m]
  std::string kernel = "PS";
  std::string solver = "weight_space";
  GprFitOptions fit;  // --period, --estimate-period, --restarts, --seed: their defaults are the library's
  std::string output;
  std::string target = "dob";       // or "smoothed": the estimate of `smoothed`
  SmoothedTargetSettings smoothed;  // --time-column, --force-column, --diagram, --nominal-*, --smoothing-cutoff-hz
};

void RunFitGpr(const FitGprOptions& o) {
  RefuseOutputsOverInputs({{"LOG", o.log}, {"--diagram", o.smoothed.diagram}}, {{"-o", o.output}});
  GprTrainingSelection selection = o.selection;
  if (!o.window.empty()) selection.window = GprRange{o.window[0], o.window[1]};
  GprFitOptions fit = o.fit;
  fit.kernel = ParseGprKernel(o.kernel);
  fit.solver = ParseGprSolver(o.solver);

  // The regression ignores time: no time column needed, rows in any order, scans concatenated, a pandas index.
  const Table log = ReadGprTrainingTable(o.log, &selection,
                                         o.target == "smoothed" ? std::optional(o.smoothed) : std::nullopt);
  CreateParentFolder(o.output);  // before the fit, so that a bad path fails at once
  const GprModel model = FitGprToLog(log, selection, fit);
  SaveGprModel(model, o.output);

  std::cout << DescribeGprFit(model) << fmt::format("wrote {}\n", o.output);
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
  cmd->add_option("--period", o->fit.period, "spatial period tau [m] of the periodic kernel (pole pitch)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_flag("--estimate-period", o->fit.estimate_period, "let tau vary under its prior (PS only)");
  cmd->add_option("--solver", o->solver, "weight_space (every sample, O(N M^2)) or exact (Cholesky, N <= 10000)")
      ->check(CLI::IsMember({"weight_space", "exact"}))
      ->capture_default_str();
  cmd->add_option("--window", o->window, "train on xmin <= x <= xmax only: xmin,xmax [m]")
      ->delimiter(',')
      ->expected(2);
  cmd->add_option("--downsample", o->selection.downsample, "keep every N-th sample (after the window)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("--restarts", o->fit.restarts, "extra optimiser starts drawn from the priors")
      ->check(CLI::NonNegativeNumber)
      ->capture_default_str();
  cmd->add_option("--seed", o->fit.seed, "seed of the restart draws (a whole number below 10^18)")
      ->capture_default_str()
      ->check(WholeNumberText(18));
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

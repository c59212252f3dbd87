// motionblocks fit-gpr LOG.csv --disturbance-column COL [--position-column COL] [--velocity-column COL] [--kernel PS|DS]
//   [--period τ] [--solver weight_space|exact] [--window xmin,xmax] [--downsample N] -o MODEL.json
// motionblocks fit-gpr LOG.csv --target smoothed --force-column COL (--nominal-mass M_n --nominal-damping B_n |
//   --diagram LOOP.json) [--time-column COL] [--smoothing-cutoff-hz F] ... -o MODEL.json
// Fits the TISO-GPR disturbance model (paper §3, MAP) to a DOB log — or to the smoothed (zero-phase) inverse-model
// estimate computed from the log's time, position and force (models/gpr/disturbance_target.h) — and writes the model
// file that the `gpr` block loads (docs/gpr.md).

#include <algorithm>
#include <filesystem>
#include <iostream>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "engine/diagram_loader.h"
#include "engine/table.h"
#include "models/gpr/disturbance_target.h"
#include "models/gpr/gpr_io.h"
#include "models/gpr/gpr_log.h"
#include "tools/commands/cli_options.h"
#include "tools/commands/command_registry.h"
#include "tools/report/output_files.h"
#include "tools/workflow/loop_from_diagram.h"

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
  // --target smoothed
  std::string target = "dob";
  std::string time_column = "time_s";
  std::string force_column;
  std::string diagram;  // the loop whose DOB gives M_n, B_n
  double nominal_mass = 0.0, nominal_damping = -1.0;
  double smoothing_cutoff_hz = SmoothedDisturbanceOptions{}.cutoff_hz;
};

constexpr const char* kSmoothedColumn = "smoothed_disturbance";

// The smoothed target's options: M_n, B_n given, or read from the DOB of --diagram.
SmoothedDisturbanceOptions SmoothedTargetOptions(const FitGprOptions& o) {
  SmoothedDisturbanceOptions so;
  so.cutoff_hz = o.smoothing_cutoff_hz;
  if (!o.diagram.empty()) {
    const PaperLoop loop = PaperLoopFromDiagram(LoadDiagram(o.diagram));
    if (!loop.has_dob) {
      throw std::invalid_argument(fmt::format("fit-gpr --diagram {}: the diagram has no dob block to read the nominal "
                                              "plant from: give --nominal-mass and --nominal-damping",
                                              o.diagram));
    }
    so.nominal_mass = loop.nominal_mass;
    so.nominal_damping = loop.nominal_damping;
  }
  if (o.nominal_mass > 0.0) so.nominal_mass = o.nominal_mass;
  if (o.nominal_damping >= 0.0) so.nominal_damping = o.nominal_damping;
  if (!(so.nominal_mass > 0.0) || o.force_column.empty()) {
    throw std::invalid_argument("fit-gpr --target smoothed: give --force-column COL (the force the plant received "
                                "[N]) and the nominal plant: --nominal-mass M_n [kg] and --nominal-damping B_n "
                                "[N*s/m], or --diagram LOOP.json (its dob block's)");
  }
  if (so.nominal_damping < 0.0) so.nominal_damping = 0.0;
  return so;
}

// Reads the log; with --target smoothed, appends the smoothed estimate and points the selection at it.
Table ReadTrainingTable(const FitGprOptions& o, GprTrainingSelection* selection) {
  if (o.target != "smoothed") {
    return ReadGprTable(o.log, {selection->position_column, selection->velocity_column,
                                selection->disturbance_column});
  }
  const SmoothedDisturbanceOptions so = SmoothedTargetOptions(o);
  Table log = ReadGprTable(o.log, {o.time_column, selection->position_column, selection->velocity_column,
                                   o.force_column});
  AddSmoothedDisturbanceColumn(log, o.time_column, selection->position_column, o.force_column, so, kSmoothedColumn);
  selection->disturbance_column = kSmoothedColumn;
  return log;
}

void RunFitGpr(const FitGprOptions& o) {
  RefuseOutputsOverInputs({{"LOG", o.log}, {"--diagram", o.diagram}}, {{"-o", o.output}});
  if (o.target == "smoothed" && !o.selection.disturbance_column.empty()) {
    throw std::invalid_argument("fit-gpr: --target smoothed computes the disturbance from time, position and force: "
                                "drop --disturbance-column (or use --target dob)");
  }
  if (o.target != "smoothed" && o.selection.disturbance_column.empty()) {
    throw std::invalid_argument("fit-gpr: name the disturbance column (the DOB estimate): --disturbance-column COL");
  }
  GprTrainingSelection selection = o.selection;
  if (!o.window.empty()) selection.window = GprRange{o.window[0], o.window[1]};
  GprFitOptions fit;
  fit.kernel = ParseGprKernel(o.kernel);
  fit.solver = ParseGprSolver(o.solver);
  fit.period = o.period;
  fit.estimate_period = o.estimate_period;
  fit.restarts = o.restarts;
  fit.seed = o.seed;

  CreateParentDirectory(o.output);  // before the fit, so that a bad path fails at once
  // The regression ignores time: no time column needed, rows in any order, scans concatenated, a pandas index.
  const Table log = ReadTrainingTable(o, &selection);
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
  cmd->add_option("--time-column", o->time_column, "time column [s] (--target smoothed; one scan after another)")
      ->capture_default_str();
  cmd->add_option("--force-column", o->force_column, "force the plant received u [N] (--target smoothed)");
  cmd->add_option("--nominal-mass", o->nominal_mass, "nominal mass M_n [kg] (--target smoothed)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--nominal-damping", o->nominal_damping, "nominal damping B_n [N*s/m] (--target smoothed)")
      ->check(CLI::NonNegativeNumber);
  cmd->add_option("--diagram", o->diagram, "read M_n, B_n from this loop's dob block (--target smoothed)")
      ->check(CLI::ExistingFile);
  cmd->add_option("--smoothing-cutoff-hz", o->smoothing_cutoff_hz,
                  "zero-phase low-pass cut-off of --target smoothed [Hz] (above the disturbance's band)")
      ->check(CLI::PositiveNumber)
      ->capture_default_str();
  cmd->add_option("-o,--output", o->output, "model file to write (JSON)")->required();
  cmd->callback([o] { RunFitGpr(*o); });
}

}  // namespace

MB_REGISTER_COMMAND(fit_gpr, {"fit-gpr", CommandGroup::kLearnedCompensation, &SetupFitGprCommand, false})

}  // namespace mb

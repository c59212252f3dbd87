// motionblocks predict-gpr MODEL.json IN.csv [--position-column COL] [--velocity-column COL] -o OUT.csv
// Evaluates a TISO-GPR model file along a log: OUT.csv = IN.csv's columns plus "mean" (posterior mean,
// eq. 22/24), "std" (latent posterior standard deviation, √eq. 23) and "extrapolated" (1 where the row's position
// or velocity lies outside the trained range or is not finite: the model has no data there; else 0).

#include <filesystem>
#include <iostream>

#include <fmt/format.h>

#include "engine/table.h"
#include "models/gpr/gpr_io.h"
#include "models/gpr/gpr_log.h"
#include "tools/commands/cli_options.h"
#include "tools/commands/command_registry.h"
#include "tools/report/output_files.h"

namespace mb {

namespace {

struct PredictGprOptions {
  std::string model;
  std::string input;
  std::string position;  // "": the model's own columns (GprInputColumns)
  std::string velocity;
  std::string output;
};

void RunPredictGpr(const PredictGprOptions& o) {
  RefuseOutputsOverInputs({{"MODEL", o.model}, {"INPUT", o.input}}, {{"-o", o.output}});
  const GprModel model = LoadGprModel(o.model);
  CreateParentFolder(o.output);
  const auto [position, velocity] = GprInputColumns(model, o.position, o.velocity);
  const Table in = ReadGprTable(o.input, {position, velocity});
  const Table out = PredictGprOnLog(model, in, position, velocity);
  WriteTable(out, o.output);

  const Eigen::VectorXd& extrapolated = out.column(kGprExtrapolatedColumn);
  const auto outside = (extrapolated.array() != 0.0).count();
  if (outside > 0) {
    const GprRange x = model.x_range(), xdot = model.xdot_range();
    std::cout << fmt::format("note: {} of {} rows lie outside the trained range ({} in [{:.6g}, {:.6g}] m, {} in "
                             "[{:.6g}, {:.6g}] m/s): their mean and std extrapolate (the velocity is clamped, the "
                             "position is not; docs/gpr.md); column {} is 1 there\n",
                             outside, in.rows(), position, x.min, x.max, velocity, xdot.min, xdot.max,
                             kGprExtrapolatedColumn);
  }
  std::cout << fmt::format("wrote {} ({} rows: {} columns of {} + mean, std, {})\n", o.output, out.rows(),
                           in.names().size(), o.input, kGprExtrapolatedColumn);
}

void SetupPredictGprCommand(CLI::App& app) {
  auto o = std::make_shared<PredictGprOptions>();
  auto* cmd = app.add_subcommand("predict-gpr", "Evaluate a GPR model file along a log: adds columns mean, std and extrapolated (1 where "
                                 "the position or velocity lies outside the trained range, else 0)");
  cmd->add_option("model", o->model, "model file written by fit-gpr")->required()->check(CLI::ExistingFile);
  cmd->add_option("input", o->input, "CSV table with position and velocity columns (time not needed)")
      ->required()
      ->check(CLI::ExistingFile);
  cmd->add_option("--position-column", o->position, "position column x [m] (default: the model's, else position_m)");
  cmd->add_option("--velocity-column", o->velocity,
                  "velocity column xdot [m/s] (default: the model's, else velocity_m_s)");
  AddDeprecatedAlias(cmd, "--position", "--position-column", &o->position);
  AddDeprecatedAlias(cmd, "--velocity", "--velocity-column", &o->velocity);
  cmd->add_option("-o,--output", o->output, "CSV file to write")->required();
  cmd->callback([o] { RunPredictGpr(*o); });
}

}  // namespace

MB_REGISTER_COMMAND(predict_gpr, {"predict-gpr", CommandGroup::kLearnedCompensation, &SetupPredictGprCommand, false})

}  // namespace mb

// motionblocks sweep [DIAGRAM] SWEEP.json [--jobs N] [--fresh] [--save-logs] [--shard K/N|auto[/N] | --mpi] --out DIR
// Without DIAGRAM, the sweep file's own "diagram" (relative to the sweep file) is run.
// Runs a diagram over a grid, list or seeded random sample of parameter values (tools/batch/sweep.h), in parallel;
// writes DIR/runs.csv and DIR/runs.json (one row of metrics per run). Resumable: runs already in DIR/runs.csv
// with status ok are not run again. --shard runs one share of the runs (tools/batch/shard.h; merged by sweep-merge),
// --mpi spreads them over the ranks of `mpirun` (tools/batch/sweep_mpi.h).

#include <iostream>

#include <fmt/format.h>

#include "tools/commands/commands.h"
#include "tools/batch/shard.h"
#include "tools/batch/sweep.h"
#include "tools/batch/sweep_mpi.h"

namespace mb {

namespace fs = std::filesystem;

namespace {

struct SweepCommandOptions {
  std::vector<std::string> files;  // [DIAGRAM] SWEEP
  std::string out;
  int jobs = 0;
  bool fresh = false;
  bool save_logs = false;
  std::size_t max_runs = kDefaultMaxSweepRuns;
  std::string shard;  // "" = the whole sweep
  bool mpi = false;
};

// The outcome on this process: the whole sweep, one shard, or (MPI) nothing on ranks > 0.
std::optional<SweepOutcome> RunSweepOn(const fs::path& diagram, const SweepSpec& spec, const SweepCommandOptions& o,
                                       const SweepOptions& options) {
  if (o.mpi) return RunSweepMpi(diagram, spec, o.out, options);
  if (!o.shard.empty()) return RunSweepShard(diagram, spec, ParseSweepShard(o.shard), o.out, options);
  return RunSweep(diagram, spec, o.out, options);
}

void RunSweepCommand(const SweepCommandOptions& o) {
  const std::string& sweep = o.files.back();
  const SweepSpec spec = ReadSweepFile(sweep, o.max_runs);
  const fs::path diagram = o.files.size() == 2 ? fs::path(o.files.front()) : SweepDiagramPath(spec, sweep);
  SweepOptions options;
  options.jobs = o.jobs;
  options.resume = !o.fresh;
  options.save_logs = o.save_logs;
  const std::optional<SweepOutcome> result = RunSweepOn(diagram, spec, o, options);
  if (!result) return;  // an MPI worker: rank 0 reports
  const SweepOutcome& outcome = *result;
  std::cout << fmt::format("{} runs ({}{}): {} run now, {} already done, {} failed\n", outcome.rows.size(), spec.kind,
                           o.shard.empty() ? "" : ", shard " + o.shard, outcome.ran, outcome.resumed, outcome.failed);
  for (const auto& row : outcome.rows) {
    if (row.status != "ok") std::cout << fmt::format("  run {} failed: {}\n", row.id, row.error);
  }
  std::cout << fmt::format("wrote {0}/runs.csv, {0}/runs.json{1}\n", o.out, o.save_logs ? ", runs/<id>/signals.csv" : "");
  if (outcome.failed > 0) {
    throw std::runtime_error(fmt::format("{} of {} runs failed", outcome.failed, outcome.rows.size()));
  }
}

}  // namespace

void SetupSweepCommand(CLI::App& app) {
  auto options = std::make_shared<SweepCommandOptions>();
  auto* cmd = app.add_subcommand(
      "sweep", "Run a diagram over a grid, list or seeded random sample of parameters in parallel: runs.csv, runs.json");
  cmd->add_option("files", options->files,
                  "[DIAGRAM] SWEEP: the diagram JSON file (default: the sweep file's \"diagram\", relative to the "
                  "sweep file) and the sweep JSON file (grid, list or random; see tools/batch/sweep.h)")
      ->required()
      ->expected(1, 2)
      ->type_name("[DIAGRAM] SWEEP")
      ->check(CLI::ExistingFile);
  cmd->add_option("--out", options->out, "output folder (runs.csv, runs.json)")->required();
  cmd->add_option("--jobs,-j", options->jobs, "parallel runs (default: all cores)")->check(CLI::NonNegativeNumber);
  cmd->add_flag("--fresh", options->fresh, "run everything again (default: skip runs already in runs.csv)");
  cmd->add_flag("--save-logs", options->save_logs, "also write DIR/runs/<id>/signals.csv for every run");
  cmd->add_option("--max-runs", options->max_runs, "refuse a sweep of more runs than N")
      ->capture_default_str()
      ->check(CLI::PositiveNumber);
  auto* shard = cmd->add_option("--shard", options->shard,
                                 "run only shard K of N (run i belongs to shard i mod N) into --out, for a cluster "
                                 "array job; auto or auto/N takes K from SLURM_ARRAY_TASK_ID, JOB_COMPLETION_INDEX or "
                                 "OMPI_COMM_WORLD_RANK; merge the folders with sweep-merge")
                        ->type_name("K/N|auto[/N]");
  cmd->add_flag("--mpi", options->mpi,
                "under mpirun: rank 0 hands out the runs and writes runs.csv, the other ranks simulate")
      ->excludes(shard);
  cmd->callback([options] { RunSweepCommand(*options); });
}

}  // namespace mb

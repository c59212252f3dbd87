// motionblocks sweep [DIAGRAM] SWEEP.json [--jobs N] [--fresh] [--save-logs]
//                    [--shard x/y|auto[/N] | --shard-index K/N | --mpi] --out DIR
// Without DIAGRAM, the sweep file's own "diagram" (relative to the sweep file) is run.
// Runs a diagram over a grid, list or seeded random sample of parameter values (tools/batch/sweep.h), in parallel;
// writes DIR/runs.csv and DIR/runs.json (one row of metrics per run) and DIR/report.html (tools/report/sweep_report.h).
// Resumable: runs already in DIR/runs.csv with status ok are not run again. --shard x/y (counted from 1) or
// --shard-index K/N (from 0) runs one share of the runs (tools/batch/shard.h; merged by sweep-merge),
// --mpi spreads them over the ranks of `mpirun` (tools/batch/sweep_mpi.h).

#include <iostream>

#include <fmt/format.h>

#include "tools/commands/cli_options.h"
#include "tools/commands/command_registry.h"
#include "tools/batch/shard.h"
#include "tools/batch/sweep.h"
#include "tools/batch/sweep_mpi.h"
#include "tools/report/output_files.h"

namespace mb {

namespace fs = std::filesystem;

namespace {

struct SweepCommandOptions {
  std::vector<std::string> files;  // [DIAGRAM] SWEEP
  std::string out;
  SweepOptions run;  // --jobs, --save-logs: their defaults are the library's
  bool fresh = false;
  std::size_t max_runs = kDefaultMaxSweepRuns;
  std::string shard;        // --shard x/y (from 1) or auto[/N]; "" = not given
  std::string shard_index;  // --shard-index K/N (from 0); "" = not given
  bool mpi = false;
};

// The outcome on this process: the whole sweep, one shard, or (MPI) nothing on ranks > 0.
std::optional<SweepOutcome> RunSweepOn(const fs::path& diagram, const SweepSpec& spec, const SweepCommandOptions& o,
                                       const std::optional<SweepShard>& shard, const SweepOptions& options) {
  if (o.mpi) return RunSweepMpi(diagram, spec, o.out, options);
  if (shard) return RunSweepShard(diagram, spec, *shard, o.out, options);
  return RunSweep(diagram, spec, o.out, options);
}

void RunSweepCommand(const SweepCommandOptions& o) {
  const std::string& sweep = o.files.back();
  const SweepSpec spec = ReadSweepFile(sweep, o.max_runs);
  NoteSweepMemory(spec);  // only with --max-runs raised: say what it will cost first
  const fs::path diagram = o.files.size() == 2 ? fs::path(o.files.front()) : SweepDiagramPath(spec, sweep);
  RefuseOutputsOverInputs({{"SWEEP", sweep}, {"DIAGRAM", diagram}}, {}, {{"--out", o.out, SweepOutputNames()}});
  SweepOptions options = o.run;
  options.resume = !o.fresh;
  const std::optional<SweepShard> shard = ParseSweepShardOptions(o.shard, o.shard_index);
  const std::optional<SweepOutcome> result = RunSweepOn(diagram, spec, o, shard, options);
  if (!result) return;  // an MPI worker: rank 0 reports
  PrintSweepSummary(*result, spec.kind, shard ? ShardLabel(*shard) : "", o.out, options.save_logs, std::cout);
  if (result->failed > 0) {
    throw std::runtime_error(fmt::format("{} of {} runs failed", result->failed, result->rows.size()));
  }
}

void SetupSweepCommand(CLI::App& app) {
  auto options = std::make_shared<SweepCommandOptions>();
  auto* cmd = app.add_subcommand(
      "sweep", "Run a diagram over a grid, list or seeded random sample of parameters in parallel: runs.csv, runs.json, "
      "report.html");
  cmd->add_option("files", options->files,
                  "[DIAGRAM] SWEEP: the diagram JSON file (default: the sweep file's \"diagram\", relative to the "
                  "sweep file) and the sweep JSON file (grid, list or random; see tools/batch/sweep_spec.h)")
      ->required()
      ->expected(1, 2)
      ->type_name("[DIAGRAM] SWEEP")
      ->check(CLI::ExistingFile);
  cmd->add_option("--out", options->out, "output folder (runs.csv, runs.json, report.html)")->required();
  cmd->add_option("--jobs,-j", options->run.jobs, "parallel runs (default: all cores)")->check(CLI::NonNegativeNumber);
  cmd->add_flag("--fresh", options->fresh, "run everything again (default: skip runs already in runs.csv)");
  cmd->add_flag("--save-logs", options->run.save_logs, "also write DIR/runs/<id>/signals.csv for every run");
  cmd->add_option("--max-runs", options->max_runs,
                  fmt::format("refuse a sweep of more runs than N (at most {}: every run's row is held in memory)",
                              kMaxSweepRunsCeiling))
      ->capture_default_str()
      ->check(CLI::Range(std::size_t{1}, kMaxSweepRunsCeiling));
  auto* shard = cmd->add_option("--shard", options->shard,
                                 "run only shard x of y, counted from 1 as Jest and Playwright do (1/2 and 2/2 are the "
                                 "halves; run i belongs to shard i mod y + 1), into --out, for a cluster array job; "
                                 "auto or auto/N takes the index (from 0) from SLURM_ARRAY_TASK_ID, "
                                 "JOB_COMPLETION_INDEX or OMPI_COMM_WORLD_RANK; merge the folders with sweep-merge")
                        ->type_name("x/y|auto[/N]")
                        ->check(NonEmpty("write x/y (shard x of y, from 1) or auto[/N]"));
  auto* shard_index = cmd->add_option("--shard-index", options->shard_index,
                                       "as --shard, counted from 0: shard index K of N, 0 <= K < N (0/2 and 1/2 are "
                                       "the halves)")
                              ->type_name("K/N")
                              ->check(NonEmpty("write K/N (shard index K of N, from 0)"))
                              ->excludes(shard);
  cmd->add_flag("--mpi", options->mpi,
                "under mpirun: rank 0 hands out the runs and writes runs.csv, the other ranks simulate")
      ->excludes(shard)
      ->excludes(shard_index);
  cmd->callback([options] { RunSweepCommand(*options); });
}

}  // namespace

MB_REGISTER_COMMAND(sweep, {"sweep", CommandGroup::kBatch, &SetupSweepCommand, true})

}  // namespace mb

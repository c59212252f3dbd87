// motionblocks sweep-merge DIR… --out DIR
// Merges the folders of `sweep … --shard K/N` (tools/batch/shard.h): checks that they come from the same sweep and
// diagram and that every run is there exactly once, then writes DIR/runs.csv (rows in run-id order: the runs.csv of
// the sweep run in one process), DIR/runs.json, DIR/report.html and DIR/runs/<id>/ of --save-logs.

#include <iostream>

#include <fmt/format.h>

#include "tools/batch/shard.h"
#include "tools/commands/command_registry.h"
#include "tools/report/sweep_report.h"
#include "tools/report/output_files.h"

namespace mb {

namespace {

struct SweepMergeCommandOptions {
  std::vector<std::string> shards;
  std::string out;
};

void RunSweepMergeCommand(const SweepMergeCommandOptions& o) {
  RequireReportFolderName("--out", o.out);  // its report.html (issue 41)
  std::vector<std::filesystem::path> shards(o.shards.begin(), o.shards.end());
  const SweepMergeOutcome outcome = MergeSweepShards(shards, o.out);
  std::cout << fmt::format("merged {} shard folders: {} runs, each once ({} failed)\n", shards.size(), outcome.runs,
                           outcome.failed);
  std::cout << fmt::format("wrote {0}/runs.csv, {0}/runs.json, {0}/{1}{2}\n", o.out, kSweepReportFile,
                           outcome.copied_run_folders > 0 ? ", runs/<id>/" : "");
  if (outcome.failed > 0) {
    throw std::runtime_error(fmt::format("{} of {} runs failed: run their shards again (failed runs are retried) and "
                                         "merge again",
                                         outcome.failed, outcome.runs));
  }
}

void SetupSweepMergeCommand(CLI::App& app) {
  auto options = std::make_shared<SweepMergeCommandOptions>();
  auto* cmd = app.add_subcommand(
      "sweep-merge", "Merge the folders of `sweep --shard K/N` into one runs.csv, checking every run is there once");
  cmd->add_option("shards", options->shards, "the --out folders of the shards (in any order)")
      ->required()
      ->type_name("DIR…")
      ->check(CLI::ExistingDirectory);
  cmd->add_option("--out", options->out, "output folder (runs.csv, runs.json, report.html, sweep-shard.json)")
      ->required();
  cmd->callback([options] { RunSweepMergeCommand(*options); });
}

}  // namespace

MB_REGISTER_COMMAND(sweep_merge, {"sweep-merge", CommandGroup::kBatch, &SetupSweepMergeCommand, false})

}  // namespace mb

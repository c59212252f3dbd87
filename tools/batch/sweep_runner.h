#pragma once
// The steps of one sweep (tools/batch/sweep.h), shared by the engines that run it: RunSweep's TBB threads on one
// machine and the MPI ranks of tools/batch/sweep_mpi.cc. Callers use RunSweep, RunSweepShard or RunSweepMpi.
//
//   SweepRunner runner(diagram, spec, out, options);   // reads the diagram, checks every assignment
//   for (std::size_t i : runner.Start()) runner.Record(i, runner.Execute(i));   // any order, any thread
//   SweepOutcome outcome = runner.Finish();             // runs.csv, runs.json in sweep order; report.html
//
// A process that only simulates (an MPI worker) calls Execute alone; Start, Record and Finish touch the output folder.

#include <cstddef>
#include <filesystem>
#include <memory>
#include <string>
#include <vector>

#include "tools/batch/sweep.h"

namespace mb {

class SweepRunner {
 public:
  /// Reads the diagram and checks every value the sweep assigns against it (nothing is written yet).
  /// @throws DiagramError as RunSweep.
  SweepRunner(const std::filesystem::path& diagram, const SweepSpec& spec, const std::filesystem::path& out,
              const SweepOptions& options);
  ~SweepRunner();
  SweepRunner(const SweepRunner&) = delete;
  SweepRunner& operator=(const SweepRunner&) = delete;

  /// Creates the output folder, reads the runs already done (options.resume) or removes runs.csv, opens runs.csv for
  /// appending (header if new) and returns the positions still to run, ascending.
  /// @throws std::runtime_error as RunSweep (runs.csv of another sweep, an unwritable folder).
  std::vector<std::size_t> Start();
  /// Runs the run at `position` (0 ≤ position < spec.run_count()): its row, "failed" with the message if it threw.
  /// Writes runs/<id>/signals.csv with options.save_logs and calls options.on_result. Thread-safe.
  SweepRow Execute(std::size_t position) const;
  /// Appends the row of the run at `position` to runs.csv and advances the progress line. Thread-safe.
  void Record(std::size_t position, SweepRow row);
  /// Rewrites runs.csv and runs.json in sweep order and writes report.html from them (options.report); the outcome
  /// with every row. Call once, after every Record. @throws std::runtime_error if a file cannot be written.
  SweepOutcome Finish();

  /// The diagram's metric names: the metric columns of runs.csv.
  const std::vector<std::string>& metric_names() const;

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace mb

// Sweeps (tools/batch): runs per second of the shipped Monte Carlo sweep diagrams/paper/sweeps/controller_random.json
// (16 perturbed controllers and payloads of the conventional loop, 3 s each) on 1 and 2 threads, and how the cost of
// one run grows with its stop time (0.5 to 8 s, one thread). MPI ranks are measured by scripts/bench_sweep_mpi.sh
// (the same sweep under mpirun). Numbers in docs/benchmarks.md ("Sweeps").

#include <filesystem>
#include <string>

#include <unistd.h>

#include <benchmark/benchmark.h>
#include <nlohmann/json.hpp>

#include "tools/batch/sweep.h"

namespace {

namespace fs = std::filesystem;

const fs::path kSweep = fs::path(MB_SOURCE_DIR) / "diagrams/paper/sweeps/controller_random.json";
// The sweep's "diagram" (../conventional.json) lies outside the sweep file's folder, which a sweep file may not read
// from: the diagram is given, as `motionblocks sweep DIAGRAM SWEEP` gives it.
const fs::path kDiagram = fs::path(MB_SOURCE_DIR) / "diagrams/paper/conventional.json";

fs::path OutFolder() { return fs::temp_directory_path() / ("mb_sweep_benchmark_" + std::to_string(::getpid())); }

void RunSweepBenchmark(benchmark::State& state, const mb::SweepSpec& spec, int jobs) {
  mb::SweepOptions options;
  options.jobs = jobs;
  options.resume = false;  // every iteration runs every run
  options.progress = false;
  options.report = false;  // the runs' throughput, not gnuplot's
  for (auto _ : state) {
    const mb::SweepOutcome outcome = mb::RunSweep(kDiagram, spec, OutFolder(), options);
    if (outcome.failed > 0) state.SkipWithError("a run failed");
  }
  const auto runs = static_cast<double>(spec.run_count());
  state.counters["runs_per_s"] =
      benchmark::Counter(runs * static_cast<double>(state.iterations()), benchmark::Counter::kIsRate);
  state.counters["s_per_run"] = benchmark::Counter(runs * static_cast<double>(state.iterations()),
                                                   benchmark::Counter::kIsRate | benchmark::Counter::kInvert);
  fs::remove_all(OutFolder());
}

// The 16 runs of controller_random.json on state.range(0) threads.
void BM_SweepRunsPerSecond(benchmark::State& state) {
  RunSweepBenchmark(state, mb::ReadSweepFile(kSweep), static_cast<int>(state.range(0)));
}

// The same 16 runs with stopTime = state.range(0) / 10 s, one thread: the cost per run against its length.
void BM_SweepCostPerRunByStopTime(benchmark::State& state) {
  mb::SweepSpec spec = mb::ReadSweepFile(kSweep);
  spec.fixed.emplace_back("defaultExperiment.stopTime", static_cast<double>(state.range(0)) / 10.0);
  state.counters["stop_time_s"] = static_cast<double>(state.range(0)) / 10.0;
  RunSweepBenchmark(state, spec, 1);
}

BENCHMARK(BM_SweepRunsPerSecond)->Arg(1)->Arg(2)->Unit(benchmark::kMillisecond)->UseRealTime();
BENCHMARK(BM_SweepCostPerRunByStopTime)->Arg(5)->Arg(10)->Arg(20)->Arg(40)->Arg(80)->Unit(benchmark::kMillisecond)
    ->UseRealTime();

}  // namespace

// One closed-loop run of diagrams/paper/conventional.json: 3 s, 3,000 control steps at 1 ms, continuous plant
// under RK4 sub-steps. Goal: under 5 ms per run (Release). Variants: the diagram's solver step, and the step
// 1e-4 s suggested for accuracy checks.

#include <filesystem>
#include <string>

#include <benchmark/benchmark.h>

#include "engine/diagram_loader.h"
#include "engine/simulator.h"

namespace {

const std::string kDiagram = std::string(MB_SOURCE_DIR) + "/diagrams/paper/conventional.json";

void RunConventional(benchmark::State& state, const char* solver_step) {
  nlohmann::json j = mb::ReadDiagramJson(kDiagram);
  if (solver_step) j["solver"]["step"] = std::stod(solver_step);
  const mb::Diagram diagram = mb::BuildDiagram(j, std::filesystem::path(kDiagram).parent_path(), kDiagram);
  mb::Simulator simulator(diagram);
  double rmse = 0.0;
  for (auto _ : state) {
    const mb::SimulationResult r = simulator.Run();
    rmse = r.metrics.at("tracking_rmse");
    benchmark::DoNotOptimize(rmse);
  }
  state.counters["tracking_rmse_um"] = rmse * 1e6;
  state.counters["control_steps"] = 3000;
}

void BM_ConventionalLoop(benchmark::State& state) { RunConventional(state, nullptr); }
void BM_ConventionalLoopRk4Step1e4(benchmark::State& state) { RunConventional(state, "1e-4"); }

BENCHMARK(BM_ConventionalLoop)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ConventionalLoopRk4Step1e4)->Unit(benchmark::kMillisecond);

}  // namespace

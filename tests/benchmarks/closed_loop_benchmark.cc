// One closed-loop run of diagrams/paper/conventional.json: 3 s, 3,000 control steps at 1 ms, continuous plant
// under RK4 sub-steps. Goal: under 5 ms per run (Release). Variants: the diagram's solver step, and the step
// 1e-4 s suggested for accuracy checks. BM_PlantPhysicsFloor: the floor under the first — the same plant's
// physics (blocks/linear_motor.h: cogging, Stribeck friction, damping, mass) under the same RK4 steps in a
// hand-written loop, fed the run's own control force (u_c.y, held over each 1 ms): no engine at all.

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>
#include <string>
#include <vector>

#include <benchmark/benchmark.h>

#include "blocks/linear_motor.h"
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

// The diagram's plant under classical RK4 (4 steps of 0.25 ms per control step, as the diagram's solver), its
// force held from the logged u_c.y. Counter: the largest difference from the engine's logged velocity, which
// shows that the loop integrates the same trajectory (equal to round-off).
void BM_PlantPhysicsFloor(benchmark::State& state) {
  const nlohmann::json j = mb::ReadDiagramJson(kDiagram);
  const mb::Diagram diagram = mb::BuildDiagram(j, std::filesystem::path(kDiagram).parent_path(), kDiagram);
  const mb::SimulationResult run = mb::Simulator(diagram).Run();
  const std::vector<double>& force = run.log.Column("u_c.y");
  const std::vector<double>& logged_velocity = run.log.Column("plant.velocity");
  const auto* plant = dynamic_cast<const mb::LinearMotor*>(diagram.blocks()[diagram.FindBlock("plant")].get());
  if (plant == nullptr) throw std::logic_error("conventional.json's 'plant' is not a linear_motor");
  const double inverse_mass = 1.0 / plant->moving_mass();
  const double damping = plant->damping();
  const auto acceleration = [&](double x, double v, double u) {
    return (u + plant->Disturbance(x, v) - damping * v) * inverse_mass;
  };
  constexpr int kSubsteps = 4;
  constexpr double h = 0.001 / kSubsteps;
  double largest_difference = 0.0;
  for (auto _ : state) {
    double x = 0.0, v = 0.0;
    largest_difference = 0.0;
    for (std::size_t k = 0; k + 1 < force.size(); ++k) {
      const double u = force[k];
      for (int s = 0; s < kSubsteps; ++s) {
        const double a1 = acceleration(x, v, u);
        const double x2 = x + 0.5 * h * v, v2 = v + 0.5 * h * a1;
        const double a2 = acceleration(x2, v2, u);
        const double x3 = x + 0.5 * h * v2, v3 = v + 0.5 * h * a2;
        const double a3 = acceleration(x3, v3, u);
        const double x4 = x + h * v3, v4 = v + h * a3;
        const double a4 = acceleration(x4, v4, u);
        x += h / 6.0 * (v + 2.0 * v2 + 2.0 * v3 + v4);
        v += h / 6.0 * (a1 + 2.0 * a2 + 2.0 * a3 + a4);
      }
      largest_difference = std::max(largest_difference, std::abs(v - logged_velocity[k + 1]));
    }
    benchmark::DoNotOptimize(x);
  }
  state.counters["derivative_evaluations"] = static_cast<double>(4 * kSubsteps * (force.size() - 1));
  state.counters["max_velocity_difference"] = largest_difference;
}

BENCHMARK(BM_ConventionalLoop)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_ConventionalLoopRk4Step1e4)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_PlantPhysicsFloor)->Unit(benchmark::kMillisecond);

}  // namespace

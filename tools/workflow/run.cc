#include "tools/workflow/run.h"

#include <chrono>

#include "tools/workflow/measurement.h"

namespace mb {

DiagramRun::DiagramRun(const Diagram& diagram, const RunSettings& settings)
    : diagram_(diagram), sim_(diagram), samples_in_memory_(settings.samples_in_memory) {
  FeedInputsFromFiles(diagram, settings.inputs, &sim_);
}

RunOutcome DiagramRun::Execute(LogSink* sink, const std::function<void(double)>& progress) {
  if (progress) {
    const double t0 = diagram_.experiment().start_time;
    sim_.SetProgressCallback([&progress, t0](double t, double t_stop) { progress((t - t0) / (t_stop - t0)); });
  }
  sim_.StreamLogTo(sink, samples_in_memory_);
  const auto start = std::chrono::steady_clock::now();
  sim_.Initialize();
  sim_.AdvanceTo(diagram_.experiment().stop_time);
  RunOutcome outcome;
  outcome.result.log = sim_.log();
  outcome.result.metrics = sim_.StreamedMetrics();
  outcome.result.solver_stats = sim_.solver_stats();
  outcome.result.solver_name = diagram_.solver().type;
  outcome.result.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  outcome.samples = sim_.logged_samples();
  sim_.SetProgressCallback({});  // `progress` may not outlive this call
  return outcome;
}

}  // namespace mb

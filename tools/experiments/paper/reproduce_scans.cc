// reproduce, step 1: the training scans (section 3.2), a list sweep run in parallel; logs kept in memory.

#include <fmt/format.h>

#include <stdexcept>

#include "tools/batch/sweep.h"
#include "tools/experiments/paper/reproduce_context.h"

namespace mb::paper {

namespace fs = std::filesystem;
using json = nlohmann::json;

void RunTrainingScans(ReproduceContext& c) {
  const ReproduceOptions& o = c.options;
  const int jobs = c.jobs;
  // 1. Training scans (section 3.2): the list sweep, in parallel; logs kept in memory.
  SweepSpec scan_spec = ReadSweepFile(c.scans_sweep);
  if (o.quick) {
    std::vector<std::size_t> every_other;
    for (std::size_t i = 0; i < scan_spec.run_count(); i += 2) every_other.push_back(i);
    scan_spec.KeepRuns(every_other);
  }
  c.Say(fmt::format("[1/{}] training scans: {} constant-velocity strokes over 700 mm ({})", kSteps,
                    scan_spec.run_count(), c.scans_sweep.string()));
  c.scans.assign(scan_spec.run_count(), SignalLog{});
  for (std::size_t i = 0; i < scan_spec.run_count(); ++i) {
    for (const auto& [k, v] : scan_spec.run(i).assignments) {
      if (k == "reference.velocities") c.scan_velocities.push_back(v.at(0).get<double>());
    }
  }
  {
    SweepOptions so;
    so.jobs = jobs;
    so.resume = false;
    so.progress = o.progress;
    so.report = false;  // the scans are drawn in reproduce's own report.html
    so.on_result = [&](std::size_t i, const SimulationResult& r) { c.scans[i] = r.log; };
    const SweepOutcome outcome = RunSweep(c.training_scan, scan_spec, o.out / "scans", so);
    for (const auto& row : outcome.rows) {
      if (row.status != "ok") throw std::runtime_error(fmt::format("training scan {} failed: {}", row.id, row.error));
    }
  }
  c.results["configuration"]["scan_velocities_m_s"] = c.scan_velocities;
}

}  // namespace mb::paper

#include "tools/experiments/paper/reproduce.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <thread>

#include <fmt/format.h>

#include "engine/diagram_loader.h"
#include "engine/file_access.h"
#include "tools/batch/sweep.h"
#include "tools/experiments/paper/reproduce_context.h"

namespace mb {

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace paper {

ReproduceContext::ReproduceContext(const ReproduceOptions& o)
    : options(o),
      start(std::chrono::steady_clock::now()),
      jobs(o.jobs > 0 ? o.jobs : std::max(1, static_cast<int>(std::thread::hardware_concurrency()))),
      arena(jobs),
      conventional(o.diagrams / "conventional.json"),
      gp_loop(o.diagrams / "gp_loop.json"),
      gp_loop_online(o.diagrams / "gp_loop_online.json"),
      gp_loop_adaptive_mass(o.diagrams / "gp_loop_adaptive_mass.json"),
      training_scan(o.diagrams / "training_scan.json"),
      scans_sweep(o.diagrams / "sweeps" / "training_scans.json") {}

void ReproduceContext::Say(const std::string& text) const {
  if (options.message) options.message(text);
}

double ReproduceContext::Elapsed() const {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
}

const GprModel& ReproduceContext::ModelOf(int kernel, int window, bool paper_sized) const {
  for (const auto& f : fits) {
    if (f.kernel == kernel && f.window == window && f.paper_size == paper_sized) return *f.model;
  }
  throw std::logic_error("missing fit");
}

const ClosedLoopCase& ReproduceContext::Case(PaperCase which) const {
  const auto i = static_cast<std::size_t>(which);
  if (cases.size() != kPaperCaseCount) throw std::logic_error("ReproduceContext::Case before the closed-loop runs");
  return cases[i];
}

double ReproduceContext::RmseUm(PaperCase which) const {
  return Case(which).result.metrics.at("tracking_rmse") * 1e6;
}

const ClosedLoopCase& ReproduceContext::Online(OnlineCase which) const {
  if (online_cases.size() != kOnlineCaseCount) {
    throw std::logic_error("ReproduceContext::Online before the online-learning runs");
  }
  return online_cases[static_cast<std::size_t>(which)];
}

double ReproduceContext::OnlineRmseUm(OnlineCase which) const {
  return Online(which).result.metrics.at("tracking_rmse") * 1e6;
}

SimulationResult Simulate(const fs::path& diagram, const Assignments& assignments) {
  const json j = ApplySweepAssignments(ReadDiagramJson(diagram), assignments, diagram.string());
  const Diagram d = BuildDiagram(j, diagram.parent_path(), diagram.string());
  Simulator simulator(d);
  return simulator.Run();
}

Diagram BuildWith(const fs::path& diagram, const Assignments& assignments) {
  const json j = ApplySweepAssignments(ReadDiagramJson(diagram), assignments, diagram.string());
  return BuildDiagram(j, diagram.parent_path(), diagram.string());
}

std::vector<double> PredictAlong(const GprModel& model, const SignalLog& log, const std::string& position,
                                 const std::string& velocity) {
  const auto& x = log.Column(position);
  const auto& v = log.Column(velocity);
  std::vector<double> mu(x.size());
  for (std::size_t i = 0; i < x.size(); ++i) mu[i] = model.PredictPosteriorMean(x[i], v[i]);
  return mu;
}

}  // namespace paper

GprTrainingSet SelectTrainingWindow(const std::vector<SignalLog>& scans, double window_length, int downsample,
                                    const std::string& target) {
  if (!(window_length > 0.0)) {
    throw std::invalid_argument(fmt::format("training window length must be positive, got {} m", window_length));
  }
  if (downsample < 1) throw std::invalid_argument(fmt::format("downsample must be ≥ 1, got {}", downsample));
  std::vector<double> xs, vs, ds;
  long long kept = 0;
  for (std::size_t s = 0; s < scans.size(); ++s) {
    const auto& x = scans[s].Column("plant.x");
    const auto& v = scans[s].Column("reference.velocity");
    const auto& d = scans[s].Column(target);
    const auto& flag = scans[s].Column("reference.constant_velocity");
    double lo = std::numeric_limits<double>::infinity();
    double hi = -lo;
    for (std::size_t i = 0; i < x.size(); ++i) {
      if (flag[i] > 0.5) {
        lo = std::min(lo, x[i]);
        hi = std::max(hi, x[i]);
      }
    }
    if (!(lo <= hi)) throw std::invalid_argument(fmt::format("scan {} has no constant-velocity section", s));
    const double centre = 0.5 * (lo + hi);  // x_c,i of eq. 25
    for (std::size_t i = 0; i < x.size(); ++i) {
      if (flag[i] > 0.5 && std::abs(x[i] - centre) <= 0.5 * window_length) {
        if (kept++ % downsample == 0) {
          xs.push_back(x[i]);
          vs.push_back(v[i]);
          ds.push_back(d[i]);
        }
      }
    }
  }
  GprTrainingSet set;
  set.x = Eigen::Map<const Eigen::VectorXd>(xs.data(), static_cast<Eigen::Index>(xs.size()));
  set.xdot = Eigen::Map<const Eigen::VectorXd>(vs.data(), static_cast<Eigen::Index>(vs.size()));
  set.d = Eigen::Map<const Eigen::VectorXd>(ds.data(), static_cast<Eigen::Index>(ds.size()));
  return set;
}

double RootMeanSquareDifference(const std::vector<double>& a, const std::vector<double>& b) {
  if (a.size() != b.size() || a.empty()) {
    throw std::invalid_argument(fmt::format("RMS difference of {} and {} samples", a.size(), b.size()));
  }
  double sum = 0.0;
  for (std::size_t i = 0; i < a.size(); ++i) sum += (a[i] - b[i]) * (a[i] - b[i]);
  return std::sqrt(sum / static_cast<double>(a.size()));
}

json Reproduce(const ReproduceOptions& o) {
  paper::CheckOdriveData(o);  // a folder named explicitly is read or refused before the long steps
  paper::ReproduceContext c(o);
  fs::create_directories(o.out / "models");
  AllowDiagramFilesUnder(o.out / "models");  // the paper's diagrams read the GP models this run writes there
  c.results["configuration"] = {{"quick", o.quick},
                                {"jobs", c.jobs},
                                {"diagrams", fs::absolute(o.diagrams).string()},
                                {"window_lengths_m",
                                 {paper::kWindowLength[0], paper::kWindowLength[1], paper::kWindowLength[2]}}};
  paper::RunTrainingScans(c);          // 1. (reproduce_scans.cc)
  paper::SelectWindows(c);             // 2. (reproduce_windows.cc)
  paper::FitModels(c);                 // 3. (reproduce_fits.cc)
  paper::ComputeTable1(c);             // 4. (reproduce_table1.cc)
  paper::RunClosedLoopCases(c);        // 5. (reproduce_table2.cc)
  paper::RunPayloadSweeps(c);          // 6.
  paper::AnalyseStabilityOfModels(c);  // 7. (reproduce_stability.cc)
  paper::CompareConfidenceWeighting(c);  // 7. (reproduce_confidence.cc)
  paper::LearnOnline(c);               // 7. (reproduce_online.cc)
  paper::TimePosteriorMean(c);         // 8.
  paper::RunRealMotor(c);              // 8. (reproduce_real_motor.cc)
  paper::StateFindings(c);             //    (reproduce_findings.cc)
  paper::WriteReproduceReport(c);      // 9. (reproduce_report.cc)
  return c.results;
}

}  // namespace mb

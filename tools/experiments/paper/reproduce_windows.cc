// reproduce, step 2: the training windows D(1..3) (eq. 25–26), every sample and a paper-size downsample.

#include <algorithm>
#include <cmath>

#include <fmt/format.h>

#include "models/gpr/disturbance_target.h"
#include "tools/experiments/paper/reproduce_context.h"
#include "tools/workflow/loop_from_diagram.h"

namespace mb::paper {

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

// Appends kSmoothedTarget to every scan: the smoothed inverse-model estimate (models/gpr/disturbance_target.h) from
// the measured position plant.x and the applied force u_c.y, with the nominal plant of the scan diagram's DOB.
void AddSmoothedTargets(ReproduceContext& c) {
  const PaperLoop loop = PaperLoopFromDiagram(BuildWith(c.training_scan, {}));
  SmoothedDisturbanceOptions so;
  so.nominal_mass = loop.nominal_mass;
  so.nominal_damping = loop.nominal_damping;
  so.cutoff_hz = kSmoothedTargetCutoffHz;
  for (SignalLog& scan : c.scans) {
    const auto map = [](const std::vector<double>& v) {
      return Eigen::Map<const Eigen::VectorXd>(v.data(), static_cast<Eigen::Index>(v.size()));
    };
    const Eigen::VectorXd d =
        SmoothedDisturbanceEstimate(map(scan.time), map(scan.Column("plant.x")), map(scan.Column("u_c.y")), so);
    scan.names.push_back(kSmoothedTarget);
    scan.columns.emplace_back(d.data(), d.data() + d.size());
  }
  c.results["configuration"]["smoothed_target"] = {{"nominal_mass_kg", so.nominal_mass},
                                                   {"nominal_damping_N_s_m", so.nominal_damping},
                                                   {"cutoff_hz", so.cutoff_hz}};
}

}  // namespace

void SelectWindows(ReproduceContext& c) {
  AddSmoothedTargets(c);
  // 2. Windows D(1..3) (eq. 25–26), every sample and a paper-size downsample.
  c.Say(
      fmt::format("[2/{}] training windows D(1), D(2), D(3): L = 125, 225, 325 mm around each scan's centre", kSteps));
  json datasets;
  for (int k = 0; k < 3; ++k) {
    c.full[k] = SelectTrainingWindow(c.scans, kWindowLength[k]);
    const int factor =
        std::max(1, static_cast<int>(std::lround(static_cast<double>(c.full[k].x.size()) / kPaperDatasetSize[k])));
    c.paper_size[k] = SelectTrainingWindow(c.scans, kWindowLength[k], factor);
    datasets[kWindowName[k]] = {{"window_m", kWindowLength[k]},
                                {"samples", c.full[k].x.size()},
                                {"paper_size_downsample", factor},
                                {"paper_size_samples", c.paper_size[k].x.size()},
                                {"paper_samples", kPaperDatasetSize[k]}};
  }
  c.results["configuration"]["datasets"] = datasets;
}

}  // namespace mb::paper

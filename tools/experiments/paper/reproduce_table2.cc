// reproduce, steps 5–6: Table 2 and the payload case (section 5.3) as closed-loop Fig. 9 runs, and the payload study
// as sweeps.

#include <fmt/format.h>
#include <tbb/parallel_for.h>

#include <stdexcept>

#include "tools/batch/sweep.h"
#include "tools/experiments/paper/reproduce_context.h"

namespace mb::paper {

namespace fs = std::filesystem;
using json = nlohmann::json;

void RunClosedLoopCases(ReproduceContext& c) {
  // 5–6. Table 2 and the payload case: the runs of PaperCase, in its order, in parallel.
  c.cases = {{"conventional", c.conventional, {}, {}},
             {"DS", c.gp_loop, {{"gpr.model", c.model_paths["DS_D2"].string()}}, {}},
             {"PS", c.gp_loop, {{"gpr.model", c.model_paths["PS_D2"].string()}}, {}},
             {"conventional_payload", c.conventional, {{"plant.payload_mass", kPayloadMass}}, {}},
             {"DS_payload",
              c.gp_loop,
              {{"gpr.model", c.model_paths["DS_D2"].string()}, {"plant.payload_mass", kPayloadMass}},
              {}},
             {"PS_payload",
              c.gp_loop,
              {{"gpr.model", c.model_paths["PS_D2"].string()}, {"plant.payload_mass", kPayloadMass}},
              {}},
             {"PS_true_disturbance", c.gp_loop, {{"gpr.model", c.ps_true_target_path.string()}}, {}},
             {"PS_smoothed", c.gp_loop, {{"gpr.model", c.ps_smoothed_target_path.string()}}, {}},
             {"PS_smoothed_payload",
              c.gp_loop,
              {{"gpr.model", c.ps_smoothed_target_path.string()}, {"plant.payload_mass", kPayloadMass}},
              {}}};
  c.Say(
      fmt::format("[5/{}] Table 2 and section 5.3: Fig. 9 runs, conventional / DS / PS (D(2)), without and with a "
                  "{} kg payload",
                  kSteps, kPayloadMass));
  c.arena.execute([&] {
    tbb::parallel_for(std::size_t{0}, c.cases.size(),
                      [&](std::size_t i) { c.cases[i].result = Simulate(c.cases[i].diagram, c.cases[i].assignments); });
  });
  const double conv = c.RmseUm(PaperCase::kConventional), ds = c.RmseUm(PaperCase::kDs), ps = c.RmseUm(PaperCase::kPs);
  c.table2 = {{"unit", "µm"},
              {"conventional", conv},
              {"DS", ds},
              {"PS", ps},
              {"max_abs_um",
               {{"conventional", c.Case(PaperCase::kConventional).result.metrics.at("tracking_max_abs") * 1e6},
                {"DS", c.Case(PaperCase::kDs).result.metrics.at("tracking_max_abs") * 1e6},
                {"PS", c.Case(PaperCase::kPs).result.metrics.at("tracking_max_abs") * 1e6}}},
              {"paper", kPaperTable2},
              {"order_ps_ds_conventional", ps < ds && ds < conv},
              {"ablation_ps_trained_on_true_disturbance", c.RmseUm(PaperCase::kPsTrueDisturbance)},
              {"ps_trained_on_smoothed_estimate", c.RmseUm(PaperCase::kPsSmoothed)},
              {"ps_smoothed_ratio_to_conventional", c.RmseUm(PaperCase::kPsSmoothed) / conv}};
  c.payload_json = {{"unit", "µm"},
                    {"payload_mass_kg", kPayloadMass},
                    {"moving_mass_kg", 0.2621},
                    {"conventional", c.RmseUm(PaperCase::kConventionalPayload)},
                    {"DS", c.RmseUm(PaperCase::kDsPayload)},
                    {"PS", c.RmseUm(PaperCase::kPsPayload)},
                    {"PS_smoothed", c.RmseUm(PaperCase::kPsSmoothedPayload)},
                    {"without_payload", {{"conventional", conv}, {"DS", ds}, {"PS", ps}}}};
}

void RunPayloadSweeps(ReproduceContext& c) {
  const ReproduceOptions& o = c.options;
  const int jobs = c.jobs;
  // The payload study as sweeps (diagrams/paper/sweeps): conventional.json and gp_loop.json with each D(2) model.
  c.Say(fmt::format("[6/{}] payload study: sweeps/payload_conventional.json and sweeps/payload_gp_loop.json (DS, PS)",
                    kSteps));
  {
    struct PayloadSweep {
      const char* name;
      fs::path diagram;
      fs::path sweep;
      std::string model;
    };
    const PayloadSweep sweeps[] = {
        {"conventional", c.conventional, o.diagrams / "sweeps" / "payload_conventional.json", ""},
        {"DS", c.gp_loop, o.diagrams / "sweeps" / "payload_gp_loop.json", c.model_paths["DS_D2"].string()},
        {"PS", c.gp_loop, o.diagrams / "sweeps" / "payload_gp_loop.json", c.model_paths["PS_D2"].string()}};
    json study;
    for (const PayloadSweep& ps : sweeps) {
      SweepSpec spec = ReadSweepFile(ps.sweep);
      if (!ps.model.empty()) spec.fixed.emplace_back("gpr.model", ps.model);
      SweepOptions so;
      so.jobs = jobs;
      so.resume = false;
      so.progress = o.progress;
      so.report = false;  // the payload study is drawn in reproduce's own report.html
      const SweepOutcome outcome = RunSweep(ps.diagram, spec, o.out / "payload_study" / ps.name, so);
      std::vector<double> mass, rmse;
      for (const SweepRow& row : outcome.rows) {
        if (row.status != "ok") {
          throw std::runtime_error(fmt::format("payload sweep {} run {} failed: {}", ps.name, row.id, row.error));
        }
        for (const auto& [k, v] : row.assignments) {
          if (k == "plant.payload_mass") mass.push_back(v.get<double>());
        }
        rmse.push_back(row.metrics.at("tracking_rmse") * 1e6);
      }
      study["payload_mass_kg"] = mass;
      study[ps.name] = rmse;
    }
    study["unit"] = "µm";
    c.payload_json["sweep"] = study;
  }
}

}  // namespace mb::paper

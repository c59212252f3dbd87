// reproduce, step 4: Table 1, each model's RMSE against the disturbance along the Fig. 9 run.

#include <fmt/format.h>

#include <cmath>

#include "tools/experiments/paper/reproduce_context.h"

namespace mb::paper {

namespace fs = std::filesystem;
using json = nlohmann::json;

void ComputeTable1(ReproduceContext& c) {
  // 4. Table 1 along the Fig. 9 run of the conventional loop.
  c.Say(fmt::format("[4/{}] Table 1: model RMSE against the disturbance along the Fig. 9 run (0 … 600 mm)", kSteps));
  c.conv = Simulate(c.conventional, {});
  const auto& d_true = c.conv.log.Column("plant.disturbance");
  const auto& d_dob = c.conv.log.Column("dob.d_hat");
  c.table1["unit"] = "N";
  c.table1["reference"] = "the twin's true disturbance plant.disturbance along the Fig. 9 run of conventional.json";
  for (int kernel = 0; kernel < 2; ++kernel) {
    std::vector<double> rmse, rmse_dob, rmse_paper_size;
    for (int k = 0; k < 3; ++k) {
      const auto mu = PredictAlong(c.ModelOf(kernel, k, false), c.conv.log, "plant.x", "plant.velocity");
      rmse.push_back(RootMeanSquareDifference(mu, d_true));
      rmse_dob.push_back(RootMeanSquareDifference(mu, d_dob));
      const auto mu_p = PredictAlong(c.ModelOf(kernel, k, true), c.conv.log, "plant.x", "plant.velocity");
      rmse_paper_size.push_back(RootMeanSquareDifference(mu_p, d_true));
    }
    c.table1_ours[kKernelName[kernel]] = rmse;
    c.table1[kKernelName[kernel]] = {{"D1", rmse[0]}, {"D2", rmse[1]}, {"D3", rmse[2]}};
    c.table1["against_dob_estimate"][kKernelName[kernel]] = {
        {"D1", rmse_dob[0]}, {"D2", rmse_dob[1]}, {"D3", rmse_dob[2]}};
    c.table1["paper_size_fits"][kKernelName[kernel]] = {
        {"D1", rmse_paper_size[0]}, {"D2", rmse_paper_size[1]}, {"D3", rmse_paper_size[2]}};
    c.table1["paper"][kKernelName[kernel]] = {{"D1", kPaperTable1.at(kKernelName[kernel])[0]},
                                              {"D2", kPaperTable1.at(kKernelName[kernel])[1]},
                                              {"D3", kPaperTable1.at(kKernelName[kernel])[2]}};
  }
  c.d_rms = RootMeanSquareDifference(d_true, std::vector<double>(d_true.size(), 0.0));
  c.table1["ablation_ps_d2_trained_on_true_disturbance"] =
      RootMeanSquareDifference(PredictAlong(*c.ps_true_target, c.conv.log, "plant.x", "plant.velocity"), d_true);
  // Where the Fig. 9 run lies relative to the D(2) window (its centre: the mean of the scans' centres).
  c.window_centre = c.full[1].x.size() > 0 ? 0.5 * (c.full[1].x.minCoeff() + c.full[1].x.maxCoeff()) : 0.0;
  {
    const auto& x = c.conv.log.Column("plant.x");
    long long inside = 0;
    for (double xi : x) inside += std::abs(xi - c.window_centre) <= 0.5 * kWindowLength[1] ? 1 : 0;
    c.fraction_inside_d2 = static_cast<double>(inside) / static_cast<double>(x.size());
  }
  c.table1["fig9_fraction_inside_D2"] = c.fraction_inside_d2;
  c.table1["disturbance_rms"] = c.d_rms;
  c.table1["dob_estimate_rmse"] = RootMeanSquareDifference(d_dob, d_true);
  const auto& ps1 = c.table1_ours["PS"];
  const auto& ds1 = c.table1_ours["DS"];
  c.table1["ps_change_d1_to_d3_percent"] = 100.0 * (ps1[2] - ps1[0]) / ps1[0];
  c.table1["ds_falls_with_window"] = ds1[0] > ds1[1] && ds1[1] > ds1[2];
}

}  // namespace mb::paper

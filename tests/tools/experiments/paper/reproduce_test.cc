// tools/experiments/paper/reproduce.h: the training-window selection of eq. 25–26 on synthetic scans, and `reproduce --quick` end to
// end on the shipped diagrams: results.json has the five sections with the orderings the paper reports.

#include "tools/experiments/paper/reproduce.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <map>
#include <numbers>
#include <sstream>

#include <unistd.h>

#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

namespace mb {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;

// A scan at constant velocity v from x0 to x0 + length (flag 1 throughout), 1 mm per sample, plus one
// transition sample (flag 0) at each end.
SignalLog SyntheticScan(double x0, double length, double v) {
  SignalLog log;
  log.names = {"plant.x", "reference.velocity", "dob.d_hat", "reference.constant_velocity"};
  log.columns.resize(4);
  const int n = static_cast<int>(std::lround(length / 1e-3));
  for (int i = -1; i <= n + 1; ++i) {
    const double x = x0 + 1e-3 * i;
    const bool constant = i >= 0 && i <= n;
    log.time.push_back(1e-3 * (i + 1));
    log.columns[0].push_back(x);
    log.columns[1].push_back(constant ? v : 0.5 * v);
    log.columns[2].push_back(std::sin(2.0 * std::numbers::pi * x / 0.0225));
    log.columns[3].push_back(constant ? 1.0 : 0.0);
  }
  return log;
}

TEST(SelectTrainingWindowTest, KeepsConstantVelocitySamplesAroundEachScansCentre) {
  // Scan 1 centred at 0 (−0.35 … 0.35), scan 2 centred at 0.1 (0 … 0.2).
  const std::vector<SignalLog> scans = {SyntheticScan(-0.35, 0.7, 0.1), SyntheticScan(0.0, 0.2, 0.3)};
  const GprTrainingSet set = SelectTrainingWindow(scans, 0.125);
  // |x − 0| ≤ 62.5 mm: 125 samples (−62 … 62 mm); |x − 0.1| ≤ 62.5 mm: 125 samples (38 … 162 mm).
  ASSERT_EQ(set.x.size(), 250);
  EXPECT_NEAR(set.x.head(125).minCoeff(), -0.062, 1e-9);
  EXPECT_NEAR(set.x.head(125).maxCoeff(), 0.062, 1e-9);
  EXPECT_NEAR(set.x.tail(125).minCoeff(), 0.038, 1e-9);
  EXPECT_NEAR(set.x.tail(125).maxCoeff(), 0.162, 1e-9);
  EXPECT_DOUBLE_EQ(set.xdot.head(125).maxCoeff(), 0.1);  // the constant scan velocity
  EXPECT_DOUBLE_EQ(set.xdot.tail(125).minCoeff(), 0.3);
  EXPECT_DOUBLE_EQ(set.d[0], std::sin(2.0 * std::numbers::pi * set.x[0] / 0.0225));
  EXPECT_EQ(SelectTrainingWindow(scans, 0.125, 10).x.size(), 25);
}

TEST(SelectTrainingWindowTest, Errors) {
  const std::vector<SignalLog> scans = {SyntheticScan(-0.35, 0.7, 0.1)};
  EXPECT_THROW(SelectTrainingWindow(scans, 0.0), std::invalid_argument);
  EXPECT_THROW(SelectTrainingWindow(scans, 0.1, 0), std::invalid_argument);
  SignalLog missing = scans[0];
  missing.names[2] = "other";
  EXPECT_THROW(SelectTrainingWindow({missing}, 0.1), std::invalid_argument);
  EXPECT_THROW(RootMeanSquareDifference({1.0}, {1.0, 2.0}), std::invalid_argument);
  EXPECT_DOUBLE_EQ(RootMeanSquareDifference({1.0, 3.0}, {0.0, 0.0}), std::sqrt(5.0));
}

TEST(ReproduceTest, QuickRunWritesResultsWithThePapersOrderings) {
  ReproduceOptions options;
  options.quick = true;
  options.progress = false;
  options.diagrams = fs::path(MB_SOURCE_DIR) / "diagrams" / "paper";
  options.out = fs::temp_directory_path() / ("mb_reproduce_test_" + std::to_string(::getpid()));
  fs::remove_all(options.out);
  const json returned = Reproduce(options);
  std::ifstream in(options.out / "results.json");
  ASSERT_TRUE(in.good());
  const json r = json::parse(in);
  EXPECT_EQ(r["table2"], returned["table2"]);
  for (const char* key : {"table1", "table2", "payload", "stability", "timing", "confidence_weighting",
                          "online_learning"}) EXPECT_TRUE(r.contains(key)) << key;

  // Table 2 [µm]: the calibrated conventional loop near the paper's 42.0 µm; PS < DS < conventional.
  const json& t2 = r["table2"];
  EXPECT_EQ(t2["unit"], "µm");
  const double conv = t2["conventional"], ds = t2["DS"], ps = t2["PS"];
  EXPECT_NEAR(conv, 42.0, 0.25 * 42.0);
  EXPECT_LT(ps, ds);
  EXPECT_LT(ds, conv);
  EXPECT_TRUE(t2["order_ps_ds_conventional"].get<bool>());

  // Table 1 [N]: PS changes by less than 15 % from D(1) to D(3), DS falls as the window grows, and PS beats DS
  // over the full range.
  const json& t1 = r["table1"];
  const double ps1 = t1["PS"]["D1"], ps3 = t1["PS"]["D3"];
  EXPECT_LT(std::abs(ps3 - ps1) / ps1, 0.15);
  EXPECT_GT(t1["DS"]["D1"].get<double>(), t1["DS"]["D2"].get<double>());
  EXPECT_GT(t1["DS"]["D2"].get<double>(), t1["DS"]["D3"].get<double>());
  for (const char* w : {"D1", "D2", "D3"}) EXPECT_LT(t1["PS"][w].get<double>(), t1["DS"][w].get<double>()) << w;

  // Payload (section 5.3): the mass mismatch costs tracking in every case; PS stays the best without retraining.
  const json& p = r["payload"];
  EXPECT_GT(p["conventional"].get<double>(), conv);
  EXPECT_LT(p["PS"].get<double>(), p["conventional"].get<double>());
  // The payload sweep (sweeps/payload_*.json): the conventional error grows with the mass, PS stays below it.
  const json& study = p["sweep"];
  const auto masses = study["payload_mass_kg"].get<std::vector<double>>();
  const auto conv_sweep = study["conventional"].get<std::vector<double>>();
  const auto ps_sweep = study["PS"].get<std::vector<double>>();
  ASSERT_GE(masses.size(), 3u);
  ASSERT_EQ(conv_sweep.size(), masses.size());
  ASSERT_EQ(ps_sweep.size(), masses.size());
  EXPECT_NEAR(conv_sweep[0], conv, 1e-9);  // payload 0 is the Table 2 run
  for (std::size_t i = 0; i < masses.size(); ++i) {
    if (i > 0) {
      EXPECT_GT(conv_sweep[i], conv_sweep[i - 1]) << masses[i];
    }
    EXPECT_LT(ps_sweep[i], conv_sweep[i]) << masses[i];
  }

  // Stability for the α used: certified with the DOB loop closed (ρ < 1, α below its bound).
  const json& s = r["stability"];
  EXPECT_DOUBLE_EQ(s["alpha"].get<double>(), 0.9);
  for (const char* k : {"DS", "PS"}) {
    EXPECT_LT(s[k]["dob"]["rho"].get<double>(), 1.0) << k;
    EXPECT_GT(s[k]["dob"]["alpha_max_bound"].get<double>(), 0.9) << k;
  }
  // Variance-aware compensation (issue 14): inside the trained ranges g is near 1, so the weighted runs stay within
  // 5 % of the unweighted; the highest α it runs at is still certified (ρ < 1 with the constants of g·d̂).
  const json& w = r["confidence_weighting"];
  for (const char* k : {"DS", "PS"}) {
    EXPECT_NEAR(w["tracking_rmse"][std::string(k) + "_weighted"].get<double>(), w["tracking_rmse"][k].get<double>(),
                0.05 * w["tracking_rmse"][k].get<double>())
        << k;
    EXPECT_LT(w["stability"][k]["rho"].get<double>(), 1.0) << k;
  }
  EXPECT_GE(w["high_alpha"].get<double>(), 0.9);
  EXPECT_LT(w["stability"]["PS_high_alpha"]["rho"].get<double>(), 1.0);
  // Real motor (issue 14): on the ODrive records the periodic kernel keeps the cogging beyond its half-revolution
  // window and DS does not — the paper's Table 1 claim on a machine the project did not model.
  // The records are shipped (diagrams/odrive/data): the step runs on every clone.
  const json& motor = r["real_motor"];
  ASSERT_FALSE(motor.contains("skipped")) << motor.dump();
  {
    std::map<std::string, json> d2;
    for (const json& row : motor["rows"]) {
      if (row["window"] == "D2") d2[row["kernel"].get<std::string>()] = row;
    }
    ASSERT_EQ(d2.size(), 3u);
    EXPECT_LT(d2["PS"]["rmse_rest_of_revolution_A"].get<double>(),
              0.7 * d2["DS"]["rmse_rest_of_revolution_A"].get<double>());
    EXPECT_GT(d2["PS"]["correlation_with_map"].get<double>(), 0.8);
    EXPECT_NEAR(d2["PS_estimated_period"]["period_rev"].get<double>(), 1.0 / 7.0, 0.02 / 7.0);
  }
  // Learning online (issue 14): from no data at all, one Fig. 9 run ends well below the conventional loop; from the
  // offline model it stays near that model (the payload's m_p·ẍ is not a function of (x, ẋ): no gain there).
  const json& online = r["online_learning"]["table2"];
  EXPECT_LT(online["PS_online_from_prior"].get<double>(), 0.85 * online["conventional"].get<double>());
  EXPECT_LT(online["PS_online"].get<double>(), 1.1 * online["PS"].get<double>());
  ASSERT_EQ(r["online_learning"]["track"]["segment_rmse_um"]["online_from_prior"].size(), 6u);
  // The GPR's posterior mean costs far less than the 1 ms control period.
  for (const char* k : {"DS", "PS"}) {
    const double ns = r["timing"][k]["posterior_mean_ns"];
    EXPECT_GT(ns, 0.0);
    EXPECT_LT(ns, 1e5) << k;
  }
  std::ifstream html(options.out / "report.html");
  std::stringstream text;
  text << html.rdbuf();
  EXPECT_NE(text.str().find("Table 2"), std::string::npos);
  EXPECT_NE(text.str().find("Where our figures differ"), std::string::npos);
  fs::remove_all(options.out);
}

}  // namespace
}  // namespace mb

// fit-gpr and predict-gpr on training tables as people have them (issue 11): no time column, rows in any order,
// scans that restart at t = 0, pandas' default to_csv (an unnamed index column), one scan velocity; predict-gpr
// reads the model's own column names by default. Each case writes its small CSV and runs the executable.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <sstream>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "tests/tools/commands/run_motionblocks.h"

namespace mb {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using testing::CommandResult;
using testing::RunMotionblocksIn;

// One row of a scan: position x [m], velocity v [m/s], disturbance d [N] (cogging with τ = 22.5 mm, viscous
// 0.5 N·s/m, a deterministic ±0.02 N ripple standing in for noise).
struct Sample {
  double t, x, v, d;
};

std::vector<Sample> Scans(const std::vector<double>& velocities) {
  std::vector<Sample> rows;
  for (double v : velocities) {
    for (int i = 0; i < 120; ++i) {
      const double x = 0.001 * i;
      const double d = 2.0 * std::sin(2.0 * std::numbers::pi * x / 0.0225) + 0.5 * v + 0.02 * std::sin(7.3 * i);
      rows.push_back({x / v, x, v, d});  // each scan starts at t = 0
    }
  }
  return rows;
}

class GprTables : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("mb_gpr_tables_" + std::to_string(::getpid()) + "_" +
            ::testing::UnitTest::GetInstance()->current_test_info()->name());
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  void Write(const std::string& name, const std::string& text) { std::ofstream(dir_ / name) << text; }
  CommandResult Run(const std::vector<std::string>& arguments) { return RunMotionblocksIn(dir_, arguments); }
  fs::path dir_;
};

TEST_F(GprTables, FitWithoutTimeColumnRowsInAnyOrderThenPredictWithTheModelsColumns) {
  const auto rows = Scans({0.05, 0.1});
  std::ostringstream csv;
  csv << "x_m,v_m_s,dob_N\n";
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const auto& r = rows[(k * 97) % rows.size()];  // 97 and 240 are coprime: every row once, shuffled
    csv << r.x << ',' << r.v << ',' << r.d << '\n';
  }
  Write("training.csv", csv.str());
  const CommandResult fit = Run({"fit-gpr", "training.csv", "--position", "x_m", "--velocity", "v_m_s",
                                 "--disturbance", "dob_N", "--restarts", "0", "-o", "model.json"});
  ASSERT_EQ(fit.exit_code, 0) << fit.output;
  EXPECT_THAT(fit.output, HasSubstr("to 240 samples"));

  // The last row lies far outside the trained positions (0 … 0.119 m): predicted, and marked extrapolated (issue 30).
  Write("query.csv", "v_m_s,x_m\n0.05,0.004\n0.1,0.011\n0.1,1e299\n");
  const CommandResult predict = Run({"predict-gpr", "model.json", "query.csv", "-o", "predicted.csv"});
  ASSERT_EQ(predict.exit_code, 0) << predict.output;
  EXPECT_THAT(predict.output, HasSubstr("note: 1 of 3 rows lie outside the trained range (x_m in [0, 0.119] m"));
  std::ifstream in(dir_ / "predicted.csv");
  std::string header;
  std::getline(in, header);
  EXPECT_EQ(header, "v_m_s,x_m,mean,std,extrapolated");
  std::vector<std::string> flags;
  for (std::string line; std::getline(in, line);) flags.push_back(line.substr(line.rfind(',') + 1));
  EXPECT_EQ(flags, (std::vector<std::string>{"0", "0", "1"}));
}

// --target smoothed: the disturbance is computed from time, position and force (M_n·ẍ + B_n·ẋ − u, zero-phase), each
// scan (restarting at t = 0) separately; at constant velocity u = B_n·v − d.
TEST_F(GprTables, FitsTheSmoothedTargetFromTimePositionAndForce) {
  std::ostringstream csv;
  csv << "time_s,x_m,v_m_s,u_N\n";
  for (const auto& r : Scans({0.05, 0.1})) csv << r.t << ',' << r.x << ',' << r.v << ',' << 3.0 * r.v - r.d << '\n';
  Write("scans.csv", csv.str());
  const CommandResult fit =
      Run({"fit-gpr", "scans.csv", "--position-column", "x_m", "--velocity-column", "v_m_s", "--target", "smoothed",
           "--force-column", "u_N", "--nominal-mass", "0.2621", "--nominal-damping", "3", "--smoothing-cutoff-hz",
           "5", "--restarts", "0", "-o", "model.json"});
  ASSERT_EQ(fit.exit_code, 0) << fit.output;
  EXPECT_THAT(fit.output, HasSubstr("to 240 samples"));
  std::ifstream model(dir_ / "model.json");
  const std::string text((std::istreambuf_iterator<char>(model)), std::istreambuf_iterator<char>());
  EXPECT_THAT(text, HasSubstr("disturbance: smoothed_disturbance"));

  const CommandResult missing = Run({"fit-gpr", "scans.csv", "--position-column", "x_m", "--velocity-column",
                                     "v_m_s", "--target", "smoothed", "--nominal-mass", "0.2621", "-o", "m.json"});
  EXPECT_EQ(missing.exit_code, 2) << missing.output;
  EXPECT_THAT(missing.output, HasSubstr("fit-gpr --target smoothed: give --force-column COL (the force the plant "
                                        "received [N]) and the nominal plant: --nominal-mass M_n [kg] and "
                                        "--nominal-damping B_n [N*s/m], or --diagram LOOP.json (its dob block's)"));
  const CommandResult both = Run({"fit-gpr", "scans.csv", "--target", "smoothed", "--disturbance-column", "u_N",
                                  "-o", "m.json"});
  EXPECT_EQ(both.exit_code, 2) << both.output;
  EXPECT_THAT(both.output, HasSubstr("fit-gpr: --target smoothed computes the disturbance from time, position and "
                                     "force: drop --disturbance-column (or use --target dob)"));
}

TEST_F(GprTables, FitTakesScansThatRestartAtZeroAndPandasIndex) {
  const auto rows = Scans({0.05, 0.1});
  std::ostringstream restarting, pandas;
  restarting << "time_s,position_m,velocity_m_s,dob_N\n";
  pandas << ",time_s,position_m,velocity_m_s,dob_N\n";
  for (std::size_t k = 0; k < rows.size(); ++k) {
    const auto& r = rows[k];
    restarting << r.t << ',' << r.x << ',' << r.v << ',' << r.d << '\n';
    pandas << k << ',' << r.t << ',' << r.x << ',' << r.v << ',' << r.d << '\n';
  }
  Write("restarting.csv", restarting.str());
  Write("pandas.csv", pandas.str());
  for (const char* file : {"restarting.csv", "pandas.csv"}) {
    const CommandResult fit =
        Run({"fit-gpr", file, "--disturbance", "dob_N", "--restarts", "0", "-o", std::string(file) + ".json"});
    EXPECT_EQ(fit.exit_code, 0) << file << ": " << fit.output;
    EXPECT_THAT(fit.output, HasSubstr("to 240 samples")) << file;
  }
}

TEST_F(GprTables, FitTakesOneScanVelocity) {
  const auto rows = Scans({0.1});
  std::ostringstream csv;
  csv << "position_m,velocity_m_s,dob_N\n";
  for (const auto& r : rows) csv << r.x << ',' << r.v << ',' << r.d << '\n';
  Write("one_velocity.csv", csv.str());
  const CommandResult fit = Run({"fit-gpr", "one_velocity.csv", "--disturbance", "dob_N", "--restarts", "0", "-o",
                                 "model.json"});
  ASSERT_EQ(fit.exit_code, 0) << fit.output;
  // One velocity v = 0.1 m/s: the trained range is v ± 10 % (models/gpr/gpr_fit.h, TrainedVelocityRange).
  EXPECT_THAT(fit.output, HasSubstr("xdot [0.09, 0.11] m/s"));
}

}  // namespace
}  // namespace mb

// `motionblocks fit` as users call it: on the EMPS record (equation error), the refit parameters with their
// 95 % confidence intervals in fit.json, the fitted diagram, the error falling; a bad parameter name is one
// clear message and exit code 1.

#include <filesystem>
#include <fstream>
#include <string>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/tools/commands/run_motionblocks.h"

namespace mb {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

using testing::CommandResult;
using testing::ProcessTempDir;
using testing::ReadJsonFile;
using testing::RunMotionblocks;

const std::string kEmps = std::string(MB_SOURCE_DIR) + "/diagrams/emps";

// The benchmark's IDIM-LS figures: M ≈ 94 kg, Fv ≈ 195 N·s/m, Fc ≈ 21 N (EMPS_Description.pdf).
TEST(FitCommand, RefitsTheEmpsRigidBodyWithConfidenceIntervals) {
  const fs::path out = ProcessTempDir("mb_fit_command");
  fs::remove_all(out);
  const auto r = RunMotionblocks("fit " + kEmps + "/rigid_body.json --measurement " + kEmps +
                                 "/data/DATA_EMPS.csv --fit inertia.gain,friction.viscous "
                                 "--fit friction.coulomb,offset.value --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("force: RMSE"));
  const auto fit = ReadJsonFile(out / "fit.json");
  ASSERT_EQ(fit["parameters"].size(), 4u);
  const double expected[] = {94.0, 195.0, 21.0};
  const double tolerance[] = {4.0, 15.0, 3.0};
  for (std::size_t i = 0; i < 4; ++i) {
    const auto& p = fit["parameters"][i];
    const double estimate = p["estimate"], se = p["standard_error"];
    EXPECT_GT(se, 0.0) << p.dump();
    EXPECT_NEAR(p["ci95"][0].get<double>(), estimate - 1.96 * se, 1e-9 * std::abs(estimate) + 1e-12);
    EXPECT_NEAR(p["ci95"][1].get<double>(), estimate + 1.96 * se, 1e-9 * std::abs(estimate) + 1e-12);
    if (i < 3) {
      EXPECT_NEAR(estimate, expected[i], tolerance[i]) << p["name"];
    }
  }
  EXPECT_EQ(fit["parameters"][0]["name"], "inertia.gain");
  EXPECT_EQ(fit["mode"], "equation_error");
  EXPECT_LT(fit["rmse_after"].get<double>(), 0.7 * fit["rmse_before"].get<double>());
  // The fitted diagram carries the estimates and loads again.
  const auto fitted = ReadJsonFile(out / "fitted.json");
  double mass = 0.0;
  for (const auto& e : fitted["elements"]) {
    if (e["name"] == "inertia") mass = e["parameters"]["gain"];
  }
  EXPECT_DOUBLE_EQ(mass, fit["parameters"][0]["estimate"].get<double>());
  const auto again = RunMotionblocks("fit " + (out / "fitted.json").string() + " --measurement " + kEmps +
                                     "/data/DATA_EMPS.csv --fit offset.value --out " + (out / "again").string());
  ASSERT_EQ(again.exit_code, 0) << again.output;
  EXPECT_NEAR(ReadJsonFile(out / "again" / "fit.json")["rmse_before"].get<double>(), fit["rmse_after"].get<double>(),
              1e-6 * fit["rmse_after"].get<double>());
  fs::remove_all(out);
}

TEST(FitCommand, UnknownParameterIsOneClearMessage) {
  const auto r = RunMotionblocks("fit " + kEmps + "/rigid_body.json --measurement " + kEmps +
                                 "/data/DATA_EMPS_PULSES.csv --fit mass.gain --out " +
                                 ProcessTempDir("mb_fit_command_bad").string());
  EXPECT_EQ(r.exit_code, 2);  // bad input (README "Exit codes")
  EXPECT_THAT(r.output, HasSubstr("motionblocks: error: free parameter 'mass.gain': no element 'mass'"));
}

}  // namespace
}  // namespace mb

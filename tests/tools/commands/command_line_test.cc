// The motionblocks executable as users call it: exit codes, files written, one clear message on bad input.

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
using testing::RunMotionblocks;

const std::string kSource = MB_SOURCE_DIR;

TEST(CommandLine, VersionPrintsTheProjectVersion) {
  const CommandResult r = RunMotionblocks("--version");
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, ::testing::StartsWith("motionblocks " MB_PROJECT_VERSION));
}

TEST(StabilityCommand, ConventionalLoopIsStableAndTheReportHasTheTermsAndBodePlots) {
  const fs::path out = ProcessTempDir("mb_stability_command");
  fs::remove_all(out);
  const CommandResult r =
      RunMotionblocks("stability " + kSource + "/diagrams/paper/conventional.json --bode-points 50 --out " +
                      out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("conventional FF/FB/DOB loop stable: yes"));
  std::ifstream in(out / "stability.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_TRUE(j.at("dob_loop_stable").get<bool>());
  EXPECT_TRUE(j.at("inner_loop_stable").get<bool>());
  EXPECT_DOUBLE_EQ(j.at("loop").at("nominal_mass").get<double>(), 0.2621);
  EXPECT_GT(j.at("paper").at("gamma_d_to_x").get<double>(), 0.0);
  EXPECT_EQ(j.at("bode").size(), 50u);
  EXPECT_FALSE(j.at("has_gpr").get<bool>());
  EXPECT_TRUE(fs::exists(out / "report.html"));
}

TEST(StabilityCommand, PayloadOverrideReachesTheLoop) {
  const fs::path out = ProcessTempDir("mb_stability_payload");
  const CommandResult r = RunMotionblocks("stability " + kSource +
                                          "/diagrams/paper/conventional.json --bode-points 10 "
                                          "--set plant.payload_mass=0.25 --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream in(out / "stability.json");
  EXPECT_NEAR(nlohmann::json::parse(in).at("loop").at("mass").get<double>(), 0.2621 + 0.25, 1e-12);
}

TEST(StabilityCommand, DiagramWithoutTheLoopSaysWhatIsMissing) {
  const CommandResult r = RunMotionblocks("stability " + kSource + "/diagrams/emps/rigid_body.json --out " +
                                          ProcessTempDir("mb_stability_bad").string());
  EXPECT_EQ(r.exit_code, 2);  // bad input (README "Exit codes")
  EXPECT_THAT(r.output, HasSubstr("motionblocks: error:"));
  EXPECT_THAT(r.output, HasSubstr("dob"));
}

}  // namespace
}  // namespace mb

// `motionblocks fit` as users call it: on the EMPS record (equation error), the refit parameters with their
// 95 % confidence intervals in fit.json, the fitted diagram, the error falling; a bad parameter name is one
// clear message and exit code 1.

#include <cmath>
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

// Issue 30: results that mean nothing are not reported as results. Each log is written here; the EMPS rigid body
// (force = M·a + Fv·v + Fc·sign(v) + offset) is fitted to it.
class UnidentifiableFit : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = ProcessTempDir("mb_fit_unidentifiable");
    fs::remove_all(dir_);
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  // time_s, position_m = position(t), force_N = force(t, i) for 4000 samples at 1 kHz.
  template <typename Position, typename Force>
  std::string WriteLog(const std::string& name, Position position, Force force) {
    std::ofstream out(dir_ / name);
    out << "time_s,position_m,force_N\n";
    out.precision(17);
    for (int i = 0; i < 4000; ++i) {
      const double t = 1e-3 * i;
      out << t << ',' << position(t) << ',' << force(t, i) << '\n';
    }
    return (dir_ / name).string();
  }
  fs::path dir_;
};

TEST_F(UnidentifiableFit, ALogWithoutMotionExitsThreeNamingWhatItCannotEstimate) {
  const std::string log = WriteLog("still.csv", [](double) { return 0.1; },
                                   [](double, int i) { return 5.0 + 0.3 * std::sin(1.7 * i); });
  const fs::path out = dir_ / "out";
  fs::create_directories(out);
  std::ofstream(out / "fitted.json") << "{}";  // an earlier run's
  const auto r = RunMotionblocks("fit " + kEmps + "/rigid_body.json --measurement " + log +
                                 " --fit inertia.gain,friction.viscous,offset.value --out " + out.string());
  EXPECT_EQ(r.exit_code, 3) << r.output;
  EXPECT_THAT(r.output,
              HasSubstr("motionblocks: error: " + log +
                        ": the parameters cannot be estimated from this log: inertia.gain, friction.viscous have no "
                        "effect on the model output in this log (the motion does not excite them: e.g. no "
                        "acceleration for a mass, no velocity for friction); leave them out of --fit (keep the "
                        "diagram's value) or record a log that excites them (details in " +
                        (out / "fit.json").string() + ")\n"));
  const auto fit = ReadJsonFile(out / "fit.json");
  EXPECT_EQ(fit["identifiable"], false);
  EXPECT_EQ(fit["status"], "not identifiable");
  EXPECT_EQ(fit["not_identifiable"]["no_effect"], (nlohmann::json{"inertia.gain", "friction.viscous"}));
  EXPECT_TRUE(fit["parameters"][0]["standard_error"].is_null());  // nothing estimated: no interval
  EXPECT_NEAR(fit["parameters"][2]["estimate"].get<double>(), 5.0, 0.05);  // the offset is
  EXPECT_FALSE(fs::exists(out / "fitted.json"));
}

// improve on the same log: refused as fit refuses it (exit 3), not a loop of steps fitted to nothing (tests/hostile).
TEST_F(UnidentifiableFit, ImproveOnALogWithoutMotionExitsThreeAsFitDoes) {
  const std::string log = WriteLog("still_improve.csv", [](double) { return 0.1; },
                                   [](double, int i) { return 5.0 + 0.3 * std::sin(1.7 * i); });
  const auto r = RunMotionblocks("improve " + kEmps + "/rigid_body.json --measurement " + log +
                                 " --max-effects 1 --out " + (dir_ / "improve").string());
  EXPECT_EQ(r.exit_code, 3) << r.output;
  EXPECT_THAT(r.output, HasSubstr(": the diagram's free parameters cannot be estimated from this log: "));
  EXPECT_THAT(r.output, HasSubstr("nothing to improve on (motionblocks fit says the same)"));
}

TEST_F(UnidentifiableFit, CoulombAndOffsetOnAOneSignedVelocityCannotBeToldApart) {
  const std::string log = WriteLog("one_signed.csv", [](double t) { return 0.01 * t + 0.02 * t * t; },
                                   [](double t, int i) {
                                     return 95.0 * 0.04 + 200.0 * (0.01 + 0.04 * t) + 20.0 + 3.0 + 0.3 * std::sin(1.7 * i);
                                   });
  const auto r = RunMotionblocks("fit " + kEmps + "/rigid_body.json --measurement " + log +
                                 " --fit friction.viscous,friction.coulomb,offset.value --out " + (dir_ / "o").string());
  EXPECT_EQ(r.exit_code, 3) << r.output;
  EXPECT_THAT(r.output, HasSubstr(": the parameters cannot be estimated from this log: friction.coulomb and "
                                  "offset.value cannot be told apart (they change the output alike: condition number "));
  const auto fit = ReadJsonFile(dir_ / "o" / "fit.json");
  EXPECT_EQ(fit["not_identifiable"]["cannot_be_told_apart"], nlohmann::json::array({nlohmann::json::array({"friction.coulomb", "offset.value"})}));
  EXPECT_GT(fit["condition_number"].get<double>(), 1e6);
  EXPECT_THAT(fit["warning"].get<std::string>(), HasSubstr("fit only one of them"));
}

TEST_F(UnidentifiableFit, ANonFiniteResultExitsThreeWithTheReason) {
  const std::string log = WriteLog("huge.csv", [](double t) { return 0.1 * std::sin(6.28 * t); },
                                   [](double t, int) { return 1e300 * std::cos(6.28 * t); });
  const auto r = RunMotionblocks("fit " + kEmps + "/rigid_body.json --measurement " + log +
                                 " --fit offset.value --out " + (dir_ / "o").string());
  EXPECT_EQ(r.exit_code, 3) << r.output;
  EXPECT_THAT(r.output, HasSubstr(log + ": the fit of force to column 'force_N' is not finite: RMSE before inf, RMSE "
                                        "after inf"));
  EXPECT_THAT(r.output, HasSubstr("the largest measured |force_N| is 1e+300 N (values beyond about 1e150 overflow "
                                  "when squared): check the column's unit and remove outlier rows\n"));
  EXPECT_THAT(r.output, ::testing::Not(HasSubstr("nan")));
}

}  // namespace
}  // namespace mb

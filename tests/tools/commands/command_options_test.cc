// The command line as people use it (issue 11): --set reaches the solver and defaultExperiment sections on every
// command as in sweeps; one option name per meaning across commands, the old spellings kept as deprecated aliases.

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
using nlohmann::json;
using ::testing::HasSubstr;
using ::testing::Not;
using testing::CommandResult;
using testing::ProcessTempDir;
using testing::ReadJsonFile;
using testing::RunMotionblocks;

// x' = -x, x(0) = 1 on rk4 with a 1 ms step, logged every 1 ms for 0.1 s.
fs::path WriteDecayDiagram(const fs::path& dir) {
  const json j = {
      {"schemaVersion", "1.0"},
      {"name", "decay"},
      {"defaultExperiment", {{"startTime", 0.0}, {"stopTime", 0.1}, {"stepSize", 0.001}}},
      {"solver", {{"type", "rk4"}, {"step", 1e-3}}},
      {"elements",
       {{{"name", "x"}, {"type", "integrator"}, {"parameters", {{"initial_condition", 1.0}}}},
        {{"name", "k"}, {"type", "gain"}, {"parameters", {{"gain", -1.0}}}}}},
      {"connections",
       {{{"startElement", "x"}, {"startConnector", "y"}, {"endElement", "k"}, {"endConnector", "u"}},
        {{"startElement", "k"}, {"startConnector", "y"}, {"endElement", "x"}, {"endConnector", "u"}}}},
      {"log", {"x.y"}}};
  const fs::path path = dir / "decay.json";
  std::ofstream(path) << j.dump(2);
  return path;
}

// A 1 N force on a mass the diagram writes in grams, {"value": 2000, "unit": "g"}, for 1 s: the final velocity
// [m/s] is 1/mass [kg].
fs::path WriteGramMassDiagram(const fs::path& dir) {
  const json j = {
      {"schemaVersion", "1.0"},
      {"defaultExperiment", {{"startTime", 0.0}, {"stopTime", 1.0}, {"stepSize", 0.01}}},
      {"solver", {{"type", "rk4"}, {"step", 0.01}}},
      {"elements",
       {{{"name", "force"}, {"type", "constant"}, {"parameters", {{"value", 1.0}}}},
        {{"name", "mass"}, {"type", "rigid_body"}, {"parameters", {{"mass", {{"value", 2000}, {"unit", "g"}}}}}}}},
      {"connections", {{{"startElement", "force"}, {"startConnector", "y"}, {"endElement", "mass"}, {"endConnector", "f"}}}},
      {"log", {"mass.v"}},
      {"metrics", {{{"name", "final_velocity"}, {"type", "final"}, {"signal", "mass.v"}, {"unit", "m/s"}}}}};
  const fs::path path = dir / "g.json";
  std::ofstream(path) << j.dump(2);
  return path;
}

// Issue 30: a --set number is in the parameter's SI unit whatever unit the diagram wrote (2 means 2 kg, not 2 g); a
// quantity object is accepted and converted; --help says so.
TEST(CommandOptions, SetNumbersAreInTheSiUnitAndQuantitiesAreConverted) {
  const fs::path dir = ProcessTempDir("mb_options_set_units");
  const fs::path diagram = WriteGramMassDiagram(dir);
  auto final_velocity = [&](const std::string& set, const std::string& name) {
    const CommandResult r =
        RunMotionblocks("run " + diagram.string() + " " + set + " --quiet --out " + (dir / name).string());
    EXPECT_EQ(r.exit_code, 0) << r.output;
    return r.exit_code == 0 ? ReadJsonFile(dir / name / "summary.json")["metrics"]["final_velocity"].get<double>() : 0.0;
  };
  EXPECT_NEAR(final_velocity("--set mass.mass=4", "kg"), 0.25, 1e-9);  // 4 kg (4 g would give 250 m/s)
  EXPECT_NEAR(final_velocity(R"(--set 'mass.mass={"value": 500, "unit": "g"}')", "g"), 2.0, 1e-9);
  const CommandResult typo =
      RunMotionblocks("run " + diagram.string() + R"( --set 'mass.mass={"value": 500, "unti": "g"}' --out )" +
                      (dir / "typo").string());
  EXPECT_EQ(typo.exit_code, 2);
  EXPECT_THAT(typo.output, HasSubstr("/elements/1/parameters/mass/unti: a quantity takes only \"value\" and "
                                     "\"unit\", not 'unti' (did you mean \"unit\"?)"));
  EXPECT_THAT(RunMotionblocks("run --help").output, HasSubstr("A number is in the parameter's SI unit"));
  fs::remove_all(dir);
}

TEST(CommandOptions, SetChangesTheSolverAndTheExperimentOfRun) {
  const fs::path dir = ProcessTempDir("mb_options_set");
  const fs::path diagram = WriteDecayDiagram(dir);
  const CommandResult rk4 = RunMotionblocks("run " + diagram.string() + " --quiet --out " + (dir / "rk4").string());
  ASSERT_EQ(rk4.exit_code, 0) << rk4.output;
  const CommandResult cvode = RunMotionblocks("run " + diagram.string() + " --set solver.type=cvode --set " +
                                              "defaultExperiment.stopTime=0.2 --quiet --out " + (dir / "cvode").string());
  ASSERT_EQ(cvode.exit_code, 0) << cvode.output;
  const json a = ReadJsonFile(dir / "rk4" / "summary.json");
  const json b = ReadJsonFile(dir / "cvode" / "summary.json");
  EXPECT_EQ(a["solver"]["type"], "rk4");
  EXPECT_EQ(b["solver"]["type"], "cvode");
  // rk4 takes one step per millisecond with 4 right-hand sides each; CVODE stops at every log point and chooses its
  // own steps and evaluations (measured: 203 steps, not rk4's 200 over 0.2 s): the solver really changed.
  EXPECT_EQ(a["solver"]["steps"], 100);
  EXPECT_EQ(a["solver"]["rhs_evaluations"], 400);
  EXPECT_NE(b["solver"]["steps"], 200);
  EXPECT_NE(b["solver"]["rhs_evaluations"], 800);
  EXPECT_EQ(a["samples"], 101);
  EXPECT_EQ(b["samples"], 201);  // stopTime 0.2 s reached the run
  fs::remove_all(dir);
}

TEST(CommandOptions, AMisspelledSolverKeyInSetIsRefusedWithTheClosestName) {
  const fs::path dir = ProcessTempDir("mb_options_set_typo");
  const CommandResult r = RunMotionblocks("run " + WriteDecayDiagram(dir).string() +
                                          " --set solver.tpye=cvode --quiet --out " + (dir / "o").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("/solver/tpye"));
  EXPECT_THAT(r.output, HasSubstr("did you mean 'type'"));
  fs::remove_all(dir);
}

const std::string kEmps = std::string(MB_SOURCE_DIR) + "/diagrams/emps";
const std::string kEmpsLog = kEmps + "/data/DATA_EMPS.csv";

TEST(CommandOptions, TheOldNameOfAnOptionStillWorksAndSaysTheNewOne) {
  const fs::path dir = ProcessTempDir("mb_options_alias");
  const CommandResult old_name = RunMotionblocks("fit " + kEmps + "/rigid_body.json --measurement " + kEmpsLog +
                                                 " --params offset.value --quiet --out " + (dir / "old").string());
  ASSERT_EQ(old_name.exit_code, 0) << old_name.output;
  EXPECT_THAT(old_name.output,
              HasSubstr("motionblocks: note: --params is the old name of --fit; it still works, but write --fit\n"));
  const CommandResult new_name = RunMotionblocks("fit " + kEmps + "/rigid_body.json --measurement " + kEmpsLog +
                                                 " --fit offset.value --out " + (dir / "new").string());
  ASSERT_EQ(new_name.exit_code, 0) << new_name.output;
  EXPECT_THAT(new_name.output, Not(HasSubstr("old name")));
  EXPECT_THAT(new_name.output, HasSubstr("fit " + kEmps + "/rigid_body.json to "));  // the stage line …
  EXPECT_THAT(old_name.output, Not(HasSubstr("fit " + kEmps + "/rigid_body.json to ")));  // … silenced by --quiet
  const json a = ReadJsonFile(dir / "old" / "fit.json");
  const json b = ReadJsonFile(dir / "new" / "fit.json");
  EXPECT_EQ(a["parameters"], b["parameters"]);  // the same refit, whichever name
  fs::remove_all(dir);
}

TEST(CommandOptions, HelpListsOnlyTheNewNames) {
  const CommandResult fit = RunMotionblocks("fit --help");
  EXPECT_THAT(fit.output, HasSubstr("--fit"));
  EXPECT_THAT(fit.output, Not(HasSubstr("--params")));
  const CommandResult fit_gpr = RunMotionblocks("fit-gpr --help");
  EXPECT_THAT(fit_gpr.output, HasSubstr("--disturbance-column"));
  EXPECT_THAT(fit_gpr.output, Not(HasSubstr("--disturbance ")));
}

TEST(CommandOptions, FitGprWithoutTheDisturbanceColumnSaysWhichOption) {
  const CommandResult r = RunMotionblocks("fit-gpr " + kEmpsLog + " -o /tmp/never_written_model.json");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("motionblocks: error: fit-gpr: name the disturbance column (the DOB estimate): "
                                  "--disturbance-column COL"));
}

// Progress goes to stderr only on a terminal or with --progress (a test's output is a file), never with --quiet.
TEST(CommandOptions, ProgressIsShownWithTheFlagAndSilencedByQuiet) {
  const fs::path dir = ProcessTempDir("mb_options_progress");
  const fs::path diagram = WriteDecayDiagram(dir);
  const CommandResult plain = RunMotionblocks("run " + diagram.string() + " --out " + (dir / "a").string());
  ASSERT_EQ(plain.exit_code, 0) << plain.output;
  EXPECT_THAT(plain.output, Not(HasSubstr("100 %")));
  const CommandResult shown = RunMotionblocks("run " + diagram.string() + " --progress --out " + (dir / "b").string());
  ASSERT_EQ(shown.exit_code, 0) << shown.output;
  EXPECT_THAT(shown.output, HasSubstr("run decay  100 % ("));
  const CommandResult both =
      RunMotionblocks("run " + diagram.string() + " --progress --quiet --out " + (dir / "c").string());
  EXPECT_EQ(both.exit_code, 2) << both.output;
  EXPECT_THAT(both.output, HasSubstr("--progress excludes --quiet"));
  fs::remove_all(dir);
}

// Library texts reach the user reworded, with the input and what to do (tools/commands/error_text.h).
TEST(CommandOptions, AnOutputFolderUnderAFileIsOneClearMessage) {
  const fs::path dir = ProcessTempDir("mb_options_out_under_file");
  const fs::path diagram = WriteDecayDiagram(dir);
  std::ofstream(dir / "plain_file") << "x";
  const CommandResult r =
      RunMotionblocks("run " + diagram.string() + " --quiet --out " + (dir / "plain_file" / "o").string());
  EXPECT_EQ(r.exit_code, 1) << r.output;
  EXPECT_THAT(r.output, HasSubstr("motionblocks: error: cannot use the file or folder " +
                                  (dir / "plain_file" / "o").string() + " (reading " + diagram.string() +
                                  "): Not a directory. Check that the path exists"));
  EXPECT_THAT(r.output, Not(HasSubstr("filesystem error")));
  fs::remove_all(dir);
}

TEST(CommandOptions, ALongSetValueIsNotEchoed) {
  const fs::path dir = ProcessTempDir("mb_options_long_set");
  const std::string value(100'000, 'v');  // one argument may not exceed 128 KB (MAX_ARG_STRLEN)
  const CommandResult r =
      testing::RunMotionblocksIn(dir, {"run", WriteDecayDiagram(dir).string(), "--set", value, "--quiet"});
  EXPECT_EQ(r.exit_code, 2);
  EXPECT_LT(r.output.size(), 1000u);
  EXPECT_THAT(r.output, HasSubstr("… (99800 more bytes)': write a parameter override as block.parameter=value"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace mb

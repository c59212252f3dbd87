// The documented exit codes (README "Exit codes"): 0 ok, 1 failure, 2 bad usage or bad input, 3 numerical
// failure — for the cases of issue 11 that used to exit 0 with a wrong answer, hang or exhaust memory.

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
using testing::CommandResult;
using testing::ProcessTempDir;
using testing::RunMotionblocks;

// x' = k·x with x(0) = 1 (k = gain), logged, with an RMSE metric: what `run` computes for a diagram.
fs::path WriteGrowthDiagram(const fs::path& dir, double gain, const json& experiment) {
  const json j = {
      {"schemaVersion", "1.0"},
      {"name", "growth"},
      {"defaultExperiment", experiment},
      {"solver", {{"type", "rk4"}, {"step", 1e-3}}},
      {"elements",
       {{{"name", "x"}, {"type", "integrator"}, {"parameters", {{"initial_condition", 1.0}}}},
        {{"name", "k"}, {"type", "gain"}, {"parameters", {{"gain", gain}}}}}},
      {"connections",
       {{{"startElement", "x"}, {"startConnector", "y"}, {"endElement", "k"}, {"endConnector", "u"}},
        {{"startElement", "k"}, {"startConnector", "y"}, {"endElement", "x"}, {"endConnector", "u"}}}},
      {"log", {"x.y"}},
      {"metrics", {{{"name", "tracking_rmse"}, {"type", "rmse"}, {"signal", "x.y"}}}}};
  const fs::path path = dir / "growth.json";
  std::ofstream(path) << j.dump(2);
  return path;
}

const json kShortRun = {{"startTime", 0.0}, {"stopTime", 0.1}, {"stepSize", 0.001}};

CommandResult RunDiagram(const fs::path& diagram, const std::string& extra = "") {
  return RunMotionblocks("run " + diagram.string() + " --quiet --out " + (diagram.parent_path() / "out").string() +
                         extra);
}

TEST(ExitCodes, UsageErrorsAreTwoAndHelpIsZero) {
  EXPECT_EQ(RunMotionblocks("no-such-command").exit_code, 2);
  EXPECT_EQ(RunMotionblocks("run").exit_code, 2);
  EXPECT_EQ(RunMotionblocks("run --help").exit_code, 0);
}

TEST(ExitCodes, ADivergingRunIsANumericalFailureNamingBlockSignalAndTime) {
  const fs::path dir = ProcessTempDir("mb_exit_diverge");
  const CommandResult r = RunDiagram(WriteGrowthDiagram(dir, 1e308, kShortRun));
  EXPECT_EQ(r.exit_code, 3) << r.output;
  EXPECT_THAT(r.output, HasSubstr("motionblocks: error: rk4 solver: block 'x' output 'y' is inf after the step to "
                                  "t = 0.001 s"));
  EXPECT_FALSE(fs::exists(dir / "out" / "summary.json"));  // no -nan RMSE written as a result
  fs::remove_all(dir);
}

TEST(ExitCodes, AStepLongerThanTheRunIsBadInput) {
  const fs::path dir = ProcessTempDir("mb_exit_step");
  const CommandResult r =
      RunDiagram(WriteGrowthDiagram(dir, -1.0, {{"startTime", 0.0}, {"stopTime", 0.1}, {"stepSize", 1.0}}));
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("motionblocks: error: growth: defaultExperiment.stepSize (1 s) is longer than the "
                                  "run (0.1 s"));
  fs::remove_all(dir);
}

TEST(ExitCodes, RunsBeyondMaxStepsAreRefusedAndTheLimitCanBeRaised) {
  const fs::path dir = ProcessTempDir("mb_exit_max_steps");
  const fs::path diagram = WriteGrowthDiagram(dir, -1.0, kShortRun);  // 100 steps of 1 ms
  const CommandResult refused = RunDiagram(diagram, " --max-steps 50");
  EXPECT_EQ(refused.exit_code, 2) << refused.output;
  EXPECT_THAT(refused.output, HasSubstr("takes about 100 steps, more than the limit of 50."));
  EXPECT_THAT(refused.output, HasSubstr("raise the limit with --max-steps N"));
  EXPECT_EQ(RunDiagram(diagram, " --max-steps 1000").exit_code, 0);
  // stopTime 1e9 and 1e308: refused at once, not a hang or bad_alloc.
  const CommandResult long_run =
      RunDiagram(WriteGrowthDiagram(dir, -1.0, {{"startTime", 0.0}, {"stopTime", 1e9}, {"stepSize", 0.001}}));
  EXPECT_EQ(long_run.exit_code, 2) << long_run.output;
  EXPECT_THAT(long_run.output, HasSubstr("takes about 1e+12 steps, more than the limit of 1e+08"));
  const CommandResult huge =
      RunDiagram(WriteGrowthDiagram(dir, -1.0, {{"startTime", 0.0}, {"stopTime", 1e308}, {"stepSize", 0.001}}));
  EXPECT_EQ(huge.exit_code, 2) << huge.output;
  EXPECT_THAT(huge.output, HasSubstr("t + 0.001 == t in double precision, so time could never advance"));
  fs::remove_all(dir);
}

// `run` streams its log to signals.csv: a log of 2 × 50,001 values is written whole under --max-steps 60000, which
// bounds what a run may hold in memory (an in-memory log of that size is refused: runtime_limits_test); `run` keeps
// at most 20,000 samples per signal in memory for its figures (2 × 20,000 < 60,000).
TEST(ExitCodes, RunStreamsALogLargerThanTheMemoryLimitToDisk) {
  const fs::path dir = ProcessTempDir("mb_exit_streamed");
  const fs::path diagram = WriteGrowthDiagram(dir, -1.0, {{"startTime", 0.0}, {"stopTime", 5.0}, {"stepSize", 1e-4}});
  json j;
  std::ifstream(diagram) >> j;
  j["log"] = {"x.y", "k.y"};
  j["solver"] = {{"type", "rk4"}, {"step", 1e-4}};  // 50,000 steps
  std::ofstream(diagram) << j.dump(2);
  const CommandResult r = RunDiagram(diagram, " --max-steps 60000");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  std::ifstream in(diagram.parent_path() / "out" / "signals.csv");
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "time_s,x.y,k.y");
  std::size_t rows = 0;
  while (std::getline(in, line)) ++rows;
  EXPECT_EQ(rows, 50001u);
  EXPECT_EQ(testing::ReadJsonFile(diagram.parent_path() / "out" / "summary.json")["samples"], 50001);
  fs::remove_all(dir);
}

TEST(ExitCodes, DeeplyNestedJsonIsBadInput) {
  const fs::path dir = ProcessTempDir("mb_exit_deep");
  const fs::path deep = dir / "deep.json";
  std::ofstream(deep) << std::string(100000, '[') << std::string(100000, ']');
  const CommandResult r = RunMotionblocks("run " + deep.string() + " --quiet --out " + (dir / "out").string());
  EXPECT_EQ(r.exit_code, 2) << r.output.substr(0, 2000);
  EXPECT_THAT(r.output, HasSubstr("deep.json: JSON nested deeper than 256 levels"));
  fs::remove_all(dir);
}

TEST(ExitCodes, AHugeSweepIsRefusedBeforeAnyRun) {
  const fs::path dir = ProcessTempDir("mb_exit_sweep");
  const fs::path diagram = WriteGrowthDiagram(dir, -1.0, kShortRun);
  json values = json::array();
  for (int i = 0; i < 1000; ++i) values.push_back(i);
  const fs::path sweep = dir / "grid.json";
  std::ofstream(sweep) << json{{"grid", {{"k.gain", values}, {"x.initial_condition", values}, {"k.other", values}}}};
  const CommandResult r = RunMotionblocks("sweep " + diagram.string() + " " + sweep.string() + " --quiet --out " +
                                          (dir / "out").string());
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("/grid: the Cartesian product gives 1e+09 runs, more than the limit of 100000"));
  EXPECT_FALSE(fs::exists(dir / "out" / "runs.csv"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace mb

// The motionblocks executable as users call it: exit codes, files written, one clear message on bad input.

#include <filesystem>
#include <fstream>
#include <string>
#include <utility>
#include <vector>

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

// Issue 26: each command registers itself from its own file (command_registry.h); --help lists all sixteen under
// their groups, and the simulating ones, only they, get --max-steps and the progress options.
TEST(CommandLine, HelpListsEveryRegisteredCommandUnderItsGroup) {
  const CommandResult r = RunMotionblocks("--help");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::vector<std::pair<std::string, std::vector<std::string>>> groups{
      {"Simulate", {"run"}},
      {"Compare with measurements", {"compare", "fit", "improve"}},
      {"Learned compensation (TISO-GPR)", {"fit-gpr", "predict-gpr", "reproduce", "stability"}},
      {"Hardware in the loop", {"hil", "virtual-stage"}},
      {"Batch", {"sweep", "sweep-merge"}},
      {"Inspect", {"blocks", "draw", "linearize", "schema"}}};
  std::size_t previous = 0;
  for (const auto& [title, commands] : groups) {
    const std::size_t at = r.output.find(title + ":");
    ASSERT_NE(at, std::string::npos) << title << "\n" << r.output;
    EXPECT_GT(at, previous) << title << " is listed out of order";
    previous = at;
    for (const auto& command : commands) EXPECT_THAT(r.output, HasSubstr("\n  " + command + " ")) << command;
  }
  for (const char* simulating : {"run", "compare", "fit", "improve", "sweep", "reproduce"}) {
    EXPECT_THAT(RunMotionblocks(std::string(simulating) + " --help").output, HasSubstr("--max-steps")) << simulating;
  }
  EXPECT_THAT(RunMotionblocks("stability --help").output, ::testing::Not(HasSubstr("--max-steps")));
}

// Issue 27 item 4: `linearize` on H(s) = 1/(s + 2): A = −2, B = 1, C = 1, D = 0 printed and in the JSON with the Bode
// data (−6.02 dB at low frequency), the Bode report written; an unknown input connector is bad input (exit 2).
TEST(LinearizeCommand, PrintsTheMatricesWritesTheJsonAndTheBodeReport) {
  const fs::path dir = ProcessTempDir("mb_linearize");
  fs::remove_all(dir);
  fs::create_directories(dir);
  const nlohmann::json diagram = {
      {"schemaVersion", "1.0"},
      {"name", "first_order"},
      {"connectors", {{{"name", "u"}, {"kind", "input"}, {"unit", "N"}}, {{"name", "y"}, {"kind", "output"}, {"unit", "m"}}}},
      {"elements", {{{"name", "lag"}, {"type", "transfer_function"}, {"parameters", {{"numerator", {1.0}}, {"denominator", {1.0, 2.0}}}}}}},
      {"connections", {{{"startConnector", "u"}, {"endElement", "lag"}, {"endConnector", "u"}},
                       {{"startElement", "lag"}, {"startConnector", "y"}, {"endConnector", "y"}}}}};
  std::ofstream(dir / "lag.json") << diagram.dump();
  CommandResult r = testing::RunMotionblocksIn(dir, {"linearize", "lag.json", "--input", "u=1", "--from-hz", "0.001",
                                                     "--to-hz", "10", "--points", "5", "--report", "bode"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("1 states, 1 inputs, 1 outputs"));
  EXPECT_THAT(r.output, HasSubstr("state: block 'lag' continuous state 0 of 1"));
  EXPECT_THAT(r.output, HasSubstr("wrote lag.linearization.json"));
  std::ifstream in(dir / "lag.linearization.json");
  const nlohmann::json j = nlohmann::json::parse(in);
  EXPECT_NEAR(j["A"][0][0].get<double>(), -2.0, 1e-8);
  EXPECT_NEAR(j["B"][0][0].get<double>(), 1.0, 1e-8);
  EXPECT_NEAR(j["C"][0][0].get<double>(), 1.0, 1e-8);
  EXPECT_NEAR(j["D"][0][0].get<double>(), 0.0, 1e-8);
  EXPECT_EQ(j["inputs"][0]["value"], 1.0);
  EXPECT_EQ(j["bode"][0]["frequency_hz"].size(), 5u);
  EXPECT_NEAR(j["bode"][0]["gain_db"][0].get<double>(), -6.0206, 1e-3);
  EXPECT_TRUE(fs::exists(dir / "bode" / "report.html"));
  r = testing::RunMotionblocksIn(dir, {"linearize", "lag.json", "--input", "force=1"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("no input connector 'force'; its inputs: u"));
  r = testing::RunMotionblocksIn(dir, {"linearize", "lag.json", "--input", "u=abc"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("write connector=number"));
  fs::remove_all(dir);
}

// Issue 28: `blocks` shows every type's ports and an example element; an unknown name is an error with "did you mean"
// (it printed nothing with exit 0).
TEST(BlocksCommand, ShowsPortsAndAnExampleAndRefusesAnUnknownType) {
  CommandResult r = RunMotionblocks("blocks rigid_body");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, ::testing::StartsWith("rigid_body\n"));
  EXPECT_THAT(r.output, HasSubstr("\n  ports (built with the default parameters):\n    input  0: f [N], no direct "
                                  "feedthrough\n    output 0: x [m]\n    output 1: v [m/s]\n"));
  EXPECT_THAT(r.output, HasSubstr("\n    - mass (number, kg) = 1.0: moving mass M > 0\n"));
  EXPECT_THAT(r.output, ::testing::EndsWith("\n  example: {\"name\":\"rigid_body\",\"parameters\":{},"
                                            "\"type\":\"rigid_body\"}\n"));
  r = RunMotionblocks("blocks");
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("\nstate_space\n"));
  EXPECT_THAT(r.output, HasSubstr("\n  ports depend on parameters (no default for A, B, C)\n"));
  EXPECT_THAT(r.output, HasSubstr("\n  example: {\"name\":\"unit_delay\",\"parameters\":{},\"sampleTime\":0.001,"
                                  "\"type\":\"unit_delay\"}\n"));
  r = RunMotionblocks("blocks rigid_bdy");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_EQ(r.output, "motionblocks: error: unknown block type 'rigid_bdy' (did you mean rigid_body?): "
                      "`motionblocks blocks` lists them\n");
}

// A two-block diagram and a four-run list sweep in `dir` (returns the diagram, then the sweep file).
std::pair<fs::path, fs::path> WriteGainSweep(const fs::path& dir) {
  const nlohmann::json diagram = nlohmann::json::parse(R"({
    "schemaVersion": "1.0", "name": "gain",
    "defaultExperiment": {"startTime": 0, "stopTime": 0.01, "stepSize": 0.001},
    "solver": {"type": "rk4", "step": 0.001},
    "elements": [{"name": "c", "type": "constant", "parameters": {"value": 2.0}},
                 {"name": "k", "type": "gain", "parameters": {"gain": 1.0}}],
    "connections": [{"startElement": "c", "startConnector": "y", "endElement": "k", "endConnector": "u"}],
    "log": ["k.y"],
    "metrics": [{"name": "y_final", "type": "final", "signal": "k.y", "unit": "1"}]})");
  std::ofstream(dir / "gain.json") << diagram.dump(2);
  std::ofstream(dir / "sweep.json") << R"({"list": [{"k.gain": 1}, {"k.gain": 2}, {"k.gain": 3}, {"k.gain": 4}]})";
  return {dir / "gain.json", dir / "sweep.json"};
}

// Issue 28: `--shard 1/2` and `--shard 2/2` are the two halves (counted from 1, as Jest and Playwright count);
// --shard-index 0/2 is the first half again (counted from 0); the merge has every run once.
TEST(SweepCommand, ShardsCountFromOneAndShardIndexFromZero) {
  const fs::path dir = ProcessTempDir("mb_sweep_shards");
  const auto [diagram, sweep] = WriteGainSweep(dir);
  const std::string files = "sweep " + diagram.string() + " " + sweep.string() + " --quiet --jobs 1 ";
  CommandResult r = RunMotionblocks(files + "--shard 1/2 --out " + (dir / "s1").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("2 runs (list, shard 1/2)"));
  r = RunMotionblocks(files + "--shard 2/2 --out " + (dir / "s2").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("2 runs (list, shard 2/2)"));
  r = RunMotionblocks("sweep-merge " + (dir / "s1").string() + " " + (dir / "s2").string() + " --out " +
                      (dir / "all").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("4 runs, each once"));
  // --shard-index 0/2 is --shard 1/2: the folder of 1/2 resumes (nothing runs again).
  r = RunMotionblocks(files + "--shard-index 0/2 --out " + (dir / "s1").string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("2 runs (list, shard 1/2): 0 run now, 2 already done"));
  fs::remove_all(dir);
}

TEST(SweepCommand, AShardOutOfRangeSaysWhichNumberingApplies) {
  const fs::path dir = ProcessTempDir("mb_sweep_shard_range");
  const auto [diagram, sweep] = WriteGainSweep(dir);
  const std::string files = "sweep " + diagram.string() + " " + sweep.string() + " --quiet --out " +
                            (dir / "o").string() + " ";
  CommandResult r = RunMotionblocks(files + "--shard 0/2");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("motionblocks: error: --shard 0/2: --shard x/y counts from 1, so x runs from 1 to 2 "
                                  "(write --shard 1/2 … 2/2); --shard-index K/N counts from 0 (0 <= K < N)"));
  r = RunMotionblocks(files + "--shard-index 2/2");
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("motionblocks: error: --shard-index 2/2: --shard-index counts from 0, so K runs from "
                                  "0 to 1 (write --shard-index 0/2 … 1/2); --shard x/y counts from 1 (1 <= x <= y)"));
  // An empty shard is no shard: refused, not the whole sweep (found by tests/hostile).
  for (const char* option : {"--shard", "--shard-index"}) {
    r = testing::RunMotionblocksIn(dir, {"sweep", diagram.string(), sweep.string(), "--quiet", "--out",
                                         (dir / "o").string(), option, ""});
    EXPECT_EQ(r.exit_code, 2) << option << ": " << r.output;
    EXPECT_THAT(r.output, HasSubstr("an empty value: write")) << option;
  }
  EXPECT_FALSE(fs::exists(dir / "o" / "runs.csv"));
  fs::remove_all(dir);
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

// Issue 28: the output ends with one verdict line, the JSON says the same in named fields, and no bound is printed as
// −∞ or a negative number (eq. 62 of the 'paper' decomposition cannot certify a DOB loop).
TEST(StabilityCommand, EndsWithAVerdictAndNeverPrintsANegativeBound) {
  const fs::path out = ProcessTempDir("mb_stability_verdict");
  CommandResult r = RunMotionblocks("stability " + kSource + "/diagrams/paper/conventional.json --bode-points 5 --out " +
                                    out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("eq. 62: no α > 0 is certified: ρ ≥ 1 already at α = 0\n"));
  EXPECT_THAT(r.output, ::testing::EndsWith("\nverdict: certified: the conventional FF/FB/DOB loop is stable and the GP "
                                            "path is off (α = 0); the largest certified α is unknown without a GPR "
                                            "model (--gpr)\n"));
  EXPECT_THAT(r.output, ::testing::Not(HasSubstr("∞")));
  EXPECT_THAT(r.output, ::testing::Not(HasSubstr("< -")));

  // A slow DOB, a soft PD and a fast velocity filter: the GP path at α = 0.9 is beyond the small-gain bound.
  const std::string gp_loop = kSource + "/diagrams/paper/gp_loop.json --gpr " + kSource +
                              "/diagrams/paper/models/gpr_ps_d2.json --bode-points 5 ";
  r = RunMotionblocks("stability " + gp_loop +
                      "--set dob.cutoff_hz=1 --set pd_p.gain=300 --set velocity.cutoff_hz=450 --out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, ::testing::EndsWith("\nverdict: NOT certified: ρ = 8.624 ≥ 1 at α = 0.9 (small gain, DOB loop "
                                            "closed); the largest certified α: α < 0.1044\n"));
  nlohmann::json v = testing::ReadJsonFile(out / "stability.json").at("verdict");
  EXPECT_EQ(v.at("certified"), false);
  EXPECT_EQ(v.at("failing_condition"), "small_gain");
  EXPECT_DOUBLE_EQ(v.at("alpha_used").get<double>(), 0.9);
  EXPECT_NEAR(v.at("alpha_max").get<double>(), 0.1044, 1e-4);
  EXPECT_EQ(testing::ReadJsonFile(out / "stability.json").at("dob").at("alpha_used"), 0.9);

  // The shipped loop with its model: certified, up to α < 4.231.
  r = RunMotionblocks("stability " + gp_loop + "--out " + out.string());
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, ::testing::EndsWith("\nverdict: certified: ρ = 0.2127 < 1 at α = 0.9 (small gain, DOB loop "
                                            "closed); the largest certified α: α < 4.231\n"));
  v = testing::ReadJsonFile(out / "stability.json").at("verdict");
  EXPECT_EQ(v.at("certified"), true);
  EXPECT_TRUE(v.at("failing_condition").is_null());
  fs::remove_all(out);
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

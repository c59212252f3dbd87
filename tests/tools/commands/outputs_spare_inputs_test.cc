// Outputs never replace inputs (issue 30): each command that used to overwrite one of its own inputs with exit 0
// now refuses before any work, exit code 2, naming both paths, and the input is left as it was.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>

#include "tests/tools/commands/run_motionblocks.h"

namespace mb {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using testing::ProcessTempDir;
using testing::RunMotionblocksIn;

// A self-contained diagram: a constant into a gain.
constexpr const char* kDiagram = R"({"schemaVersion": "1.0",
  "elements": [{"name": "c", "type": "constant", "parameters": {"value": 1.0}},
               {"name": "g", "type": "gain", "parameters": {"gain": 2.0}}],
  "connections": [{"startElement": "c", "startConnector": "y", "endElement": "g", "endConnector": "u"}],
  "log": ["g.y"]}
)";
constexpr const char* kTable = "time_s,position_m,velocity_m_s,force_N,d\n0,0,0,0,0\n0.001,0,0,0,0\n";

std::string ReadText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// A fresh folder with d.json (kDiagram), t.csv (a small table) and m.json (not even a model: the refusal
// comes before anything is read).
fs::path Workspace(const std::string& name) {
  const fs::path dir = ProcessTempDir(name);
  fs::remove_all(dir);
  fs::create_directories(dir / "out");
  std::ofstream(dir / "d.json") << kDiagram;
  std::ofstream(dir / "t.csv") << kTable;
  std::ofstream(dir / "m.json") << "{}\n";
  return dir;
}

// Runs `arguments` in `dir` and expects the refusal: exit 2, both paths named, `input` unchanged.
void ExpectRefused(const fs::path& dir, const std::vector<std::string>& arguments, const fs::path& input,
                   const std::string& message) {
  const std::string before = ReadText(dir / input);
  const auto r = RunMotionblocksIn(dir, arguments);
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr(message));
  EXPECT_THAT(r.output, HasSubstr("nothing was done"));
  EXPECT_EQ(ReadText(dir / input), before) << "the input " << input << " was changed";
}

TEST(OutputsSpareInputs, DrawOntoItsDiagram) {
  const fs::path dir = Workspace("mb_spare_draw");
  ExpectRefused(dir, {"draw", "d.json", "-o", "d.json"}, "d.json",
                "-o d.json is the input DIAGRAM d.json: writing it would destroy the input");
  ExpectRefused(dir, {"draw", "d.json", "--format", "dot", "-o", "out/../d.json"}, "d.json",
                "-o out/../d.json is the input DIAGRAM d.json");
  // Another output is drawn as before.
  const auto r = RunMotionblocksIn(dir, {"draw", "d.json", "--format", "dot", "-o", "d.dot"});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  EXPECT_TRUE(fs::exists(dir / "d.dot"));
}

TEST(OutputsSpareInputs, FitGprOntoItsTableAndPredictGprOntoItsModel) {
  const fs::path dir = Workspace("mb_spare_gpr");
  ExpectRefused(dir, {"fit-gpr", "t.csv", "--disturbance-column", "d", "-o", "t.csv"}, "t.csv",
                "-o t.csv is the input LOG t.csv");
  ExpectRefused(dir, {"predict-gpr", "m.json", "t.csv", "-o", "m.json"}, "m.json",
                "-o m.json is the input MODEL m.json");
  ExpectRefused(dir, {"predict-gpr", "m.json", "t.csv", "-o", "./t.csv"}, "t.csv",
                "-o ./t.csv is the input INPUT t.csv");
}

TEST(OutputsSpareInputs, CompareOntoItsDiagramOrMeasurement) {
  const fs::path dir = Workspace("mb_spare_compare");
  ExpectRefused(dir, {"compare", "d.json", "--measurement", "t.csv", "--suggest", "d.json"}, "d.json",
                "--suggest d.json is the input DIAGRAM d.json");
  ExpectRefused(dir, {"compare", "d.json", "--measurement", "t.csv", "--write-fitted", "d.json"}, "d.json",
                "--write-fitted d.json is the input DIAGRAM d.json");
  fs::copy_file(dir / "t.csv", dir / "out" / "compare.json");
  ExpectRefused(dir, {"compare", "d.json", "--measurement", "out/compare.json", "--out", "out"}, "out/compare.json",
                "--out out holds the input --measurement out/compare.json, and the command writes compare.json");
}

TEST(OutputsSpareInputs, RunOverItsInputLogAndFitOverItsDiagram) {
  const fs::path dir = Workspace("mb_spare_run_fit");
  fs::copy_file(dir / "t.csv", dir / "out" / "signals.csv");
  ExpectRefused(dir, {"run", "d.json", "--input", "f=out/signals.csv:force_N", "--out", "out"}, "out/signals.csv",
                "--out out holds the input --input out/signals.csv, and the command writes signals.csv");
  fs::copy_file(dir / "d.json", dir / "out" / "fitted.json");
  ExpectRefused(dir, {"fit", "out/fitted.json", "--measurement", "t.csv", "--out", "out"}, "out/fitted.json",
                "--out out holds the input DIAGRAM out/fitted.json, and the command writes fitted.json");
}

TEST(OutputsSpareInputs, ImproveOverItsImprovedDiagram) {
  const fs::path dir = Workspace("mb_spare_improve");
  fs::copy_file(dir / "d.json", dir / "out" / "improved.json");
  ExpectRefused(dir, {"improve", "out/improved.json", "--measurement", "t.csv", "--out", "out"}, "out/improved.json",
                "--out out holds the input DIAGRAM out/improved.json, and the command writes improved.json");
}

// Found by the hostile-input harness (tests/hostile): stability wrote its stability.json over the diagram it read.
TEST(OutputsSpareInputs, StabilityOverItsDiagramOrModelInItsOutputFolder) {
  const fs::path dir = Workspace("mb_spare_stability");
  fs::copy_file(dir / "d.json", dir / "out" / "stability.json");
  ExpectRefused(dir, {"stability", "out/stability.json", "--out", "out"}, "out/stability.json",
                "--out out holds the input DIAGRAM out/stability.json, and the command writes stability.json");
  fs::copy_file(dir / "m.json", dir / "out" / "report.html");
  ExpectRefused(dir, {"stability", "d.json", "--gpr", "out/report.html", "--out", "out"}, "out/report.html",
                "--out out holds the input --gpr out/report.html, and the command writes report.html");
}

// Found by tests/hostile: a sweep file kept in --out as runs.json was replaced by the results; hil named the board
// before the summary.json it would have written over its diagram.
TEST(OutputsSpareInputs, SweepOverItsSweepFileAndHilOverItsDiagram) {
  const fs::path dir = Workspace("mb_spare_sweep_hil");
  std::ofstream(dir / "out" / "runs.json") << R"({"grid": {"g.gain": [1.0, 2.0]}})" << "\n";
  ExpectRefused(dir, {"sweep", "d.json", "out/runs.json", "--out", "out"}, "out/runs.json",
                "--out out holds the input SWEEP out/runs.json, and the command writes runs.json");
  fs::copy_file(dir / "d.json", dir / "out" / "summary.json");
  ExpectRefused(dir, {"hil", "out/summary.json", "--board", "udp", "--port", "9", "--replace", "plant=d.json",
                      "--out", "out"},
                "out/summary.json", "--out out holds the input DIAGRAM out/summary.json, and the command writes "
                "summary.json");
}

}  // namespace
}  // namespace mb

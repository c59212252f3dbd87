// Resources are found relative to the diagram, the sweep file or the shipped data, never the working directory
// (issue 11): every case runs motionblocks from an unrelated temporary folder. What a command writes does not depend
// on it either: the plotting scripts in an output folder rerun from anywhere (issue 28).

#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "tests/tools/commands/run_motionblocks.h"

namespace mb {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using ::testing::AllOf;
using ::testing::HasSubstr;
using ::testing::Not;
using testing::CommandResult;
using testing::ProcessTempDir;
using testing::ReadJsonFile;
using testing::RunMotionblocksIn;
using testing::RunProgramIn;

std::string ReadText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

// project/: profile.csv (u = t), drive.json (from_file profile.csv → k → output connector "force"; a position
// ramp for compare), sweeps/gains.json naming "../drive.json"; elsewhere/: the working directory.
class WorkingDirectory : public ::testing::Test {
 protected:
  void SetUp() override {
    root_ = ProcessTempDir("mb_working_directory");
    fs::remove_all(root_);
    project_ = root_ / "project";
    elsewhere_ = root_ / "elsewhere";
    fs::create_directories(project_ / "sweeps");
    fs::create_directories(elsewhere_);
    std::ofstream profile(project_ / "profile.csv");
    std::ofstream measured(project_ / "measured.csv");
    profile << "time_s,u\n";
    measured << "time_s,position_m,force\n";
    for (int i = 0; i <= 200; ++i) {
      const double t = 0.001 * i;
      profile << t << "," << t << "\n";
      measured << t << "," << 0.01 * t << "," << 3.0 * t << "\n";  // force = 3·u: k.gain fits to 3
    }
    const json diagram = {
        {"schemaVersion", "1.0"},
        {"name", "drive"},
        {"defaultExperiment", {{"startTime", 0.0}, {"stopTime", 0.2}, {"stepSize", 0.001}}},
        {"solver", {{"type", "rk4"}, {"step", 0.001}}},
        {"connectors", {{{"name", "force"}, {"kind", "output"}, {"unit", "N"}}}},
        {"elements",
         {{{"name", "f"}, {"type", "from_file"}, {"parameters", {{"file", "profile.csv"}, {"column", "u"}}}},
          {{"name", "k"}, {"type", "gain"}, {"parameters", {{"gain", 1.0}}}}}},
        {"connections",
         {{{"startElement", "f"}, {"startConnector", "y"}, {"endElement", "k"}, {"endConnector", "u"}},
          {{"startElement", "k"}, {"startConnector", "y"}, {"endElement", ""}, {"endConnector", "force"}}}},
        {"log", {"k.y"}}};
    std::ofstream(project_ / "drive.json") << diagram.dump(2);
    const json sweep = {{"diagram", "../drive.json"}, {"list", {{{"k.gain", 2.0}}, {{"k.gain", 3.0}}}}};
    std::ofstream(project_ / "sweeps" / "gains.json") << sweep.dump(2);
  }
  void TearDown() override { fs::remove_all(root_); }
  fs::path root_, project_, elsewhere_;
};

// "../drive.json" lies outside the sweep file's folder: allowed with --allow-path, as for a diagram's own files.
TEST_F(WorkingDirectory, ASweepFileRunsTheDiagramItNamesRelativeToItself) {
  const CommandResult r =
      RunMotionblocksIn(elsewhere_, {"sweep", (project_ / "sweeps" / "gains.json").string(), "--allow-path",
                                     project_.string(), "--quiet", "--out", "o"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("2 runs (list): 2 run now, 0 already done, 0 failed"));
  EXPECT_TRUE(fs::exists(elsewhere_ / "o" / "runs.csv"));
}

TEST_F(WorkingDirectory, ASweepFileWithoutADiagramAsksForOne) {
  std::ofstream(project_ / "sweeps" / "bare.json") << json{{"list", {{{"k.gain", 2.0}}}}}.dump();
  const std::string sweep = (project_ / "sweeps" / "bare.json").string();
  const CommandResult r = RunMotionblocksIn(elsewhere_, {"sweep", sweep, "--quiet", "--out", "o"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("motionblocks: error: " + sweep + ": the sweep names no \"diagram\"; give the "
                                  "diagram: motionblocks sweep DIAGRAM " + sweep));
}

// The fitted diagram written into another folder names its profile from there (and says it lies outside).
TEST_F(WorkingDirectory, AFittedDiagramWrittenElsewhereStillFindsItsFile) {
  fs::create_directories(elsewhere_ / "fitted");  // --write-fitted writes a file; its folder must exist
  const CommandResult r = RunMotionblocksIn(
      elsewhere_, {"compare", (project_ / "drive.json").string(), "--measurement", (project_ / "measured.csv").string(),
                   "--fit", "k.gain", "--write-fitted", "fitted/drive.json", "--quiet", "--out", "o"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const json fitted = ReadJsonFile(elsewhere_ / "fitted" / "drive.json");
  EXPECT_EQ(fitted["elements"][0]["parameters"]["file"], "../../project/profile.csv");
  EXPECT_THAT(ReadJsonFile(elsewhere_ / "o" / "compare.json")["fitted_diagram_reads_outside_its_folder"].dump(),
              HasSubstr("f.file: ../../project/profile.csv"));
  // It runs from any folder once the profile's folder is allowed (a copy beside it would need nothing).
  const CommandResult run = RunMotionblocksIn(
      root_, {"run", (elsewhere_ / "fitted" / "drive.json").string(), "--allow-path", project_.string(), "--quiet",
              "--out", (elsewhere_ / "run").string()});
  EXPECT_EQ(run.exit_code, 0) << run.output;
}

// `reproduce` finds the paper's diagrams and sweeps in the shipped data, not in ./diagrams/paper.
TEST_F(WorkingDirectory, ReproduceFindsTheShippedDiagramsFromAnyFolder) {
  const CommandResult r =
      RunMotionblocksIn(elsewhere_, {"reproduce", "--quick", "--max-steps", "10", "--quiet", "--out", "o"});
  EXPECT_THAT(r.output, Not(HasSubstr("cannot open")));
  EXPECT_THAT(r.output, HasSubstr("--max-steps"));  // it got as far as the first scan, which the limit refuses
}

// Issue 28: an output folder holds what a user opens (report, JSON, CSV, pictures); what draws the pictures (gnuplot
// scripts and data, gnuplot's log, the diagram's DOT text) is in its plot/ folder, the scripts naming their files
// relative to themselves: moved elsewhere, `gnuplot x.gp` in plot/ or `gnuplot …/plot/x.gp` from any folder redraws
// the same PNG.
TEST_F(WorkingDirectory, AnOutputFolderHoldsWhatAUserOpensAndItsPlotScriptsRerunAnywhere) {
  const CommandResult run =
      RunMotionblocksIn(elsewhere_, {"run", (project_ / "drive.json").string(), "--quiet", "--out", "run"});
  ASSERT_EQ(run.exit_code, 0) << run.output;
  const CommandResult compare = RunMotionblocksIn(
      elsewhere_, {"compare", (project_ / "drive.json").string(), "--measurement", (project_ / "measured.csv").string(),
                   "--quiet", "--out", "compare"});
  ASSERT_EQ(compare.exit_code, 0) << compare.output;
  for (const char* name : {"run", "compare"}) {
    const fs::path out = elsewhere_ / name;
    std::vector<std::string> opened, drawing;
    for (const auto& entry : fs::directory_iterator(out)) {
      const std::string file = entry.path().filename().string(), ext = entry.path().extension().string();
      if (entry.is_directory()) {
        EXPECT_EQ(file, "plot") << name << ": a folder besides plot/";
      } else {
        EXPECT_TRUE(ext == ".html" || ext == ".json" || ext == ".csv" || ext == ".png" || ext == ".svg")
            << name << "/" << file << " is no file a user opens";
        opened.push_back(file);
      }
    }
    for (const auto& entry : fs::directory_iterator(out / "plot")) {
      const std::string ext = entry.path().extension().string();
      EXPECT_TRUE(ext == ".gp" || ext == ".dat" || ext == ".log" || ext == ".dot") << entry.path();
      drawing.push_back(entry.path().filename().string());
    }
    EXPECT_THAT(opened, ::testing::IsSupersetOf({"report.html", "diagram.svg"})) << name;
    EXPECT_THAT(drawing, ::testing::IsSupersetOf({"gnuplot.log", "diagram.dot"})) << name;
  }
  EXPECT_THAT(ReadText(elsewhere_ / "run" / "plot" / "signal_0.gp"),
              AllOf(HasSubstr("set output \"../signal_0.png\""), HasSubstr("plot \"signal_0.dat\" index 0"),
                    Not(HasSubstr(elsewhere_.string()))));

  // Moved, its PNG deleted: redrawn in plot/, then from an unrelated folder, each time the same picture.
  const fs::path moved = root_ / "moved";
  fs::rename(elsewhere_ / "run", moved);
  const std::string png = ReadText(moved / "signal_0.png");
  ASSERT_GT(png.size(), 1000u);
  fs::remove(moved / "signal_0.png");
  CommandResult gnuplot = RunProgramIn(moved / "plot", {"gnuplot", "signal_0.gp"});
  ASSERT_EQ(gnuplot.exit_code, 0) << gnuplot.output;
  EXPECT_EQ(ReadText(moved / "signal_0.png"), png);
  fs::remove(moved / "signal_0.png");
  gnuplot = RunProgramIn(project_, {"gnuplot", (moved / "plot" / "signal_0.gp").string()});
  ASSERT_EQ(gnuplot.exit_code, 0) << gnuplot.output;
  EXPECT_EQ(ReadText(moved / "signal_0.png"), png);
  EXPECT_FALSE(fs::exists(project_ / "signal_0.png"));
  // The DOT text redraws the diagram there as well.
  const CommandResult dot = RunProgramIn(moved / "plot", {"dot", "-Tsvg", "-o", "../again.svg", "diagram.dot"});
  ASSERT_EQ(dot.exit_code, 0) << dot.output;
  EXPECT_EQ(ReadText(moved / "again.svg"), ReadText(moved / "diagram.svg"));
}

}  // namespace
}  // namespace mb

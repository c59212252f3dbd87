// A diagram from someone else, or a hostile output path, must not run anything: names, connectors and paths
// reach gnuplot only as data (issue 11). Each case also checks that the figures were drawn, so that the test
// fails if gnuplot is not run at all.

#include <filesystem>
#include <fstream>
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
using testing::CommandResult;
using testing::ProcessTempDir;
using testing::RunMotionblocksIn;
using ::testing::AnyOf;
using ::testing::HasSubstr;
using ::testing::Not;

const std::string kSource = MB_SOURCE_DIR;

// Names that a shell or gnuplot would run if they were pasted into a command or a double-quoted string.
const std::vector<std::string> kHostileNames = {
    "p`touch pwned_backquote`", "q$(touch pwned_dollar)", "r'\nsystem('touch pwned_newline')\n#", "s\"`touch pwned_dq`\""};

// The files a hostile string would have created in `dir`.
std::vector<std::string> Pwned(const fs::path& dir) {
  std::vector<std::string> found;
  for (const auto& e : fs::recursive_directory_iterator(dir)) {
    if (e.path().filename().string().rfind("pwned", 0) == 0) found.push_back(e.path().string());
  }
  return found;
}

bool HasPng(const fs::path& dir) {
  for (const auto& e : fs::directory_iterator(dir)) {
    if (e.path().extension() == ".png" && fs::file_size(e.path()) > 0) return true;
  }
  return false;
}

TEST(UntrustedInput, RunDrawsElementNamesAndTheOutputPathAsText) {
  const fs::path dir = ProcessTempDir("mb_untrusted_run");
  fs::remove_all(dir);
  fs::create_directories(dir);
  json elements = json::array(), log = json::array();
  for (const auto& name : kHostileNames) {
    elements.push_back({{"name", name}, {"type", "constant"}, {"parameters", {{"value", 1.0}}}});
    log.push_back(name + ".y");
  }
  const json diagram = {{"schemaVersion", "1.0"},
                        {"name", "hostile`touch pwned_title`"},
                        {"defaultExperiment", {{"startTime", 0.0}, {"stopTime", 0.01}}},
                        {"solver", {{"type", "rk4"}, {"step", 0.001}}},
                        {"elements", elements},
                        {"log", log}};
  std::ofstream(dir / "d.json") << diagram.dump(1);
  const std::string out = "x$(touch pwned_out)`touch pwned_out2`";
  const CommandResult r = RunMotionblocksIn(dir, {"run", "d.json", "--out", out});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(Pwned(dir), ::testing::IsEmpty());
  ASSERT_TRUE(fs::exists(dir / out / "report.html")) << "the output folder is taken literally";
  EXPECT_TRUE(HasPng(dir / out)) << r.output;
  fs::remove_all(dir);
}

TEST(UntrustedInput, CompareDrawsAHostileOutputConnectorAsText) {
  const fs::path dir = ProcessTempDir("mb_untrusted_compare");
  fs::remove_all(dir);
  fs::create_directories(dir);
  json diagram;
  std::ifstream(kSource + "/diagrams/emps/rigid_body.json") >> diagram;
  const std::string connector = "f`touch pwned_connector`$(touch pwned_connector2)";
  for (auto& c : diagram["connectors"]) {
    if (c["name"] == "force") c["name"] = connector;
  }
  for (auto& c : diagram["connections"]) {
    if (c.value("endConnector", "") == "force" && !c.contains("endElement")) c["endConnector"] = connector;
  }
  diagram.erase("$schema");
  std::ofstream(dir / "d.json") << diagram.dump(1);
  {  // the first 3 s of the EMPS record
    std::ifstream in(kSource + "/diagrams/emps/data/DATA_EMPS.csv");
    std::ofstream f(dir / "log.csv");
    std::string line;
    for (int i = 0; i < 3001 && std::getline(in, line); ++i) f << line << "\n";
  }
  const std::string out = "o$(touch pwned_out)";
  const CommandResult r = RunMotionblocksIn(
      dir, {"compare", "d.json", "--measurement", "log.csv", "--no-gpr-fallback", "--out", out});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(Pwned(dir), ::testing::IsEmpty());
  EXPECT_TRUE(HasPng(dir / out)) << r.output;
  fs::remove_all(dir);
}

TEST(UntrustedInput, StabilityTakesTheOutputPathLiterally) {
  const fs::path dir = ProcessTempDir("mb_untrusted_stability");
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::string out = "s$(touch pwned_out)`touch pwned_out2`";
  const CommandResult r = RunMotionblocksIn(
      dir, {"stability", kSource + "/diagrams/paper/conventional.json", "--bode-points", "10", "--out", out});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(Pwned(dir), ::testing::IsEmpty());
  EXPECT_TRUE(HasPng(dir / out)) << r.output;
  fs::remove_all(dir);
}

TEST(UntrustedInput, AllowPathLetsADiagramReadAFolderTheUserTrusts) {
  const fs::path dir = ProcessTempDir("mb_untrusted_allow");
  fs::remove_all(dir);
  fs::create_directories(dir / "diagram");
  fs::create_directories(dir / "profiles");
  std::ofstream(dir / "profiles" / "p.csv") << "time_s,y\n0,1\n1,2\n";
  const json diagram = {
      {"schemaVersion", "1.0"},
      {"name", "allow"},
      {"defaultExperiment", {{"startTime", 0.0}, {"stopTime", 0.01}}},
      {"solver", {{"type", "rk4"}, {"step", 0.001}}},
      {"elements", {{{"name", "f"}, {"type", "from_file"}, {"parameters", {{"file", "../profiles/p.csv"}, {"column", "y"}}}}}},
      {"log", {"f.y"}}};
  std::ofstream(dir / "diagram" / "d.json") << diagram.dump(1);
  CommandResult r = RunMotionblocksIn(dir, {"run", "diagram/d.json", "--out", "o"});
  EXPECT_NE(r.exit_code, 0);
  EXPECT_THAT(r.output, ::testing::HasSubstr("outside the diagram's folder"));
  r = RunMotionblocksIn(dir, {"run", "diagram/d.json", "--out", "o", "--allow-path", "profiles"});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  fs::remove_all(dir);
}

// A diagram of constant elements named `names` (each logged), itself named `name`, run 10 ms with rk4.
json ConstantsDiagram(const std::string& name, const std::vector<std::string>& names) {
  json elements = json::array(), log = json::array();
  for (std::size_t i = 0; i < names.size(); ++i) {
    elements.push_back({{"name", names[i]}, {"type", "constant"}, {"parameters", {{"value", 1.0 + double(i)}}}});
    log.push_back(names[i] + ".y");
  }
  return {{"schemaVersion", "1.0"},
          {"name", name},
          {"defaultExperiment", {{"startTime", 0.0}, {"stopTime", 0.01}}},
          {"solver", {{"type", "rk4"}, {"step", 0.001}}},
          {"elements", elements},
          {"log", log}};
}

// signal_0.png … signal_<count − 1>.png drawn in `out` (not empty: gnuplot opens the file before it reads the plot).
void ExpectEverySignalFigure(const fs::path& out, std::size_t count, const std::string& output) {
  for (std::size_t i = 0; i < count; ++i) {
    const fs::path png = out / ("signal_" + std::to_string(i) + ".png");
    EXPECT_TRUE(fs::exists(png) && fs::file_size(png) > 0) << png << "\n" << output;
  }
}

// gnuplot 5.4 reads the single-quoted '''a' as a syntax error, and the figure of a signal named 'a was lost: every
// name now reaches gnuplot as a string of octal escapes.
TEST(UntrustedInput, EveryNameKeepsItsFigureWhateverItsCharacters) {
  const fs::path dir = ProcessTempDir("mb_untrusted_names");
  fs::remove_all(dir);
  fs::create_directories(dir);
  const std::vector<std::string> names = {"'a", "'", "''b'", "'é", "\"c", "d\\", "e@f", "g`h", "'$i", "#j"};
  std::ofstream(dir / "d.json") << ConstantsDiagram("'names", names).dump(1);
  const CommandResult r = RunMotionblocksIn(dir, {"run", "d.json", "--out", "o"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  ExpectEverySignalFigure(dir / "o", names.size(), r.output);
  fs::remove_all(dir);
}

TEST(UntrustedInput, AnOutputFolderWithANewlineOrAQuoteKeepsItsFigures) {
  const fs::path dir = ProcessTempDir("mb_untrusted_out_newline");
  fs::remove_all(dir);
  fs::create_directories(dir);
  std::ofstream(dir / "d.json") << ConstantsDiagram("n", {"a", "b"}).dump(1);
  for (const std::string out : {"o\nx", "'o\t\"y"}) {
    const CommandResult r = RunMotionblocksIn(dir, {"run", "d.json", "--out", out});
    ASSERT_EQ(r.exit_code, 0) << r.output;
    ExpectEverySignalFigure(dir / out, 2, r.output);
  }
  fs::remove_all(dir);
}

// ESC, BEL and CR from a diagram reach neither stdout (a metric's name) nor a message (the names an error lists) raw.
TEST(UntrustedInput, ControlBytesFromADiagramReachTheTerminalEscaped) {
  const fs::path dir = ProcessTempDir("mb_untrusted_escapes");
  fs::remove_all(dir);
  fs::create_directories(dir);
  json diagram = ConstantsDiagram("t\x1b]0;title\x07", {"b\x1b[31mred\r", "c"});
  diagram["metrics"] = json::array({{{"name", "m\x1b[2J\x07"}, {"type", "final"}, {"signal", "c.y"}}});
  std::ofstream(dir / "d.json") << diagram.dump(1);
  CommandResult r = RunMotionblocksIn(dir, {"run", "d.json", "--out", "o"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(r.output, HasSubstr("m\\x1b[2J\\x07 = 2"));
  EXPECT_THAT(r.output, Not(AnyOf(HasSubstr("\x1b"), HasSubstr("\x07"), HasSubstr("\r"))));
  r = RunMotionblocksIn(dir, {"run", "d.json", "--set", "x\x1b[1m.value=3", "--out", "o"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("x\\x1b[1m"));
  EXPECT_THAT(r.output, HasSubstr("b\\x1b[31mred\\x0d"));
  EXPECT_THAT(r.output, Not(AnyOf(HasSubstr("\x1b"), HasSubstr("\x07"), HasSubstr("\r"))));
  fs::remove_all(dir);
}

// A sweep file from someone else opens no diagram outside its folder, as a diagram's own file names (issue 30):
// "../../../../etc/passwd" is refused before it is opened (no JSON error quoting it); --allow-path lets one in.
TEST(UntrustedInput, ASweepFileOpensNoDiagramOutsideItsFolder) {
  const fs::path dir = ProcessTempDir("mb_untrusted_sweep_path");
  fs::remove_all(dir);
  fs::create_directories(dir / "sweeps");
  std::ofstream(dir / "d.json") << ConstantsDiagram("d", {"k"}).dump(1);
  const json list = {{{"k.value", 2.0}}};
  std::ofstream(dir / "sweeps" / "passwd.json") << json{{"diagram", "../../../../../../../../etc/passwd"}, {"list", list}};
  std::ofstream(dir / "sweeps" / "up.json") << json{{"diagram", "../d.json"}, {"list", list}};
  CommandResult r = RunMotionblocksIn(dir, {"sweep", "sweeps/passwd.json", "--quiet", "--out", "o"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("sweeps/passwd.json: its \"diagram\" \"../../../../../../../../etc/passwd\" resolves "
                                  "to /etc/passwd, outside the sweep file's folder"));
  EXPECT_THAT(r.output, HasSubstr("--allow-path /etc"));
  EXPECT_THAT(r.output, Not(AnyOf(HasSubstr("JSON"), HasSubstr("root"))));
  r = RunMotionblocksIn(dir, {"sweep", "sweeps/up.json", "--quiet", "--out", "o"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("outside the sweep file's folder"));
  EXPECT_FALSE(fs::exists(dir / "o" / "runs.csv"));
  r = RunMotionblocksIn(dir, {"sweep", "sweeps/up.json", "--allow-path", ".", "--quiet", "--out", "o"});
  EXPECT_EQ(r.exit_code, 0) << r.output;
  r = RunMotionblocksIn(dir, {"sweep", "d.json", "sweeps/passwd.json", "--quiet", "--out", "o2"});
  EXPECT_EQ(r.exit_code, 0) << "a diagram given on the command line is the user's choice\n" << r.output;
  fs::remove_all(dir);
}

}  // namespace
}  // namespace mb

// motionblocks draw: the picture of a diagram in each format, the default file name, the exit codes (0 drawn;
// 2 for a refused algebraic loop — drawn, highlighted — and for every other fault of the diagram, not drawn), and
// the run report's drawing.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <string>

#include "tests/tools/commands/run_motionblocks.h"

namespace mb {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using testing::ProcessTempDir;
using testing::RunMotionblocksIn;

const std::string kHil = std::string(MB_SOURCE_DIR) + "/diagrams/hil/pd_rigid_body.json";

std::string ReadText(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

fs::path FreshDir(const std::string& name) {
  const fs::path dir = ProcessTempDir(name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

TEST(DrawCommand, DrawsASvgNamedAfterTheDiagramByDefault) {
  const fs::path dir = FreshDir("mb_draw_default");
  const auto r = RunMotionblocksIn(dir, {"draw", kHil});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(r.output, "wrote pd_rigid_body.svg\n");
  const std::string svg = ReadText(dir / "pd_rigid_body.svg");
  EXPECT_THAT(svg, HasSubstr("<svg"));
  EXPECT_THAT(svg, HasSubstr(">controller</text>"));
  EXPECT_THAT(svg, HasSubstr(">pd_controller</text>"));
  EXPECT_THAT(svg, HasSubstr("<title>cluster_0</title>"));  // the plant subsystem
  EXPECT_THAT(svg, HasSubstr(">plant</text>"));
  EXPECT_THAT(svg, HasSubstr(">discrete, Ts = 0.001 s</text>"));
  fs::remove_all(dir);
}

TEST(DrawCommand, WritesDotOrPngWhereAsked) {
  const fs::path dir = FreshDir("mb_draw_formats");
  auto r = RunMotionblocksIn(dir, {"draw", kHil, "--format", "dot", "-o", "pd.dot", "--set", "controller.kp=100"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  const std::string dot = ReadText(dir / "pd.dot");
  EXPECT_THAT(dot, HasSubstr("digraph diagram {"));
  EXPECT_THAT(dot, HasSubstr("kp\\ =\\ 100\\n"));  // --set reaches the drawing
  r = RunMotionblocksIn(dir, {"draw", kHil, "--format", "png", "--output", (dir / "pd.png").string()});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_EQ(ReadText(dir / "pd.png").substr(0, 4), "\x89PNG");
  r = RunMotionblocksIn(dir, {"draw", kHil, "--format", "jpg"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("--format: jpg not in {svg,png,dot}"));
  fs::remove_all(dir);
}

// A diagram too large for a readable picture is refused for SVG/PNG at once (Graphviz ran for minutes on 100,000
// blocks; found by tests/hostile); its DOT source is still written.
TEST(DrawCommand, ADiagramOfThousandsOfBlocksIsRefusedAsAPictureButWrittenAsDot) {
  const fs::path dir = FreshDir("mb_draw_large");
  nlohmann::json d = {{"schemaVersion", "1.0"}, {"name", "chain"}, {"elements", nlohmann::json::array()},
                      {"connections", nlohmann::json::array()}};
  d["elements"].push_back({{"name", "b0"}, {"type", "constant"}, {"parameters", {{"value", 1.0}}}});
  for (int k = 1; k < 2500; ++k) {
    d["elements"].push_back({{"name", "b" + std::to_string(k)}, {"type", "gain"}, {"parameters", {{"gain", 1.0}}}});
    d["connections"].push_back({{"startElement", "b" + std::to_string(k - 1)}, {"startConnector", "y"},
                                {"endElement", "b" + std::to_string(k)}, {"endConnector", "u"}});
  }
  std::ofstream(dir / "chain.json") << d.dump();
  auto r = RunMotionblocksIn(dir, {"draw", "chain.json", "-o", "chain.svg"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("draw: chain has 2500 blocks, more than the 2000 a picture lays out"));
  EXPECT_FALSE(fs::exists(dir / "chain.svg"));
  r = RunMotionblocksIn(dir, {"draw", "chain.json", "--format", "dot", "-o", "chain.dot"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(ReadText(dir / "chain.dot"), HasSubstr("digraph diagram {"));
  fs::remove_all(dir);
}

TEST(DrawCommand, AnAlgebraicLoopIsDrawnHighlightedAndTheCommandFails) {
  const fs::path dir = FreshDir("mb_draw_loop");
  {
    std::ofstream out(dir / "loop.json");
    out << R"({"schemaVersion": "1.0", "name": "loop",
      "elements": [{"name": "c", "type": "constant"}, {"name": "a", "type": "sum"},
                   {"name": "k", "type": "gain", "parameters": {"gain": 0.5}}],
      "connections": [{"startElement": "c", "startConnector": "y", "endElement": "a", "endConnector": "u1"},
                      {"startElement": "k", "startConnector": "y", "endElement": "a", "endConnector": "u2"},
                      {"startElement": "a", "startConnector": "y", "endElement": "k", "endConnector": "u"}]})";
  }
  const auto r = RunMotionblocksIn(dir, {"draw", "loop.json", "--format", "dot"});
  EXPECT_EQ(r.exit_code, 2) << r.output;  // bad input, as run says of the same diagram
  EXPECT_THAT(r.output, HasSubstr("wrote loop.dot\n"));
  EXPECT_THAT(r.output, HasSubstr("draw: the algebraic loop is highlighted in the drawing\n"));
  EXPECT_THAT(r.output, HasSubstr("motionblocks: error: loop.json: algebraic loop through blocks [a, k]"));
  const std::string dot = ReadText(dir / "loop.dot");
  EXPECT_THAT(dot, HasSubstr("b1:o0 -> b2:i0 [color=\"#d62728\", penwidth=3];"));
  EXPECT_THAT(dot, HasSubstr("legend0 [label=\"algebraic loop\""));
  const auto run = RunMotionblocksIn(dir, {"run", "loop.json", "--quiet"});
  EXPECT_EQ(run.exit_code, 2);
  EXPECT_THAT(run.output, HasSubstr("algebraic loop through blocks [a, k]"));
  fs::remove_all(dir);
}

TEST(DrawCommand, ADiagramWithAnotherFaultIsNotDrawn) {
  const fs::path dir = FreshDir("mb_draw_bad");
  {
    std::ofstream out(dir / "bad.json");
    out << R"({"schemaVersion": "1.0", "elements": [{"name": "c", "type": "constnat"}], "connections": []})";
  }
  const auto r = RunMotionblocksIn(dir, {"draw", "bad.json"});
  EXPECT_EQ(r.exit_code, 2) << r.output;
  EXPECT_THAT(r.output, HasSubstr("motionblocks: error: bad.json"));
  EXPECT_THAT(r.output, HasSubstr("/elements/0/type: unknown block type 'constnat' in element 'c'; did you mean: constant"));
  EXPECT_FALSE(fs::exists(dir / "bad.svg"));
  fs::remove_all(dir);
}

TEST(DrawCommand, TheRunReportShowsTheDiagram) {
  const fs::path dir = FreshDir("mb_draw_run");
  const auto r = RunMotionblocksIn(dir, {"run", kHil, "--out", "out", "--quiet"});
  ASSERT_EQ(r.exit_code, 0) << r.output;
  EXPECT_THAT(ReadText(dir / "out" / "report.html"), HasSubstr("<a href=\"diagram.svg\">diagram.svg</a>"));
  EXPECT_THAT(ReadText(dir / "out" / "diagram.svg"), HasSubstr(">controller</text>"));
  EXPECT_THAT(ReadText(dir / "out" / "plot" / "diagram.dot"), HasSubstr("digraph diagram {"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace mb

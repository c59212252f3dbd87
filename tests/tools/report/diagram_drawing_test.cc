// The picture of a diagram (tools/report/diagram_drawing.h): what its DOT text holds (record nodes with ports,
// edges port to port, subsystems as clusters, sample-time colours and their legend, key parameters bounded), the
// escaping of hostile names (the text parses with Graphviz's dot and runs nothing), the highlighted algebraic loop,
// and improve's added elements; the clickable diagram of a report (tools/report/diagram_panel.h): each block's
// parameters with their SI values and units, hostile names kept as data.

#include "tools/report/diagram_drawing.h"
#include "tools/report/diagram_panel.h"

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>
#include <regex>
#include <string>

#include "engine/diagram_loader.h"
#include "engine/registry.h"
#include "tools/report/report.h"
#include "tools/report/run_program.h"
#include "tests/process_temp_dir.h"

namespace mb {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;
using ::testing::HasSubstr;
using ::testing::Not;

json Connect(const std::string& from, const std::string& to) {
  json c;
  const auto f = from.rfind('.'), t = to.rfind('.');
  if (f != std::string::npos) c["startElement"] = from.substr(0, f);
  c["startConnector"] = f == std::string::npos ? from : from.substr(f + 1);
  if (t != std::string::npos) c["endElement"] = to.substr(0, t);
  c["endConnector"] = t == std::string::npos ? to : to.substr(t + 1);
  return c;
}

// A PD loop at 1 ms around a rigid body in an inline subsystem, a second controller at 10 ms (another colour).
json PdLoop() {
  const json plant = {
      {"schemaVersion", "1.0"},
      {"connectors",
       {{{"name", "f"}, {"kind", "input"}, {"unit", "N"}}, {{"name", "x"}, {"kind", "output"}, {"unit", "m"}}}},
      {"elements", {{{"name", "body"}, {"type", "rigid_body"}, {"parameters", {{"mass", 0.2621}, {"damping", 3.0}}}}}},
      {"connections", {Connect("f", "body.f"), Connect("body.x", "x")}}};
  return {{"schemaVersion", "1.0"},
          {"name", "pd_loop"},
          {"connectors", {{{"name", "position"}, {"kind", "output"}, {"unit", "m"}}}},
          {"elements",
           {{{"name", "trajectory"}, {"type", "sine"}, {"parameters", {{"amplitude", 0.005}, {"frequency_hz", 2.0}}}},
            {{"name", "error"}, {"type", "sum"}, {"parameters", {{"signs", "+-"}}}},
            {{"name", "controller"},
             {"type", "pd_controller"},
             {"parameters", {{"kp", 9300.0}, {"kd", 69.0}, {"derivative_filter", 0.0005}}},
             {"sampleTime", {0.001, 0.0}}},
            {{"name", "monitor"}, {"type", "zero_order_hold"}, {"sampleTime", {0.01, 0.0}}},
            {{"name", "plant"}, {"type", "subsystem"}, {"diagram", plant}}}},
          {"connections",
           {Connect("trajectory.y", "error.u1"), Connect("plant.x", "error.u2"), Connect("error.y", "controller.e"),
            Connect("controller.u", "plant.f"), Connect("plant.x", "monitor.u"), Connect("plant.x", "position")}}};
}

std::string Dot(const json& diagram, const DrawingMarks& marks = {}) {
  return DiagramGraphvizString(BuildDiagram(diagram, "", "test.json"), marks);
}

// A folder of this process's own (ctest runs tests in parallel).
fs::path TempDir(const std::string& name) {
  const fs::path dir = mb::testing::ProcessTempDir(name);
  fs::remove_all(dir);
  fs::create_directories(dir);
  return dir;
}

std::string ReadText(const fs::path& path) {
  std::ifstream in(path);
  return std::string(std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>());
}

std::size_t Count(const std::string& text, const std::string& what) {
  std::size_t n = 0;
  for (auto at = text.find(what); at != std::string::npos; at = text.find(what, at + what.size())) ++n;
  return n;
}

TEST(DiagramDrawingTest, BlocksAreRecordsWithTheirPortsTypeAndKeyParameters) {
  const std::string dot = Dot(PdLoop());
  EXPECT_THAT(dot, HasSubstr("digraph diagram {"));
  EXPECT_THAT(dot, HasSubstr("label=\"pd_loop\""));
  // The sum: two input fields, the name and type, its non-default parameter, one output field.
  EXPECT_THAT(dot, HasSubstr("label=\"{{<i0> u1|<i1> u2}|error\\nsum\\nsigns\\ =\\ +-|{<o0> y}}\""));
  // The controller: only the parameters set to other values than their defaults, with units.
  EXPECT_THAT(dot, HasSubstr("controller\\npd_controller\\nkp\\ =\\ 9300\\nkd\\ =\\ 69\\nderivative_filter\\ =\\ "
                             "0.0005\\ s|{<o0> u}}"));
  EXPECT_THAT(dot, Not(HasSubstr("method")));  // at its default
  // A source has no input column.
  EXPECT_THAT(dot,
              HasSubstr("label=\"{trajectory\\nsine\\namplitude\\ =\\ 0.005\\nfrequency_hz\\ =\\ 2\\ Hz|{<o0> y}}\""));
  EXPECT_EQ(Count(dot, "shape=record"), 5u);
  EXPECT_EQ(Count(dot, "shape=cds"), 1u);  // the output connector
  EXPECT_THAT(dot, HasSubstr("label=\"position [m]\""));
}

TEST(DiagramDrawingTest, EdgesGoPortToPortAndSubsystemsAreClusters) {
  const Diagram d = BuildDiagram(PdLoop(), "", "test.json");
  const std::string dot = DiagramGraphvizString(d);
  const int error = d.FindBlock("error"), controller = d.FindBlock("controller"), body = d.FindBlock("plant/body");
  ASSERT_GE(body, 0);
  EXPECT_THAT(dot, HasSubstr(fmt::format("b{}:o0 -> b{}:i0;", error, controller)));
  EXPECT_THAT(dot, HasSubstr(fmt::format("b{}:o0 -> b{}:i0;", controller, body)));
  EXPECT_THAT(dot, HasSubstr(fmt::format("b{}:o0 -> b{}:i1;", body, error)));
  EXPECT_THAT(dot, HasSubstr(fmt::format("b{}:o0 -> o0;", body)));
  EXPECT_EQ(Count(dot, " -> b"), 5u);  // one edge per connected input port
  // The subsystem's element inside a cluster labelled with the subsystem's name, shown by its own name.
  const std::regex cluster("subgraph cluster_0 \\{\\n\\s*label=\"plant\";\\n\\s*style=rounded;\\n\\s*b" +
                           std::to_string(body) + " \\[shape=record[^\\n]*\\|body\\\\nrigid_body\\\\nmass");
  EXPECT_TRUE(std::regex_search(dot, cluster)) << dot;
}

TEST(DiagramDrawingTest, DiscreteBlocksAreColouredBySampleTimeWithALegend) {
  const Diagram d = BuildDiagram(PdLoop(), "", "test.json");
  const std::string dot = DiagramGraphvizString(d);
  const auto node = [&](const std::string& name) {
    const std::string id = fmt::format("b{} [", d.FindBlock(name));
    const auto at = dot.find(id);
    return at == std::string::npos ? std::string() : dot.substr(at, dot.find('\n', at) - at);
  };
  EXPECT_THAT(node("controller"), HasSubstr(fmt::format("fillcolor=\"{}\"", kSampleTimeColours[0])));
  EXPECT_THAT(node("monitor"), HasSubstr(fmt::format("fillcolor=\"{}\"", kSampleTimeColours[1])));
  EXPECT_THAT(node("plant/body"), HasSubstr("fillcolor=\"white\""));
  EXPECT_THAT(dot, HasSubstr(fmt::format("legend0 [label=\"discrete, Ts = 0.001 s\", fillcolor=\"{}\"]",
                                         kSampleTimeColours[0])));
  EXPECT_THAT(dot, HasSubstr(fmt::format("legend1 [label=\"discrete, Ts = 0.01 s\", fillcolor=\"{}\"]",
                                         kSampleTimeColours[1])));
  EXPECT_THAT(dot, Not(HasSubstr("algebraic loop")));
}

TEST(DiagramDrawingTest, KeyParametersAreBounded) {
  json j = PdLoop();
  j["elements"][0]["parameters"]["amplitude"] = 0.1234567891;  // numbers to 4 digits
  EXPECT_THAT(Dot(j), HasSubstr("{trajectory\\nsine\\namplitude\\ =\\ 0.1235\\nfrequency_hz\\ =\\ 2\\ Hz|"));
  // Seven parameters set: the first four in declared order, then how many more; a vector's first entries.
  j["elements"][4]["diagram"]["elements"][0] = {{"name", "body"},
                                                {"type", "linear_motor"},
                                                {"parameters",
                                                 {{"mass", 0.3},
                                                  {"damping", 2.0},
                                                  {"payload_mass", 0.1},
                                                  {"pole_pitch", 0.02},
                                                  {"cogging_harmonics", {1.0, 0.5, 0.25, 0.125}},
                                                  {"cogging_phases", {0.0, 0.0, 0.0, 0.0}},
                                                  {"coulomb_friction", 0.2}}}};
  j["elements"][4]["diagram"]["connections"][0]["endConnector"] = "u";
  const std::string dot = Dot(j);
  EXPECT_THAT(dot, HasSubstr("|body\\nlinear_motor\\nmass\\ =\\ 0.3\\ kg\\ndamping\\ =\\ 2\\ N*s/m\\npayload_mass\\ "
                             "=\\ 0.1\\ kg\\npole_pitch\\ =\\ 0.02\\ m\\n+\\ 3\\ more|"));
  j["elements"][4]["diagram"]["elements"][0]["parameters"] = {{"cogging_harmonics", {1.0, 0.5, 0.25, 0.125}},
                                                               {"cogging_phases", {0.0, 0.7, 1.9, 0.0}}};
  EXPECT_THAT(Dot(j), HasSubstr("|body\\nlinear_motor\\ncogging_harmonics\\ =\\ [1,\\ 0.5,\\ 0.25,\\ "
                                "…]\\ncogging_phases\\ =\\ [0,\\ 0.7,\\ 1.9,\\ …]\\ rad|"));
}

// Names that break a DOT file, a record label or a shell if pasted into one.
const char* const kHostileNames[] = {
    "a\"b",           "x<y>",           "{z}|w",       "back\\slash",      "ends\\",
    "$(touch PWNED)", "`touch PWNED2`", "two  spaces", "semi;colon -> b0", "\\N\\G\\n"};

TEST(DiagramDrawingTest, HostileNamesAreEscapedAndTheTextParsesWithDot) {
  json j = {{"schemaVersion", "1.0"},
            {"name", "evil \" } name \\"},
            {"elements", json::array()},
            {"connections", json::array()}};
  std::string previous;
  for (const char* name : kHostileNames) {
    j["elements"].push_back({{"name", name}, {"type", "gain"}, {"parameters", {{"gain", 2.0}}}});
    j["connections"].push_back(previous.empty()
                                   ? json{{"startConnector", "in\"put"}, {"endElement", name}, {"endConnector", "u"}}
                                   : Connect(previous + ".y", std::string(name) + ".u"));
    previous = name;
  }
  j["connectors"] = {{{"name", "in\"put"}, {"kind", "input"}, {"unit", "N"}},
                     {{"name", "out}put\\"}, {"kind", "output"}}};
  j["connections"].push_back(Connect(previous + ".y", "out}put\\"));
  const std::string dot = Dot(j);
  const fs::path dir = TempDir("diagram_drawing_hostile");
  WriteDrawing(dot, DrawingFormat::kDot, dir / "hostile.dot");
  // dot parses the text: every block one node, every connection one edge, and each name shown as written.
  ASSERT_EQ(RunProgram({"dot", "-Tsvg", "-o", (dir / "hostile.svg").string(), (dir / "hostile.dot").string()},
                       dir / "dot.log"),
            0)
      << ReadText(dir / "dot.log") << "\n"
      << dot;
  EXPECT_EQ(ReadText(dir / "dot.log"), "");  // no warning either (a broken record label warns)
  const std::string svg = ReadText(dir / "hostile.svg");
  EXPECT_EQ(Count(svg, "class=\"node\""), std::size(kHostileNames) + 2);
  EXPECT_EQ(Count(svg, "class=\"edge\""), std::size(kHostileNames) + 1);
  for (const std::string shown :
       {"a&quot;b", "x&lt;y&gt;", "{z}|w", "back\\slash", "ends\\", "$(touch PWNED)", "`touch PWNED2`", "two &#160;spaces",
        "semi;colon &#45;&gt; b0", "\\N\\G\\n", "in&quot;put [N]", "out}put\\", "evil &quot; } name \\"}) {
    EXPECT_THAT(svg, HasSubstr(">" + shown + "<")) << shown;
  }
  EXPECT_FALSE(fs::exists("PWNED"));
  EXPECT_FALSE(fs::exists("PWNED2"));
  EXPECT_FALSE(fs::exists(dir / "PWNED"));
}

TEST(DiagramDrawingTest, LongNamesAndValuesAreCutAtACharacterBoundary) {
  json j = PdLoop();
  const std::string long_name = "µ" + std::string(100, 'n');
  j["elements"][1]["name"] = long_name;
  for (auto& c : j["connections"]) {
    if (c.value("startElement", "") == "error") c["startElement"] = long_name;
    if (c.value("endElement", "") == "error") c["endElement"] = long_name;
  }
  const std::string dot = Dot(j);
  EXPECT_THAT(dot, HasSubstr("µ" + std::string(46, 'n') + "…\\nsum"));  // 48 bytes: µ is two
  EXPECT_THAT(dot, Not(HasSubstr(std::string(47, 'n'))));
}

// c → a (sum) ⇄ k (gain): a cycle of direct feedthrough, refused by BuildDiagram, drawn by InspectDiagram.
json Loop() {
  return {{"schemaVersion", "1.0"},
          {"elements",
           {{{"name", "c"}, {"type", "constant"}},
            {{"name", "a"}, {"type", "sum"}},
            {{"name", "k"}, {"type", "gain"}, {"parameters", {{"gain", 0.5}}}}}},
          {"connections", {Connect("c.y", "a.u1"), Connect("k.y", "a.u2"), Connect("a.y", "k.u")}}};
}

TEST(DiagramDrawingTest, TheRefusedAlgebraicLoopIsHighlighted) {
  EXPECT_THROW(BuildDiagram(Loop(), "", "loop.json"), AlgebraicLoopError);  // the loader still refuses it
  const InspectedDiagram inspected = InspectDiagram(Loop(), "", "loop.json");
  ASSERT_TRUE(inspected.algebraic_loop.has_value());
  EXPECT_THAT(inspected.algebraic_loop->what(), HasSubstr("loop.json: algebraic loop through blocks [a, k]"));
  EXPECT_TRUE(inspected.diagram.execution_order().empty());
  DrawingMarks marks;
  marks.algebraic_loop = inspected.algebraic_loop->cycle();
  const std::string dot = DiagramGraphvizString(inspected.diagram, marks);
  const std::string red = fmt::format("color=\"{}\", penwidth=3", kAlgebraicLoopColour);
  EXPECT_THAT(dot, HasSubstr("b1 [shape=record, style=\"filled,bold\", fillcolor=\"white\", color=\"" +
                             std::string(kAlgebraicLoopColour) + "\", penwidth=3"));
  EXPECT_THAT(dot, HasSubstr("b2 [shape=record, style=\"filled,bold\""));
  EXPECT_THAT(dot, HasSubstr("b0 [shape=record, style=\"filled\", fillcolor=\"white\", color=\"black\", penwidth=1"));
  EXPECT_THAT(dot, HasSubstr("b2:o0 -> b1:i1 [" + red + "];"));
  EXPECT_THAT(dot, HasSubstr("b1:o0 -> b2:i0 [" + red + "];"));
  EXPECT_THAT(dot, HasSubstr("b0:o0 -> b1:i0;"));  // into the loop, not part of it
  EXPECT_THAT(dot, HasSubstr("legend0 [label=\"algebraic loop\", fillcolor=white, " + red + "]"));
}

TEST(DiagramDrawingTest, InspectDiagramStillRefusesEveryOtherFault) {
  json j = Loop();
  j["elements"][2]["type"] = "gian";
  EXPECT_THROW(InspectDiagram(j, "", "loop.json"), DiagramError);
}

TEST(DiagramDrawingTest, AddedElementsAreDrawnInTheirOwnColourWithTheirLegend) {
  DrawingMarks marks;
  marks.added = {"controller"};
  marks.added_label = "added by improve";
  const std::string dot = Dot(PdLoop(), marks);
  EXPECT_THAT(dot, HasSubstr(fmt::format("style=\"filled,bold\", fillcolor=\"{}\", color=\"{}\", penwidth=3",
                                         kSampleTimeColours[0], kAddedColour)));
  EXPECT_EQ(Count(dot, std::string("color=\"") + kAddedColour), 2u);  // the block and its legend entry
  EXPECT_THAT(dot, HasSubstr("label=\"added by improve\""));
}

TEST(DiagramDrawingTest, WriteDrawingRendersSvgAndPngWithDot) {
  const fs::path dir = TempDir("diagram_drawing_write");
  const std::string dot = Dot(PdLoop());
  WriteDrawing(dot, DrawingFormat::kSvg, dir / "loop.svg");
  WriteDrawing(dot, DrawingFormat::kPng, dir / "loop.png");
  EXPECT_THAT(ReadText(dir / "loop.svg"), HasSubstr("<svg"));
  EXPECT_EQ(ReadText(dir / "loop.png").substr(1, 3), "PNG");
  EXPECT_THROW(WriteDrawing(dot, DrawingFormat::kSvg, dir), std::runtime_error);  // a folder is never replaced
  EXPECT_EQ(ParseDrawingFormat("png"), DrawingFormat::kPng);
  try {
    ParseDrawingFormat("jpg");
    FAIL();
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "--format jpg: unknown; choose svg, png or dot");
  }
}

TEST(DiagramDrawingTest, AReportShowsTheDiagramOrSaysWhyNot) {
  const fs::path dir = TempDir("diagram_drawing_report");
  HtmlReport report("r");
  AddDiagramDrawing(&report, PdLoop(), "", "test.json", {}, dir);
  json broken = PdLoop();
  broken["elements"][0]["type"] = "sien";
  AddDiagramDrawing(&report, broken, "", "broken.json", {}, dir, "broken");
  report.Write(dir / "report.html");
  const std::string html = ReadText(dir / "report.html");
  EXPECT_THAT(html, HasSubstr("<figure class=\"mb-diagram\">"));  // inline, clickable (diagram_panel.h)
  EXPECT_THAT(html, HasSubstr("<a href=\"diagram.svg\">diagram.svg</a>"));
  EXPECT_THAT(ReadText(dir / "diagram.svg"), HasSubstr(">controller</text>"));
  EXPECT_THAT(ReadText(dir / "plot" / "diagram.dot"), HasSubstr("digraph diagram"));
  EXPECT_THAT(html, HasSubstr("<p class=\"warn\">Diagram drawing missing: broken.json"));
  EXPECT_FALSE(fs::exists(dir / "broken.svg"));
}

// The entry of DiagramBlockData named `name`, or null.
const json* BlockEntry(const json& blocks, const std::string& name) {
  for (const auto& b : blocks) {
    if (b["name"] == name) return &b;
  }
  return nullptr;
}

// The parameter `name` of a DiagramBlockData entry, or null.
const json* ParameterOf(const json& block, const std::string& name) {
  for (const auto& p : block["parameters"]) {
    if (p["name"] == name) return &p;
  }
  return nullptr;
}

TEST(DiagramPanelTest, EachBlockCarriesEveryParameterWithItsSiValueAndUnit) {
  json j = PdLoop();
  j["elements"][4]["diagram"]["elements"][0]["parameters"]["mass"] = {{"value", 262.1}, {"unit", "g"}};
  const json blocks = DiagramBlockData(BuildDiagram(j, "", "test.json"));
  ASSERT_EQ(blocks.size(), 5u);  // trajectory, error, controller, monitor, plant/body
  const json* body = BlockEntry(blocks, "plant/body");
  ASSERT_NE(body, nullptr) << blocks.dump(1);
  EXPECT_EQ((*body)["type"], "rigid_body");
  const json* mass = ParameterOf(*body, "mass");
  ASSERT_NE(mass, nullptr);
  EXPECT_EQ((*mass)["value"], "0.2621");  // written in g, shown in SI
  EXPECT_EQ((*mass)["unit"], "kg");
  EXPECT_EQ((*mass)["default"], false);
  const json* damping = ParameterOf(*body, "damping");
  ASSERT_NE(damping, nullptr);
  EXPECT_EQ((*damping)["value"], "3");
  EXPECT_EQ((*damping)["unit"], "N·s/m");
  const json* controller = BlockEntry(blocks, "controller");
  ASSERT_NE(controller, nullptr);
  EXPECT_EQ((*controller)["type"], "pd_controller");
  const json* filter = ParameterOf(*controller, "derivative_filter");
  ASSERT_NE(filter, nullptr);
  EXPECT_EQ((*filter)["value"], "0.0005");
  EXPECT_EQ((*filter)["unit"], "s");
  EXPECT_EQ((*ParameterOf(*controller, "kp"))["unit"], "");  // dimensionless as declared: no unit
  // Every parameter, defaults included (flagged): sine's phase is not in the diagram.
  const json* trajectory = BlockEntry(blocks, "trajectory");
  ASSERT_NE(trajectory, nullptr);
  const json* phase = ParameterOf(*trajectory, "phase");
  ASSERT_NE(phase, nullptr);
  EXPECT_EQ((*phase)["value"], "0");
  EXPECT_EQ((*phase)["unit"], "rad");
  EXPECT_EQ((*phase)["default"], true);
  EXPECT_EQ((*trajectory)["parameters"].size(), BlockRegistry::Global().Find("sine")->parameters.size());
  EXPECT_EQ((*BlockEntry(blocks, "error"))["parameters"][0]["value"], "+-");
}

TEST(DiagramPanelTest, AReportEmbedsTheClickableDiagramWithHostileNamesAsData) {
  const std::string hostile = "<svg onload=alert(1)><script>alert(2)<!--\"'";
  json j = {{"schemaVersion", "1.0"},
            {"name", "h"},
            {"connectors", {{{"name", "in"}, {"kind", "input"}}, {{"name", "out"}, {"kind", "output"}}}},
            {"elements", {{{"name", hostile}, {"type", "gain"}, {"parameters", {{"gain", 2.5}}}}}},
            {"connections", {Connect("in", hostile + ".u"), Connect(hostile + ".y", "out")}}};
  const fs::path dir = TempDir("diagram_panel_hostile");
  HtmlReport report("r");
  AddDiagramDrawing(&report, j, "", "hostile.json", {}, dir);
  report.Write(dir / "report.html");
  const std::string html = ReadText(dir / "report.html");
  EXPECT_THAT(html, Not(HasSubstr("<script>alert")));
  EXPECT_THAT(html, Not(HasSubstr("<svg onload")));
  EXPECT_EQ(Count(html, "<script"), 2u);  // the block data and the panel's script, nothing else
  EXPECT_EQ(Count(html, "<svg"), 1u);
  EXPECT_THAT(html, HasSubstr("\\u003csvg onload=alert(1)>\\u003cscript>alert(2)\\u003c!--"));  // in the JSON
  EXPECT_THAT(html, HasSubstr(">&lt;svg onload=alert(1)&gt;&lt;script&gt;alert(2)&lt;!"));      // in the picture
  // The block data, read back as the page reads it, holds the name exactly.
  const std::string start = "<script type=\"application/json\" class=\"mb-blocks\">";
  const std::size_t begin = html.find(start);
  ASSERT_NE(begin, std::string::npos);
  const std::size_t end = html.find("</script>", begin + start.size());
  const json blocks = json::parse(html.substr(begin + start.size(), end - begin - start.size()));
  ASSERT_EQ(blocks.size(), 1u);
  EXPECT_EQ(blocks[0]["name"], hostile);
  EXPECT_EQ(blocks[0]["parameters"][0]["name"], "gain");
  EXPECT_EQ(blocks[0]["parameters"][0]["value"], "2.5");
  // The drawing's node of block 0 is "b0", the key the panel's script uses.
  EXPECT_THAT(html, HasSubstr("<title>b0</title>"));
}

TEST(DiagramPanelTest, InlineSvgKeepsTheSvgElementAndRefusesScript) {
  EXPECT_EQ(InlineSvg("<?xml version=\"1.0\"?>\n<!DOCTYPE svg>\n<svg width=\"1pt\"><text>a onclick=b</text></svg>\n"),
            "<svg width=\"1pt\"><text>a onclick=b</text></svg>");
  EXPECT_THROW(InlineSvg("no picture"), std::runtime_error);
  EXPECT_THROW(InlineSvg("<svg><script>x()</script></svg>"), std::runtime_error);
  EXPECT_THROW(InlineSvg("<svg><foreignObject></foreignObject></svg>"), std::runtime_error);
  EXPECT_THROW(InlineSvg("<svg><g ONLOAD = \"x()\"></g></svg>"), std::runtime_error);
}

}  // namespace
}  // namespace mb

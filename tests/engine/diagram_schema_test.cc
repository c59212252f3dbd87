// The generated diagram schema and its enforcement: misspelled keys, duplicate keys, duplicated entries and
// doubly connected connectors are errors with the JSON pointer of the file the user wrote (also inside
// subsystems) and a "did you mean" where a key is unknown.

#include <filesystem>
#include <fstream>

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "engine/diagram_document.h"
#include "engine/diagram_schema.h"
#include "engine/registry.h"
#include "engine/json_parsing.h"
#include "tests/engine/test_util.h"

namespace mb {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using ::testing::ElementsAre;
using ::testing::HasSubstr;
using testing::Build;
using testing::Connect;

using testing::MinimalDiagram;

std::vector<std::string> ProblemsOf(const json& j, const fs::path& base = ".") {
  try {
    BuildDiagram(j, base, "test.json");
  } catch (const DiagramError& e) {
    return e.problems();
  }
  return {"no DiagramError"};
}

/// A folder of this test's own, removed at the end.
class TempFolder {
 public:
  TempFolder() : path_(fs::temp_directory_path() / ("mb_schema_test_" + std::to_string(::getpid()))) {
    fs::create_directories(path_);
  }
  ~TempFolder() { fs::remove_all(path_); }
  fs::path Write(const std::string& name, const std::string& text) const {
    std::ofstream(path_ / name) << text;
    return path_ / name;
  }
  const fs::path& path() const { return path_; }

 private:
  fs::path path_;
};

TEST(DiagramSchemaTest, EveryBlockTypeWithItsParametersUnitsEnumsAndBounds) {
  const json schema = DiagramSchema(BlockRegistry::Global());
  const json& blocks = schema["definitions"]["blocks"];
  for (const auto& name : BlockRegistry::Global().TypeNames()) {
    ASSERT_TRUE(blocks.contains(name)) << name;
    for (const auto& p : BlockRegistry::Global().Find(name)->parameters) {
      EXPECT_TRUE(blocks[name]["properties"]["parameters"]["properties"].contains(p.name)) << name << "." << p.name;
    }
  }
  const json& cutoff = blocks["q_filter"]["properties"]["parameters"]["properties"]["cutoff_hz"];
  EXPECT_EQ(cutoff["default"], 30.0);
  EXPECT_EQ(cutoff["anyOf"][0], json({{"type", "number"}, {"minimum", 1e-9}, {"maximum", 1e12}}));
  // {"value", "unit"}: any unit string (the loader converts kHz, refuses another quantity: engine/units.h); the
  // bounds are checked after conversion, in Hz.
  EXPECT_EQ(cutoff["anyOf"][1]["properties"]["unit"],
            json({{"type", "string"}, {"description", "Hz or a unit of the same quantity (converted)"}}));
  EXPECT_EQ(cutoff["anyOf"][1]["properties"]["value"], json({{"type", "number"}}));
  EXPECT_EQ(blocks["friction"]["properties"]["parameters"]["properties"]["stick_model"]["anyOf"][0]["enum"],
            json({"karnopp", "none"}));
  EXPECT_EQ(blocks["unit_delay"]["required"], json::array({"sampleTime"}));
  EXPECT_EQ(blocks["gain"]["properties"]["sampleTime"], false);
  EXPECT_EQ(schema["properties"]["schemaVersion"]["const"], kDiagramSchemaVersion);
}

// Issue 28: a block type's ports without a diagram (built with its defaults), as `motionblocks blocks` and the schema
// show them; a type that needs a parameter without default is still listed.
TEST(BlockReferenceTest, PortsOfATypeBuiltWithItsDefaults) {
  const BlockRegistry& registry = BlockRegistry::Global();
  const BlockTypePorts body = DefaultPorts(registry.Get("rigid_body"));
  ASSERT_TRUE(body.known) << body.why_unknown;
  ASSERT_EQ(body.inputs.size(), 1u);
  EXPECT_EQ(body.inputs[0].name, "f");
  EXPECT_EQ(body.inputs[0].unit, "N");
  EXPECT_FALSE(body.inputs[0].direct_feedthrough);
  ASSERT_EQ(body.outputs.size(), 2u);
  EXPECT_EQ(body.outputs[1].name, "v");
  EXPECT_EQ(PortsSummary(body), "inputs f [N]; outputs x [m], v [m/s]");
  EXPECT_EQ(PortsSummary(DefaultPorts(registry.Get("gain"))), "inputs u [any, direct feedthrough]; outputs y [any]");
  // A discrete type is built with a 1 ms sample time; one with a required parameter says why its ports are unknown.
  EXPECT_TRUE(DefaultPorts(registry.Get("unit_delay")).known);
  const BlockTypePorts state_space = DefaultPorts(registry.Get("state_space"));
  EXPECT_FALSE(state_space.known);
  EXPECT_EQ(PortsSummary(state_space), "ports depend on parameters (no default for A, B, C)");
}

TEST(BlockReferenceTest, UnknownTypeSaysDidYouMean) {
  try {
    BlockRegistry::Global().Get("rigid_bdy");
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(),
                 "unknown block type 'rigid_bdy' (did you mean rigid_body?): `motionblocks blocks` lists them");
  }
  try {
    BlockRegistry::Global().Get("zzzzzzzzzzzzzzzzzzzz");
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "unknown block type 'zzzzzzzzzzzzzzzzzzzz': `motionblocks blocks` lists them");
  }
}

// Every type's example element is one a diagram accepts (type, parameters, sampleTime), and every type is listed.
TEST(BlockReferenceTest, EveryExampleElementIsAValidElement) {
  const BlockRegistry& registry = BlockRegistry::Global();
  for (const auto& name : registry.TypeNames()) {
    const BlockType& type = *registry.Find(name);
    const json example = ExampleElement(type);
    EXPECT_EQ(example["type"], name);
    ElementSpec spec{example["name"].get<std::string>(), name, example["parameters"], std::nullopt, ""};
    if (example.contains("sampleTime")) spec.sample_time = std::make_pair(example["sampleTime"].get<double>(), 0.0);
    DiagramDocument document(json::object());
    EXPECT_NO_THROW(document.Add(spec)) << name << ": " << example.dump();
    const std::string reference = BlockReference(type);
    EXPECT_EQ(reference.rfind(name + "\n", 0), 0u) << reference;
    EXPECT_THAT(reference, HasSubstr("  example: " + example.dump() + "\n")) << name;
    const BlockTypePorts ports = DefaultPorts(type);
    EXPECT_TRUE(ports.known || !ports.why_unknown.empty()) << name;
  }
  EXPECT_EQ(ExampleElement(registry.Get("state_space")),
            json::parse(R"({"name": "state_space", "type": "state_space",
                            "parameters": {"A": [1.0], "B": [1.0], "C": [1.0]}})"));
  EXPECT_EQ(ExampleElement(registry.Get("unit_delay"))["sampleTime"], 0.001);
  EXPECT_THAT(BlockReference(registry.Get("rigid_body")),
              HasSubstr("  ports (built with the default parameters):\n    input  0: f [N], no direct feedthrough\n"
                        "    output 0: x [m]\n    output 1: v [m/s]\n  parameters:\n"
                        "    - mass (number, kg) = 1.0: moving mass M > 0\n"));
}

TEST(DiagramSchemaTest, DocumentsEveryBlocksPortsForCompletion) {
  const json schema = DiagramSchema(BlockRegistry::Global());
  const std::string description = schema["definitions"]["blocks"]["rigid_body"]["description"];
  EXPECT_THAT(description, ::testing::EndsWith(" Ports: inputs f [N]; outputs x [m], v [m/s]."));
  const json& connection = schema["properties"]["connections"]["items"]["properties"];
  for (const char* input : {"f", "u", "u1", "u_c"}) {
    EXPECT_THAT(connection["endConnector"]["examples"], ::testing::Contains(input));
  }
  EXPECT_THAT(connection["startConnector"]["examples"], ::testing::Contains("v"));
  EXPECT_THAT(connection["startConnector"]["examples"], ::testing::Not(::testing::Contains("u_c")));  // inputs only
}

TEST(DiagramSchemaTest, CommittedSchemaIsTheGeneratedOne) {
  std::ifstream in(fs::path(MB_SOURCE_DIR) / "diagrams" / "schema.json");
  ASSERT_TRUE(in) << "diagrams/schema.json is missing";
  const json committed = json::parse(in);
  EXPECT_EQ(committed, DiagramSchema(BlockRegistry::Global()))
      << "diagrams/schema.json has drifted: regenerate it with `motionblocks schema > diagrams/schema.json`";
}

TEST(DiagramSchemaTest, MisspelledExperimentAndSolverKeysAreErrorsWithTheClosestKey) {
  json j = MinimalDiagram();
  j["defaultExperiment"] = {{"stopTme", 1.0}};
  j["solver"] = {{"tpye", "rk4"}, {"stepp", 1e-3}};
  EXPECT_THAT(ProblemsOf(j),
              ElementsAre("/defaultExperiment/stopTme: unknown key 'stopTme' (did you mean 'stopTime'?); the keys "
                          "here are: startTime, stepSize, stopTime",
                          "/solver/stepp: unknown key 'stepp' (did you mean 'step'?); the keys here are: atol, "
                          "maxStep, method, rtol, step, type",
                          "/solver/tpye: unknown key 'tpye' (did you mean 'type'?); the keys here are: atol, maxStep, "
                          "method, rtol, step, type"));
}

TEST(DiagramSchemaTest, MisspelledConnectionMetricAndTopLevelKeysAreErrors) {
  json j = MinimalDiagram();
  j["connections"][0].erase("endConnector");
  j["connections"][0]["endConector"] = "u";
  j["metrics"] = {{{"name", "m"}, {"signal", "g.y"}, {"tpye", "rmse"}}};
  j["elemnts"] = json::array();
  EXPECT_THAT(ProblemsOf(j),
              ElementsAre(HasSubstr("/connections/0/endConector: unknown key 'endConector' (did you mean "
                                    "'endConnector'?)"),
                          HasSubstr("/metrics/0/tpye: unknown key 'tpye' (did you mean 'type'?)"),
                          HasSubstr("/elemnts: unknown key 'elemnts' (did you mean 'elements'?)")));
}

TEST(DiagramSchemaTest, ExperimentModeIsOneOfTheModes) {
  json j = MinimalDiagram();
  j["experiment"] = {{"mode", "equation_eror"}};
  EXPECT_THAT(ProblemsOf(j), ElementsAre("/experiment/mode: \"equation_eror\" is not allowed here (did you mean "
                                         "\"equation_error\"?); use one of \"simulation\", \"equation_error\""));
}

TEST(DiagramSchemaTest, WrongTypesStopBeforeTheLoaderReadsThem) {
  json j = MinimalDiagram();
  j["elements"][0]["name"] = 5;
  j["solver"] = {{"type", 4}};
  EXPECT_THAT(ProblemsOf(j), ElementsAre("/elements/0/name: must be string, got an integer",
                                         "/solver/type: 4 is not allowed here; use one of \"euler\", \"rk4\", "
                                         "\"cvode\""));
}

TEST(DiagramSchemaTest, LoaderMessagesWinWhereItHasThem) {
  json j = MinimalDiagram();
  j["schemaVersion"] = "0.9";
  j["elements"][1]["parameters"]["gainn"] = 1;
  j["elements"][1]["descripton"] = "typo";
  EXPECT_THAT(ProblemsOf(j),
              ElementsAre("/schemaVersion: this build reads version \"1.0\", the file says \"0.9\"",
                          "/elements/1/parameters/gainn: unknown parameter 'gainn'; this block takes: gain, width "
                          "(element 'g', gain)",
                          HasSubstr("/elements/1/descripton: unknown key 'descripton' (did you mean 'description'?)")));
}

TEST(DiagramSchemaTest, DuplicatedFreeEntriesAreErrors) {
  json j = MinimalDiagram();
  j["free"] = {"g.gain", "c.value", "g.gain"};
  EXPECT_THAT(ProblemsOf(j), ElementsAre(HasSubstr("/free: Elements at indexes #0 and #2 violate uniqueness")));
}

TEST(DiagramSchemaTest, TwoConnectionsIntoOneOutputConnectorAreAnError) {
  json j = MinimalDiagram();
  j["connectors"] = {{{"name", "y"}, {"kind", "output"}}};
  j["connections"].push_back({{"startElement", "g"}, {"startConnector", "y"}, {"endConnector", "y"}});
  j["connections"].push_back({{"startElement", "c"}, {"startConnector", "y"}, {"endConnector", "y"}});
  EXPECT_THAT(ProblemsOf(j), ElementsAre("/connections/2: output connector 'y' is already connected "
                                         "(/connections/1); an output takes exactly one signal (use a sum block to "
                                         "add signals)"));
}

TEST(DiagramSchemaTest, ConnectionToAMissingOrInputConnectorIsAnError) {
  json j = MinimalDiagram();
  j["connectors"] = {{{"name", "u"}, {"kind", "input"}}, {{"name", "position"}, {"kind", "output"}}};
  j["connections"].push_back({{"startElement", "g"}, {"startConnector", "y"}, {"endConnector", "positon"}});
  j["connections"].push_back({{"startElement", "g"}, {"startConnector", "y"}, {"endConnector", "u"}});
  EXPECT_THAT(ProblemsOf(j),
              ElementsAre("/connections/1/endConnector: the diagram has no output connector 'positon' (did you mean "
                          "'position'?); a connection without endElement ends at one of the diagram's output "
                          "connectors: position",
                          "/connections/2/endConnector: the diagram has no output connector 'u'; a connection "
                          "without endElement ends at one of the diagram's output connectors: position",
                          "/connectors/1: output connector 'position' is connected to nothing"));
}

TEST(DiagramSchemaTest, TwoConnectionsIntoOneInputAreAnError) {
  json j = MinimalDiagram();
  j["connections"].push_back(Connect("c.y", "g.u"));
  EXPECT_THAT(ProblemsOf(j), ElementsAre("/connections/1: input 'g.u' is already connected; an input takes exactly "
                                         "one signal (use a sum block to add signals)"));
}

TEST(DiagramSchemaTest, DuplicateJsonKeysAreErrorsWithTheirPointer) {
  TempFolder folder;
  const fs::path file = folder.Write("dup.json", R"({"schemaVersion": "1.0",
    "defaultExperiment": {"stopTime": 1, "stopTime": 3},
    "elements": [{"name": "c", "type": "constant", "parameters": {"value": 1, "value": 2}}]})");
  try {
    ReadDiagramJson(file);
    FAIL() << "duplicate keys accepted";
  } catch (const DiagramError& e) {
    EXPECT_THAT(e.problems(),
                ElementsAre("/defaultExperiment/stopTime: the key 'stopTime' is given twice in one object (JSON keeps "
                            "only the last); remove one",
                            "/elements/0/parameters/value: the key 'value' is given twice in one object (JSON keeps "
                            "only the last); remove one"));
    EXPECT_THAT(std::string(e.what()), HasSubstr(file.string() + ": 2 problems in the diagram"));
  }
}

TEST(DiagramSchemaTest, ProblemsInsideASubsystemPointIntoTheSubsystemFile) {
  TempFolder folder;
  folder.Write("inner.json", R"({"schemaVersion": "1.0",
    "connectors": [{"name": "u", "kind": "input"}, {"name": "y", "kind": "output"}],
    "elements": [{"name": "k", "type": "gain", "parameters": {"gain": 2}},
                 {"name": "z", "type": "gain", "parameters": {"gainn": 2}}],
    "connections": [{"endElement": "k", "endConnector": "u", "startConnector": "u"},
                    {"startElement": "k", "startConnector": "y", "endElement": "z", "endConnector": "u"},
                    {"startElement": "z", "startConnector": "y", "endConnector": "y"}]})");
  json j = MinimalDiagram();
  const json sub = {{"name", "sub"}, {"type", "subsystem"}, {"diagram", "inner.json"}};
  j["elements"].insert(j["elements"].begin(), sub);
  j["elements"].push_back({{"name", "h"}, {"type", "gain"}, {"parameters", {{"gainx", 1}}}});
  j["connections"].push_back(Connect("g.y", "sub.u"));
  j["connections"].push_back(Connect("sub.y", "h.u"));
  const std::string inner = (folder.path() / "inner.json").string();
  EXPECT_THAT(ProblemsOf(j, folder.path()),
              ElementsAre(inner + ": /elements/1/parameters/gainn: unknown parameter 'gainn'; this block takes: "
                                  "gain, width (element 'sub/z', gain)",
                          "/elements/3/parameters/gainx: unknown parameter 'gainx'; this block takes: gain, width "
                          "(element 'h', gain)"));
}

// Subsystem files that include each other are refused naming the cycle of files; a chain deeper than 16 levels is
// refused naming where (both ended in the internal text "map::at"; issue 30, found again by tests/hostile).
TEST(DiagramSchemaTest, SubsystemFilesIncludingEachOtherAreACycleNamedByItsFiles) {
  TempFolder folder;
  const auto wrapper = [](const std::string& file) {
    return json{{"schemaVersion", "1.0"},
                {"connectors", json::array({{{"name", "y"}, {"kind", "output"}}})},
                {"elements", json::array({{{"name", "s"}, {"type", "subsystem"}, {"diagram", file}}})},
                {"connections", json::array({{{"startElement", "s"}, {"startConnector", "y"}, {"endConnector", "y"}}})}}
        .dump();
  };
  folder.Write("a.json", wrapper("b.json"));
  folder.Write("b.json", wrapper("a.json"));
  json j = MinimalDiagram();
  j["elements"].push_back({{"name", "sub"}, {"type", "subsystem"}, {"diagram", "a.json"}});
  const std::string a = fs::weakly_canonical(folder.path() / "a.json").string();
  const std::string b = fs::weakly_canonical(folder.path() / "b.json").string();
  EXPECT_THAT(ProblemsOf(j, folder.path()),
              ElementsAre(b + ": /elements/0/diagram: the subsystem files include each other in a cycle: " + a +
                          " → " + b + " → " + a + "; a subsystem cannot contain itself: break the cycle"));

  for (int k = 0; k < 20; ++k) folder.Write(fmt::format("c{}.json", k), wrapper(fmt::format("c{}.json", k + 1)));
  j["elements"].back()["diagram"] = "c0.json";
  const auto problems = ProblemsOf(j, folder.path());
  ASSERT_EQ(problems.size(), 1u) << ::testing::PrintToString(problems);
  EXPECT_THAT(problems[0], HasSubstr("c15.json: /elements/0: subsystems nest deeper than 16 levels"));
}

// A diagram file holding no object is refused naming the file (the command line said only "diagram: …").
TEST(DiagramSchemaTest, AFileHoldingNoObjectIsRefusedNamingTheFile) {
  TempFolder folder;
  for (const auto& [text, holds] : std::vector<std::pair<std::string, std::string>>{
           {"null", "null"}, {"[1, 2]", "an array"}, {"3", "a number"}}) {
    const fs::path file = folder.Write("h.json", text);
    try {
      (void)ReadDiagramJson(file);
      ADD_FAILURE() << text << " was read as a diagram";
    } catch (const DiagramError& e) {
      EXPECT_THAT(std::string(e.what()), HasSubstr(file.string()));
      EXPECT_THAT(e.problems(), ElementsAre("/: a diagram is a JSON object {…}, but this file holds " + holds));
    }
  }
}

// A name a megabyte long is an ordinary problem, not a stack overflow in the schema's regular expressions.
TEST(DiagramSchemaTest, AMegabyteNameIsRefusedWithoutOverflowingTheStack) {
  json j = MinimalDiagram();
  j["elements"][0]["name"] = std::string(1 << 20, 'a') + ".b";
  const auto problems = ProblemsOf(j);
  ASSERT_FALSE(problems.empty());
  EXPECT_THAT(problems[0], HasSubstr("/elements/0/name: each element needs a name without '.'"));
}

TEST(DiagramSchemaTest, ASubsystemFileIsValidatedAsWritten) {
  TempFolder folder;
  folder.Write("inner.json", R"({"schemaVersion": "1.0", "solver": {"tpye": "rk4"},
    "elements": [{"name": "k", "type": "gain"}]})");
  json j = MinimalDiagram();
  j["elements"].push_back({{"name", "sub"}, {"type", "subsystem"}, {"diagram", "inner.json"}});
  const std::string inner = (folder.path() / "inner.json").string();
  EXPECT_THAT(ProblemsOf(j, folder.path()),
              ElementsAre(inner + ": /solver/tpye: unknown key 'tpye' (did you mean 'type'?); the keys here are: atol, "
                                  "maxStep, method, rtol, step, type"));
}

TEST(DiagramSchemaTest, InlineSubsystemsAreValidatedWithTheirParent) {
  json j = MinimalDiagram();
  j["elements"].push_back({{"name", "sub"},
                           {"type", "subsystem"},
                           {"diagram", {{"schemaVersion", "1.0"},
                                        {"elements", {{{"name", "k"}, {"type", "q_filter"}, {"sampleTme", 0.1}}}}}}});
  EXPECT_THAT(ProblemsOf(j), ElementsAre(HasSubstr("/elements/2/diagram/elements/0/sampleTme: unknown key "
                                                   "'sampleTme' (did you mean 'sampleTime'?)")));
}

}  // namespace
}  // namespace mb

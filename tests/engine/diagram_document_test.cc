// DiagramDocument: each operation, checked against the block registry, and each error message (what is wrong,
// where, how to fix it).

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "engine/diagram_document.h"
#include "engine/diagram_loader.h"
#include "engine/simulator.h"

namespace mb {
namespace {

using nlohmann::json;
using ::testing::ElementsAre;
using ::testing::HasSubstr;
using ::testing::ThrowsMessage;

// source (constant 1.5) → k (gain 2) → output connector "force"; input connector "x" [m] unused.
json Base() {
  return {{"schemaVersion", "1.0"},
          {"defaultExperiment", {{"startTime", 0.0}, {"stopTime", 0.01}, {"stepSize", 0.001}}},
          {"solver", {{"type", "rk4"}, {"step", 0.001}}},
          {"connectors",
           {{{"name", "x"}, {"kind", "input"}, {"unit", "m"}, {"measurement", "position_m"}, {"optional", true}},
            {{"name", "force"}, {"kind", "output"}, {"unit", "N"}}}},
          {"elements",
           {{{"name", "source"}, {"type", "constant"}, {"parameters", {{"value", 1.5}}}},
            {{"name", "k"}, {"type", "gain"}, {"parameters", {{"gain", {{"value", 2.0}, {"unit", ""}}}}}},
            {{"name", "body"}, {"type", "rigid_body"}, {"parameters", {{"mass", {{"value", 3.0}, {"unit", "kg"}}}}}}}},
          {"connections",
           {{{"startElement", "source"}, {"startConnector", "y"}, {"endElement", "k"}, {"endConnector", "u"}},
            {{"startElement", "k"}, {"startConnector", "y"}, {"endElement", ""}, {"endConnector", "force"}},
            {{"startElement", "k"}, {"startConnector", "y"}, {"endElement", "body"}, {"endConnector", "f"}}}},
          {"free", {"k.gain"}}};
}

DiagramDocument Document() { return DiagramDocument(Base(), ".", "base.json"); }

// The final value of output connector "force" when the document's diagram runs.
double FinalForce(const DiagramDocument& document) {
  const Diagram d = BuildDiagram(document.json(), ".", "test.json");
  Simulator simulator(d);
  return simulator.Run().log.Column("force").back();
}

TEST(DiagramDocumentTest, HoldsOnlyAJsonObject) {
  EXPECT_THAT([] { DiagramDocument(json::array(), {}, "d.json"); },
              ThrowsMessage<std::invalid_argument>(HasSubstr("d.json: a diagram is a JSON object")));
  EXPECT_THAT([] { DiagramDocument(json{{"elements", 3}}, {}, "d.json"); },
              ThrowsMessage<std::invalid_argument>(HasSubstr("d.json: /elements must be an array")));
}

TEST(DiagramDocumentTest, FindsElementsByNameAndType) {
  const DiagramDocument d = Document();
  EXPECT_TRUE(d.Has("k"));
  EXPECT_FALSE(d.Has("kk"));
  EXPECT_EQ(d.TypeOf("k"), "gain");
  EXPECT_THAT(d.ElementNames(), ElementsAre("source", "k", "body"));
  EXPECT_THAT(d.ElementsOfType("rigid_body"), ElementsAre("body"));
  EXPECT_THAT([&] { d.TypeOf("bdy"); },
              ThrowsMessage<std::invalid_argument>(HasSubstr("base.json: no element named 'bdy'; did you mean: body")));
}

TEST(DiagramDocumentTest, AddGivesATakenNameASuffix) {
  DiagramDocument d = Document();
  EXPECT_EQ(d.UniqueName("offset"), "offset");
  EXPECT_EQ(d.Add({"offset", "constant", {{"value", 3.0}}, std::nullopt, "an offset"}), "offset");
  EXPECT_EQ(d.Add({"offset", "constant", {{"value", 4.0}}, std::nullopt, ""}), "offset_2");
  EXPECT_EQ(d.UniqueName("offset"), "offset_3");
  EXPECT_EQ(d.TypeOf("offset_2"), "constant");
  EXPECT_EQ(d.json()["elements"][3]["description"], "an offset");
  EXPECT_EQ(d.Add({"delay", "unit_delay", json::object(), std::pair{0.001, 0.0}, ""}), "delay");
  EXPECT_EQ(d.json()["elements"][5]["sampleTime"], json({0.001, 0.0}));
}

TEST(DiagramDocumentTest, AddChecksTypeParametersAndSampleTime) {
  DiagramDocument d = Document();
  EXPECT_THAT([&] { d.Add({"g", "gian", json::object(), std::nullopt, ""}); },
              ThrowsMessage<std::invalid_argument>(
                  HasSubstr("adding element 'g': unknown block type 'gian'; did you mean: gain")));
  EXPECT_THAT([&] { d.Add({"g", "gain", {{"gian", 2.0}}, std::nullopt, ""}); },
              ThrowsMessage<std::invalid_argument>(HasSubstr(
                  "adding element 'g' (gain): /elements/g/parameters/gian: unknown parameter 'gian'; this block "
                  "takes: gain, width")));
  EXPECT_THAT([&] { d.Add({"m", "rigid_body", {{"mass", {{"value", 3.0}, {"unit", "s"}}}}, std::nullopt, ""}); },
              ThrowsMessage<std::invalid_argument>(HasSubstr("unit mismatch: given 's', this parameter is in 'kg'")));
  EXPECT_THAT([&] { d.Add({"z", "unit_delay", json::object(), std::nullopt, ""}); },
              ThrowsMessage<std::invalid_argument>(
                  HasSubstr("block type 'unit_delay' is discrete; give its sample time [Ts, offset]")));
  EXPECT_THAT([&] { d.Add({"g", "gain", json::object(), std::pair{0.001, 0.0}, ""}); },
              ThrowsMessage<std::invalid_argument>(HasSubstr("block type 'gain' is not sampled; give no sample time")));
  EXPECT_THAT([&] { d.Add({"a.b", "gain", json::object(), std::nullopt, ""}); },
              ThrowsMessage<std::invalid_argument>(HasSubstr("an element needs a name without '.'")));
  EXPECT_EQ(d.ElementNames().size(), 3u);  // nothing was added
}

TEST(DiagramDocumentTest, ConnectChecksPortsAndDrivers) {
  DiagramDocument d = Document();
  d.Add({"g", "gain", json::object(), std::nullopt, ""});
  d.Connect({"", "x"}, {"g", "u"});
  EXPECT_EQ(d.DriverOf({"g", "u"}), (Endpoint{"", "x"}));
  EXPECT_EQ(d.DriverOf({"", "force"}), (Endpoint{"k", "y"}));
  EXPECT_FALSE(d.DriverOf({"body", "nothing"}).has_value());
  EXPECT_THAT([&] { d.Connect({"g", "out"}, {"body", "f"}); },
              ThrowsMessage<std::invalid_argument>(
                  HasSubstr("base.json: element 'g' (gain) has no output 'out'; its outputs: y")));
  EXPECT_THAT([&] { d.Connect({"g", "y"}, {"body", "force"}); },
              ThrowsMessage<std::invalid_argument>(
                  HasSubstr("base.json: element 'body' (rigid_body) has no input 'force'; its inputs: f")));
  EXPECT_THAT([&] { d.Connect({"", "v"}, {"g", "u"}); },
              ThrowsMessage<std::invalid_argument>(HasSubstr("base.json: no input connector 'v'; the inputs: x")));
  EXPECT_THAT([&] { d.Connect({"g", "y"}, {"", "torque"}); },
              ThrowsMessage<std::invalid_argument>(HasSubstr("no output connector 'torque'; the outputs: force")));
  EXPECT_THAT([&] { d.Connect({"g", "y"}, {"body", "f"}); },
              ThrowsMessage<std::invalid_argument>(HasSubstr(
                  "base.json: input 'body.f' is already driven by 'k.y'; an input takes one signal (use SumInto to "
                  "add a signal)")));
  EXPECT_THAT([&] { d.Connect({"body", ""}, {"", "force"}); },
              ThrowsMessage<std::invalid_argument>(
                  HasSubstr("element 'body' (rigid_body) has 2 outputs; name one: x, v")));
  EXPECT_EQ(d.Connections().size(), 4u);  // only the first connection was added
}

TEST(DiagramDocumentTest, SumIntoAddsASignalToADrivenInput) {
  DiagramDocument d = Document();
  EXPECT_DOUBLE_EQ(FinalForce(d), 3.0);
  const std::string offset = d.Add({"offset", "constant", {{"value", 0.25}}, std::nullopt, ""});
  const std::string sum = d.SumInto({"", "force"}, {offset, ""}, "with_offset");
  EXPECT_EQ(sum, "with_offset");
  EXPECT_EQ(d.DriverOf({"", "force"})->element, "with_offset");
  EXPECT_DOUBLE_EQ(FinalForce(d), 3.25);
  // Into an element's input: the rigid body's force gets the offset too.
  d.SumInto({"body", "f"}, {offset, ""}, "with_offset");
  EXPECT_EQ(d.DriverOf({"body", "f"})->element, "with_offset_2");
  EXPECT_NO_THROW(BuildDiagram(d.json(), ".", "test.json"));
  EXPECT_THAT([&] { d.SumInto({"offset_nothing", "u"}, {offset, ""}, "s"); },
              ThrowsMessage<std::invalid_argument>(
                  HasSubstr("base.json: nothing drives input 'offset_nothing.u'; connect it instead")));
}

TEST(DiagramDocumentTest, SubtractIntoTakesASignalFromADrivenInput) {
  DiagramDocument d = Document();
  const std::string load = d.Add({"load", "constant", {{"value", 0.25}}, std::nullopt, ""});
  const std::string difference = d.SubtractInto({"", "force"}, {load, ""}, "with_load");
  EXPECT_EQ(difference, "with_load");
  EXPECT_EQ(d.DriverOf({"", "force"})->element, "with_load");
  EXPECT_DOUBLE_EQ(FinalForce(d), 2.75);
  EXPECT_THAT([&] { d.SubtractInto({"load_nothing", "u"}, {load, ""}, "s"); },
              ThrowsMessage<std::invalid_argument>(HasSubstr("base.json: nothing drives input 'load_nothing.u'; connect it instead")));
}

TEST(DiagramDocumentTest, InsertBeforePutsAnElementIntoASignalPath) {
  DiagramDocument d = Document();
  const std::string scale = d.Add({"scale", "gain", {{"gain", 10.0}}, std::nullopt, ""});
  d.InsertBefore({"", "force"}, scale);
  EXPECT_EQ(d.DriverOf({"", "force"}), (Endpoint{"scale", "y"}));
  EXPECT_EQ(d.DriverOf({"scale", "u"}), (Endpoint{"k", "y"}));
  EXPECT_DOUBLE_EQ(FinalForce(d), 30.0);
  const std::string add = d.Add({"add", "sum", {{"signs", "++"}}, std::nullopt, ""});
  EXPECT_THAT([&] { d.InsertBefore({"", "force"}, add); },
              ThrowsMessage<std::invalid_argument>(HasSubstr(
                  "element 'add' (sum) has 2 inputs and 1 outputs; only an element with one of each can be inserted")));
}

TEST(DiagramDocumentTest, InsertAfterPutsAnElementAfterASignalForEveryBlockThatReadIt) {
  DiagramDocument d = Document();
  const std::string scale = d.Add({"scale", "gain", {{"gain", 10.0}}, std::nullopt, ""});
  d.InsertAfter({"k", "y"}, scale);
  EXPECT_EQ(d.DriverOf({"body", "f"}), (Endpoint{"scale", "y"}));  // the block reads it through the element
  EXPECT_EQ(d.DriverOf({"", "force"}), (Endpoint{"k", "y"}));      // the output connector keeps the signal
  EXPECT_EQ(d.DriverOf({"scale", "u"}), (Endpoint{"k", "y"}));
  EXPECT_DOUBLE_EQ(FinalForce(d), 3.0);
  const std::string other = d.Add({"other", "gain", {{"gain", 1.0}}, std::nullopt, ""});
  EXPECT_THAT([&] { d.InsertAfter({"source", "x"}, other); },
              ThrowsMessage<std::invalid_argument>(HasSubstr("'source.x' drives no element's input")));
}

TEST(DiagramDocumentTest, ReadInsteadOpensALoopAtASignalForEveryBlockThatReadIt) {
  DiagramDocument d = Document();
  const std::string other = d.Add({"other", "constant", {{"value", 5.0}}, std::nullopt, ""});
  EXPECT_EQ(d.ReadInstead({"k", "y"}, d.OutputOf(other)), 1u);
  EXPECT_EQ(d.DriverOf({"body", "f"}), (Endpoint{"other", "y"}));  // the block reads the replacement
  EXPECT_EQ(d.DriverOf({"", "force"}), (Endpoint{"k", "y"}));      // the output connector keeps the signal
  EXPECT_DOUBLE_EQ(FinalForce(d), 3.0);                             // and it still is k's 2 × 1.5
  EXPECT_EQ(d.ReadInstead({"k", "y"}, d.OutputOf(other)), 0u);      // k drives no element now: nothing changes
  EXPECT_EQ(d.ReadInstead({"other", "y"}, {"", "x"}), 1u);          // an input connector as the replacement
  EXPECT_EQ(d.DriverOf({"body", "f"}), (Endpoint{"", "x"}));  // (a position into a force: BuildDiagram would refuse)
}

TEST(DiagramDocumentTest, ConnectorsGetFreeNamesAndAreRemovedWithTheirConnections) {
  DiagramDocument d = Document();
  EXPECT_EQ(d.UniqueConnectorName("v"), "v");
  EXPECT_EQ(d.UniqueConnectorName("force"), "force_2");  // an output's name is taken for inputs too
  d.AddConnector({"force_2", "input", "N", "", ""});
  EXPECT_EQ(d.UniqueConnectorName("force"), "force_3");
  EXPECT_TRUE(d.RemoveConnector("force"));
  EXPECT_FALSE(d.RemoveConnector("force"));
  EXPECT_EQ(d.DriverOf({"", "force"}), std::nullopt);               // its connection is gone
  EXPECT_EQ(d.DriverOf({"body", "f"}), (Endpoint{"k", "y"}));        // k's other reader keeps it
  EXPECT_EQ(d.Connectors("output").size(), 0u);
  EXPECT_EQ(d.UniqueConnectorName("force"), "force");
}

TEST(DiagramDocumentTest, ParametersAreCheckedAgainstTheBlockType) {
  DiagramDocument d = Document();
  EXPECT_EQ(d.Parameter("k", "gain"), json(2.0));      // unit wrapper stripped
  EXPECT_EQ(d.Parameter("body", "damping"), json(0.0));  // the registered default
  EXPECT_THAT([&] { d.Parameter("body", "mas"); },
              ThrowsMessage<std::invalid_argument>(HasSubstr(
                  "base.json: element 'body' (rigid_body) has no parameter 'mas'; did you mean: mass")));
  d.SetParameter("body", "mass", 4.0);
  EXPECT_EQ(d.json()["elements"][2]["parameters"]["mass"], json({{"value", 4.0}, {"unit", "kg"}}));
  d.SetParameter("body", "damping", 2.5);
  EXPECT_EQ(d.json()["elements"][2]["parameters"]["damping"], json(2.5));
  EXPECT_THAT([&] { d.SetParameter("body", "damping", -1.0); },
              ThrowsMessage<DiagramError>(HasSubstr("/elements/body/parameters/damping: must be >= 0")));
  EXPECT_THAT([&] { d.SetParameter("body", "damping", "high"); },
              ThrowsMessage<DiagramError>(HasSubstr("must be a number")));
  EXPECT_THAT([&] { d.SetParameter("nobody", "mass", 1.0); },
              ThrowsMessage<std::invalid_argument>(HasSubstr("no element named 'nobody'; did you mean: body")));
  const Parameters p = d.ElementParameters("body");
  EXPECT_DOUBLE_EQ(p.Number("mass"), 4.0);
  EXPECT_DOUBLE_EQ(p.Number("x0"), 0.0);
}

// Issue 30, one meaning per number: a bare number is in the parameter's SI unit whatever unit the diagram wrote;
// it is written back in the diagram's unit; a quantity object is taken as given.
TEST(DiagramDocumentTest, NumbersAreInTheSiUnitWhateverUnitTheDiagramWrote) {
  json base = Base();
  base["elements"][2]["parameters"]["mass"] = {{"value", 2000.0}, {"unit", "g"}};
  DiagramDocument d(base, ".", "g.json");
  EXPECT_DOUBLE_EQ(d.Parameter("body", "mass").get<double>(), 2.0);  // read in kg
  d.SetParameter("body", "mass", 3.0);                                // 3 kg, not 3 g
  EXPECT_EQ(d.json()["elements"][2]["parameters"]["mass"]["unit"], "g");
  EXPECT_DOUBLE_EQ(d.json()["elements"][2]["parameters"]["mass"]["value"].get<double>(), 3000.0);
  EXPECT_DOUBLE_EQ(d.ElementParameters("body").Number("mass"), 3.0);
  d.SetParameter("body", "mass", json{{"value", 500.0}, {"unit", "g"}});  // a quantity, as given
  EXPECT_DOUBLE_EQ(d.ElementParameters("body").Number("mass"), 0.5);
  EXPECT_THAT([&] { d.SetParameter("body", "mass", json{{"value", 500.0}, {"unti", "g"}}); },
              ThrowsMessage<DiagramError>(HasSubstr("/elements/body/parameters/mass/unti: a quantity takes only "
                                                    "\"value\" and \"unit\", not 'unti' (did you mean \"unit\"?)")));
}

TEST(DiagramDocumentTest, FreeParametersAreChecked) {
  DiagramDocument d = Document();
  EXPECT_THAT(d.FreeParameters(), ElementsAre("k.gain"));
  d.AddFreeParameter("body.mass");
  d.AddFreeParameter("body.mass");  // listed once
  EXPECT_THAT(d.FreeParameters(), ElementsAre("k.gain", "body.mass"));
  EXPECT_THAT([&] { d.AddFreeParameter("body"); },
              ThrowsMessage<std::invalid_argument>(HasSubstr("free parameter 'body': write element.parameter")));
  EXPECT_THAT([&] { d.AddFreeParameter("body.weight"); },
              ThrowsMessage<std::invalid_argument>(HasSubstr("has no parameter 'weight'")));
}

TEST(DiagramDocumentTest, ExperimentAndSolver) {
  DiagramDocument d = Document();
  EXPECT_EQ(d.Mode(), ExperimentMode::kSimulation);
  EXPECT_EQ(d.SolverStep(), 0.001);
  EXPECT_EQ(d.ExperimentStepSize(), 0.001);
  d.SetExperiment(1.0, 3.0, 0.5);
  EXPECT_EQ(d.json()["defaultExperiment"], json({{"startTime", 1.0}, {"stopTime", 3.0}, {"stepSize", 0.5}}));
  d.SetExperimentDuration(4.0);
  EXPECT_EQ(d.json()["defaultExperiment"], json({{"startTime", 1.0}, {"stopTime", 5.0}, {"stepSize", 0.5}}));
  DiagramDocument bare(json{{"elements", json::array()}, {"experiment", {{"mode", "equation_error"}}}});
  EXPECT_EQ(bare.Mode(), ExperimentMode::kEquationError);
  EXPECT_FALSE(bare.SolverStep().has_value());
  d.CopyExperimentFrom(bare);
  EXPECT_FALSE(d.json().contains("defaultExperiment"));
  bare.CopyExperimentFrom(Document());
  EXPECT_EQ(bare.json()["defaultExperiment"]["stopTime"], 0.01);
}

TEST(DiagramDocumentTest, SectionSettingsSetExperimentAndSolverKeys) {
  DiagramDocument document(Base(), ".", "d.json");
  document.SetSectionSetting("defaultExperiment", "stopTime", 2.5);
  document.SetSectionSetting("solver", "step", 1e-4);
  EXPECT_DOUBLE_EQ(document.json()["defaultExperiment"]["stopTime"].get<double>(), 2.5);
  EXPECT_DOUBLE_EQ(document.SolverStep().value(), 1e-4);
  EXPECT_TRUE(DiagramDocument::IsSettingSection("solver"));
  EXPECT_FALSE(DiagramDocument::IsSettingSection("body"));
  EXPECT_THAT([&] { document.SetSectionSetting("body", "mass", 1.0); },
              ThrowsMessage<std::invalid_argument>(
                  HasSubstr("d.json: 'body.mass': only defaultExperiment.<key> and solver.<key> are settings")));
  EXPECT_THAT([&] { document.SetSectionSetting("solver", "", 1.0); },
              ThrowsMessage<std::invalid_argument>(HasSubstr("d.json: 'solver.': name the setting after the dot")));
}

TEST(DiagramDocumentTest, ConnectorsLoggingNotesAndSubsystems) {
  DiagramDocument d = Document();
  ASSERT_EQ(d.Connectors("input").size(), 1u);
  EXPECT_EQ(d.Connectors("input")[0].measurement, "position_m");
  EXPECT_EQ(d.Connectors("output")[0].measurement, "force");  // defaults to the connector's name
  d.SetLoggedSignals({"k.y"});
  EXPECT_THAT(d.LoggedSignals(), ElementsAre("k.y"));
  d.ClearMetrics();
  EXPECT_EQ(d.json()["metrics"], json::array());
  d.AppendNote("one.");
  d.AppendNote(" two.");
  EXPECT_EQ(d.json()["notes"], "one. two.");
  EXPECT_THAT([&] { d.SetSubsystemDiagram("body", "io.json"); },
              ThrowsMessage<std::invalid_argument>(HasSubstr("element 'body' is a 'rigid_body', not a subsystem")));
  // A subsystem's ports are its inner diagram's connectors.
  json inner = Base();
  inner["connectors"].push_back({{"name", "f_in"}, {"kind", "input"}, {"unit", "N"}});
  d.Add({"g", "gain", json::object(), std::nullopt, ""});
  json with_subsystem = d.json();
  with_subsystem["elements"].push_back(
      {{"name", "plant"}, {"type", "subsystem"}, {"diagram", inner}, {"parameters", {{"k.gain", 3.0}}}});
  DiagramDocument s(with_subsystem, ".", "outer.json");
  s.Connect({"plant", "force"}, {"g", "u"});
  EXPECT_THAT([&] { s.Connect({"g", "y"}, {"plant", "f"}); },
              ThrowsMessage<std::invalid_argument>(HasSubstr("element 'plant' (subsystem) has no input 'f'; its "
                                                             "inputs: x, f_in")));
  EXPECT_THAT(s.SetSubsystemDiagram("plant", "io.json"), ElementsAre("plant.k.gain = 3.0"));
  EXPECT_EQ(s.json()["elements"].back()["diagram"], "io.json");
}

TEST(DiagramRolesTest, TheLoaderReadsAndChecksRoles) {
  json j = Base();
  j["roles"] = {{"plant", "body"}};
  const Diagram d = BuildDiagram(j, ".", "roles.json");
  EXPECT_EQ(d.roles().at("plant"), "body");
  EXPECT_EQ(d.block_type(d.FindBlock("body")), "rigid_body");
  EXPECT_DOUBLE_EQ(d.block_parameters(d.FindBlock("body")).Number("mass"), 3.0);
  j["roles"] = {{"plant", "bodie"}};
  EXPECT_THAT([&] { BuildDiagram(j, ".", "roles.json"); },
              ThrowsMessage<DiagramError>(HasSubstr("/roles/plant: no element named 'bodie'")));
  // The shape of "roles" is the schema's to check (engine/diagram_schema.h).
  j["roles"] = {{"plant", "body"}, {"dob", 3}};
  EXPECT_THAT([&] { BuildDiagram(j, ".", "roles.json"); },
              ThrowsMessage<DiagramError>(HasSubstr("/roles/dob: must be string, got an integer")));
  j["roles"] = json::array();
  EXPECT_THAT([&] { BuildDiagram(j, ".", "roles.json"); },
              ThrowsMessage<DiagramError>(HasSubstr("/roles: must be object, got an array")));
}

}  // namespace
}  // namespace mb

// Diagram validation: every error names where (JSON pointer, element) and how to fix it.

#include <gmock/gmock.h>
#include <gtest/gtest.h>
#include <fmt/format.h>

#include "engine/execution_order.h"
#include "tests/engine/test_util.h"

namespace mb {
namespace {

using nlohmann::json;
using ::testing::HasSubstr;
using testing::Build;
using testing::Connect;

using testing::MinimalDiagram;

std::string ErrorOf(const json& j) {
  try {
    Build(j);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "no error";
}

TEST(DiagramLoaderTest, MinimalDiagramBuilds) {
  const Diagram d = Build(MinimalDiagram());
  EXPECT_EQ(d.blocks().size(), 2u);
  EXPECT_EQ(d.execution_order(), (std::vector<int>{0, 1}));
}

TEST(DiagramLoaderTest, UnknownBlockTypeSuggestsName) {
  json j = MinimalDiagram();
  j["elements"][1]["type"] = "gian";
  EXPECT_THAT(ErrorOf(j), HasSubstr("/elements/1/type: unknown block type 'gian' in element 'g'; did you mean: gain"));
}

TEST(DiagramLoaderTest, MissingExtraAndMistypedParametersAllReported) {
  json j = MinimalDiagram();
  j["elements"][1]["parameters"] = {{"gain", "two"}, {"gainn", 1}};
  j["elements"].push_back({{"name", "z"}, {"type", "unit_delay"}});
  const std::string e = ErrorOf(j);
  EXPECT_THAT(e, HasSubstr("/elements/1/parameters/gain: must be an array of numbers"));
  EXPECT_THAT(e, HasSubstr("/elements/1/parameters/gainn: unknown parameter 'gainn'; this block takes: gain, width"));
  EXPECT_THAT(e, HasSubstr("/elements/2: element 'z' (unit_delay) is discrete: add \"sampleTime\""));
}

TEST(DiagramLoaderTest, ParameterUnitsAreChecked) {
  const std::vector<ParamSpec> specs = {Required("mass", "kg", "moving mass"),
                                        Bounded("damping", 3.0, "N*s/m", "viscous damping", 0.0, 1e9)};
  std::vector<std::string> errors;
  auto ok = ValidateParameters(specs, {{"mass", {{"value", 2.0}, {"unit", "kg"}}}}, "/elements/0/parameters", &errors);
  EXPECT_TRUE(errors.empty());
  EXPECT_EQ(ok.at("mass"), 2.0);
  EXPECT_EQ(ok.at("damping"), 3.0);  // default filled in
  ValidateParameters(specs, {{"mass", {{"value", 2.0}, {"unit", "s"}}}, {"damping", -1.0}}, "/elements/0/parameters",
                     &errors);
  ASSERT_EQ(errors.size(), 2u);
  EXPECT_EQ(errors[0], "/elements/0/parameters/mass: unit mismatch: given 's', this parameter is in 'kg' (SI)");
  EXPECT_EQ(errors[1], "/elements/0/parameters/damping: must be >= 0 [N*s/m], got -1");
}

TEST(DiagramLoaderTest, UnconnectedInputNamed) {
  json j = MinimalDiagram();
  j["connections"] = json::array();
  EXPECT_THAT(ErrorOf(j), HasSubstr("/elements/1: input 'g.u' is not connected"));
}

TEST(DiagramLoaderTest, WidthMismatchNamed) {
  json j = MinimalDiagram();
  j["elements"][0]["parameters"]["value"] = {1.0, 2.0};
  EXPECT_THAT(ErrorOf(j), HasSubstr("/connections/0: width mismatch: c.y has width 2, input g.u expects 1"));
}

TEST(DiagramLoaderTest, AlgebraicLoopNamesEveryBlockInTheCycle) {
  json j = {{"schemaVersion", "1.0"},
            {"elements",
             {{{"name", "c"}, {"type", "constant"}},
              {{"name", "a"}, {"type", "sum"}},
              {{"name", "k"}, {"type", "gain"}, {"parameters", {{"gain", 0.5}}}}}},
            {"connections", {Connect("c.y", "a.u1"), Connect("k.y", "a.u2"), Connect("a.y", "k.u")}}};
  try {
    Build(j);
    FAIL() << "expected an algebraic loop error";
  } catch (const AlgebraicLoopError& e) {
    EXPECT_THAT(std::string(e.what()), HasSubstr("algebraic loop through blocks [a, k]"));
    EXPECT_THAT(std::string(e.what()), HasSubstr("a.y → k.u (direct feedthrough)"));
    EXPECT_THAT(std::string(e.what()), HasSubstr("k.y → a.u2 (direct feedthrough)"));
    EXPECT_THAT(std::string(e.what()), HasSubstr("unit_delay"));
    EXPECT_EQ(e.cycle().size(), 2u);
  }
  // Breaking the loop with a unit delay makes it valid.
  j["elements"].push_back({{"name", "z"}, {"type", "unit_delay"}, {"sampleTime", 0.01}});
  j["connections"][1] = Connect("z.y", "a.u2");
  j["connections"].push_back(Connect("k.y", "z.u"));
  EXPECT_NO_THROW(Build(j));
}

TEST(DiagramLoaderTest, SchemaVersionAndSolverChecked) {
  json j = MinimalDiagram();
  j["schemaVersion"] = "0.9";
  j["solver"] = {{"type", "ode45"}};
  const std::string e = ErrorOf(j);
  EXPECT_THAT(e, HasSubstr("/schemaVersion: this build reads version \"1.0\""));
  EXPECT_THAT(e, HasSubstr("/solver/type: 'ode45' is not a solver"));
}

TEST(DiagramLoaderTest, OverridesApplyAndUnknownBlockIsReported) {
  json j = MinimalDiagram();
  ApplyOverrides(&j, {ParameterOverride::Parse("g.gain=3.5")}, "test.json");
  EXPECT_EQ(j["elements"][1]["parameters"]["gain"], 3.5);
  EXPECT_THROW(ApplyOverrides(&j, {ParameterOverride::Parse("h.gain=1")}, "test.json"), DiagramError);
  EXPECT_THROW(ParameterOverride::Parse("gain=1"), std::invalid_argument);
  EXPECT_EQ(ParameterOverride::Parse("plant.mode=fast").value, "fast");
}

// Issue 30: `--set mass.mass=2` on a mass written {"value": 2000, "unit": "g"} is 2 kg, not 2 g; a quantity object
// is accepted and converted.
TEST(DiagramLoaderTest, OverrideNumbersAreInTheSiUnit) {
  json j = MinimalDiagram();
  j["elements"].push_back({{"name", "mass"}, {"type", "rigid_body"},
                           {"parameters", {{"mass", {{"value", 2000.0}, {"unit", "g"}}}}}});
  j["connections"].push_back(Connect("g.y", "mass.f"));
  ApplyOverrides(&j, {ParameterOverride::Parse("mass.mass=2")}, "g.json");
  EXPECT_DOUBLE_EQ(Build(j).block_parameters(2).Number("mass"), 2.0);
  EXPECT_EQ(j["elements"][2]["parameters"]["mass"]["unit"], "g");  // the diagram's unit kept
  ApplyOverrides(&j, {ParameterOverride::Parse(R"(mass.mass={"value": 0.5, "unit": "kg"})")}, "g.json");
  EXPECT_DOUBLE_EQ(Build(j).block_parameters(2).Number("mass"), 0.5);
  ApplyOverrides(&j, {ParameterOverride::Parse(R"(mass.mass={"value": 250, "unit": "g"})")}, "g.json");
  EXPECT_DOUBLE_EQ(Build(j).block_parameters(2).Number("mass"), 0.25);
}

TEST(DiagramLoaderTest, QuantityWithAnotherKeyIsRefused) {
  json j = MinimalDiagram();
  j["elements"].push_back({{"name", "mass"}, {"type", "rigid_body"},
                           {"parameters", {{"mass", {{"value", 500.0}, {"unti", "g"}}}}}});
  j["connections"].push_back(Connect("g.y", "mass.f"));
  EXPECT_THAT(ErrorOf(j), HasSubstr("/elements/2/parameters/mass/unti: a quantity takes only \"value\" and "
                                    "\"unit\", not 'unti' (did you mean \"unit\"?); write {\"value\": …, "
                                    "\"unit\": \"kg\"}"));
  j["elements"][2]["parameters"]["mass"] = {{"value", 500.0}, {"unit", "g"}, {"note", "scale"}};
  EXPECT_THAT(ErrorOf(j), HasSubstr("/elements/2/parameters/mass/note: a quantity takes only"));
}

// Issue 30: an output connector is unit-checked like an input port; connector names are unique.
TEST(DiagramLoaderTest, OutputConnectorUnitAndNameAreChecked) {
  json j = MinimalDiagram();
  j["elements"].push_back({{"name", "mass"}, {"type", "rigid_body"}, {"parameters", {{"mass", 1.0}}}});
  j["connections"].push_back(Connect("g.y", "mass.f"));
  j["connectors"] = {{{"name", "position"}, {"kind", "output"}, {"unit", "kg"}}};
  j["connections"].push_back({{"startElement", "mass"}, {"startConnector", "x"}, {"endConnector", "position"}});
  EXPECT_THAT(ErrorOf(j), HasSubstr("/connectors/0/unit: unit mismatch: output connector 'position' is in 'kg', but "
                                    "the signal wired to it, mass.x, is in 'm'"));
  j["connectors"][0]["unit"] = "rad";  // a linear block on a rotary axis
  EXPECT_NO_THROW(Build(j));
  j["connectors"][0]["unit"] = "m";
  EXPECT_NO_THROW(Build(j));
  j["connectors"].push_back({{"name", "position"}, {"kind", "input"}, {"unit", "m"}, {"optional", true}});
  EXPECT_THAT(ErrorOf(j), HasSubstr("/connectors/1/name: connector 'position' is declared twice (also /connectors/0)"));
}

// A metric type outside the table (engine/metric_type.h; the schema enum comes from it) is a load error listing the
// table, not a NaN after the run.
TEST(DiagramLoaderTest, UnknownMetricTypeIsALoadErrorListingTheTypes) {
  json j = MinimalDiagram();
  j["metrics"] = {{{"name", "peak"}, {"type", "maximum"}, {"signal", "g.y"}}};
  EXPECT_THAT(ErrorOf(j), HasSubstr("/metrics/0/type: \"maximum\" is not allowed here; use one of \"rmse\", "
                                    "\"max_abs\", \"mean\", \"final\", \"rms_difference\""));
  j["metrics"][0]["type"] = "max_abs";
  EXPECT_EQ(Build(j).metrics().at(0).type, MetricType::kMaxAbs);
}

// Two metrics of one name were both computed and one silently lost in the results (found by tests/hostile).
TEST(DiagramLoaderTest, TwoMetricsOfOneNameAreALoadError) {
  json j = MinimalDiagram();
  j["metrics"] = {{{"name", "peak"}, {"type", "max_abs"}, {"signal", "g.y"}},
                  {{"name", "peak"}, {"type", "final"}, {"signal", "g.y"}}};
  EXPECT_THAT(ErrorOf(j), HasSubstr("/metrics/1/name: the metric name 'peak' is used by /metrics/0 too"));
  j["metrics"][1]["name"] = "last";
  EXPECT_EQ(Build(j).metrics().size(), 2u);
}

// Issue 25: a connector in a unit of no motion quantity (a voltage standing for a position) declares what it stands
// for, and the blocks take it on ports of that quantity; a declaration that contradicts the unit is refused.
TEST(DiagramLoaderTest, ConnectorQuantityLetsAVoltageStandForAPosition) {
  json j = MinimalDiagram();
  j["elements"].push_back({{"name", "spring"}, {"type", "position_dependent_force"}});
  j["connectors"] = {{{"name", "x"}, {"kind", "input"}, {"unit", "V"}}};
  j["connections"].push_back({{"startConnector", "x"}, {"endElement", "spring"}, {"endConnector", "x"}});
  EXPECT_THAT(ErrorOf(j), HasSubstr("unit mismatch: x is in 'V', input spring.x expects 'm'"));
  j["connectors"][0]["quantity"] = "position";
  EXPECT_NO_THROW(Build(j));
  j["connectors"][0]["quantity"] = "force";
  EXPECT_THAT(ErrorOf(j), HasSubstr("unit mismatch: x is in 'V', input spring.x expects 'm'"));
  j["connectors"][0]["unit"] = "rad";
  EXPECT_THAT(ErrorOf(j), HasSubstr("/connectors/0/quantity: \"force\" contradicts the unit 'rad', which measures a "
                                    "position; leave \"quantity\" out (the unit says it) or fix the unit"));
  j["connectors"][0]["quantity"] = "length";
  EXPECT_THAT(ErrorOf(j), HasSubstr("/connectors/0/quantity"));
}

TEST(DiagramLoaderTest, SubsystemIsExpandedAndRewired) {
  json inner = {{"schemaVersion", "1.0"},
                {"connectors", {{{"name", "in"}, {"kind", "input"}}, {{"name", "out"}, {"kind", "output"}}}},
                {"elements", {{{"name", "k"}, {"type", "gain"}, {"parameters", {{"gain", 3.0}}}}}},
                {"connections",
                 {{{"startConnector", "in"}, {"endElement", "k"}, {"endConnector", "u"}},
                  {{"startElement", "k"}, {"startConnector", "y"}, {"endConnector", "out"}}}}};
  json outer = {{"schemaVersion", "1.0"},
                {"defaultExperiment", {{"stopTime", 0.1}}},
                {"elements",
                 {{{"name", "c"}, {"type", "constant"}, {"parameters", {{"value", 2.0}}}},
                  {{"name", "sub"}, {"type", "subsystem"}, {"diagram", inner}, {"parameters", {{"k.gain", 5.0}}}}}},
                {"connections", {Connect("c.y", "sub.in"), Connect("sub.out", "c2.u")}}};
  outer["elements"].push_back({{"name", "c2"}, {"type", "gain"}});
  outer["log"] = {"c2.y", "sub/k.y"};
  const Diagram d = Build(outer);
  EXPECT_GE(d.FindBlock("sub/k"), 0);
  const auto r = Simulator(d).Run();
  EXPECT_DOUBLE_EQ(r.log.Column("c2.y").back(), 10.0);  // the override k.gain = 5 applies
}

}  // namespace
}  // namespace mb

namespace mb {
namespace {

// Issue 30: a 100,000-block diagram did not load in 30 s (a linear FindBlock per connection; the lookup is a hash
// map now). A long chain of gains builds and every block is found by name; how long it takes is a benchmark's business,
// not a unit test's (under ASan on a loaded machine 100,000 blocks took 47 s).
TEST(DiagramLoaderTest, ALongChainBuildsAndEveryBlockIsFoundByName) {
  constexpr int kBlocks = 20000;
  json elements = json::array({{{"name", "source"}, {"type", "constant"}}});
  json connections = json::array();
  for (int i = 0; i < kBlocks; ++i) {
    elements.push_back({{"name", "g" + std::to_string(i)}, {"type", "gain"}});
    connections.push_back({{"startElement", i == 0 ? std::string("source") : "g" + std::to_string(i - 1)},
                           {"startConnector", "y"},
                           {"endElement", "g" + std::to_string(i)},
                           {"endConnector", "u"}});
  }
  const json j = {{"schemaVersion", "1.0"},
                  {"name", "chain"},
                  {"defaultExperiment", {{"startTime", 0.0}, {"stopTime", 0.01}, {"stepSize", 0.001}}},
                  {"solver", {{"type", "rk4"}, {"step", 0.001}}},
                  {"elements", elements},
                  {"connections", connections}};
  const Diagram d = Build(j);
  EXPECT_EQ(d.blocks().size(), static_cast<std::size_t>(kBlocks + 1));
  EXPECT_EQ(d.FindBlock("g19999"), kBlocks);
  EXPECT_EQ(d.FindBlock("g7"), 8);
  EXPECT_EQ(d.FindBlock("source"), 0);
  EXPECT_EQ(d.FindBlock("g20000"), -1);
}

// Issue 41: what was accepted without a word is refused with its pointer.
TEST(DiagramLoaderTest, AZeroLogIntervalIsRefusedAndAnAbsentOneIsAutomatic) {
  json j = MinimalDiagram();
  j["defaultExperiment"] = {{"startTime", 0.0}, {"stopTime", 1.0}, {"stepSize", 0.0}};
  EXPECT_THAT(ErrorOf(j), HasSubstr("/defaultExperiment/stepSize: must be > 0 s (the log interval), got 0; leave "
                                    "stepSize out to log at the fastest discrete period (or every solver step)"));
  j["defaultExperiment"].erase("stepSize");
  EXPECT_EQ(ErrorOf(j), "no error");
}

TEST(DiagramLoaderTest, AFreeEntryNamesAnElementAndOneOfItsParameters) {
  json j = MinimalDiagram();
  j["free"] = {"g.gian", "k.gain", "g", "g.gain"};
  const std::string e = ErrorOf(j);
  EXPECT_THAT(e, HasSubstr("/free/0: 'g.gian': element 'g' (gain) has no parameter 'gian' (did you mean 'gain'?); it "
                           "takes: gain, width"));
  EXPECT_THAT(e, HasSubstr("/free/1: 'k.gain': no element named 'k'"));
  EXPECT_THAT(e, HasSubstr("/free/2: 'g': write element.parameter"));
  EXPECT_THAT(e, ::testing::Not(HasSubstr("/free/3")));
}

TEST(DiagramLoaderTest, AConnectionNamesBothPortsEvenOfABlockWithOne) {
  json j = MinimalDiagram();
  j["connections"][0].erase("endConnector");
  EXPECT_THAT(ErrorOf(j), HasSubstr("/connections/0/endConnector: missing; name the input of element 'g' that the "
                                    "connection feeds (its inputs: u)"));
  j = MinimalDiagram();
  j["connections"][0]["startConnector"] = "";
  EXPECT_THAT(ErrorOf(j), HasSubstr("/connections/0/startConnector: missing; name the output of element 'c' that "
                                    "the connection starts from (its outputs: y)"));
}

// Issue 41: a million blocks ran past 30 s without a word; beyond kMaxDiagramElements the diagram is refused at once.
TEST(DiagramLoaderTest, ADiagramOfMoreThanTheMostElementsIsRefusedAtOnce) {
  json j = MinimalDiagram();
  for (std::size_t i = j["elements"].size(); i <= kMaxDiagramElements; ++i) {
    j["elements"].push_back({{"name", "c" + std::to_string(i)}, {"type", "constant"}});
  }
  EXPECT_EQ(ErrorOf(j), fmt::format("test.json: 1 problem in the diagram:\n  /elements: {} elements, more than the "
                                    "{} a diagram may hold (each is a block built, sorted and stepped: a run would "
                                    "take minutes before its first step); simulate a part of the model, or merge "
                                    "blocks (a gain or state_space of width n for n scalar ones)",
                                    kMaxDiagramElements + 1, kMaxDiagramElements));
}

}  // namespace
}  // namespace mb

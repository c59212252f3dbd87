// Diagram validation: every error names where (JSON pointer, element) and how to fix it.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "engine/execution_order.h"
#include "tests/engine/test_util.h"

namespace mb {
namespace {

using nlohmann::json;
using ::testing::HasSubstr;
using testing::Build;
using testing::Connect;

using testing::MinimalDiagram;
const auto Minimal = MinimalDiagram;

std::string ErrorOf(const json& j) {
  try {
    Build(j);
  } catch (const std::exception& e) {
    return e.what();
  }
  return "no error";
}

TEST(DiagramLoaderTest, MinimalDiagramBuilds) {
  const Diagram d = Build(Minimal());
  EXPECT_EQ(d.blocks().size(), 2u);
  EXPECT_EQ(d.execution_order(), (std::vector<int>{0, 1}));
}

TEST(DiagramLoaderTest, UnknownBlockTypeSuggestsName) {
  json j = Minimal();
  j["elements"][1]["type"] = "gian";
  EXPECT_THAT(ErrorOf(j), HasSubstr("/elements/1/type: unknown block type 'gian' in element 'g'; did you mean: gain"));
}

TEST(DiagramLoaderTest, MissingExtraAndMistypedParametersAllReported) {
  json j = Minimal();
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
  json j = Minimal();
  j["connections"] = json::array();
  EXPECT_THAT(ErrorOf(j), HasSubstr("/elements/1: input 'g.u' is not connected"));
}

TEST(DiagramLoaderTest, WidthMismatchNamed) {
  json j = Minimal();
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
  json j = Minimal();
  j["schemaVersion"] = "0.9";
  j["solver"] = {{"type", "ode45"}};
  const std::string e = ErrorOf(j);
  EXPECT_THAT(e, HasSubstr("/schemaVersion: this build reads version \"1.0\""));
  EXPECT_THAT(e, HasSubstr("/solver/type: 'ode45' is not a solver"));
}

TEST(DiagramLoaderTest, OverridesApplyAndUnknownBlockIsReported) {
  json j = Minimal();
  ApplyOverrides(&j, {ParameterOverride::Parse("g.gain=3.5")}, "test.json");
  EXPECT_EQ(j["elements"][1]["parameters"]["gain"], 3.5);
  EXPECT_THROW(ApplyOverrides(&j, {ParameterOverride::Parse("h.gain=1")}, "test.json"), DiagramError);
  EXPECT_THROW(ParameterOverride::Parse("gain=1"), std::invalid_argument);
  EXPECT_EQ(ParameterOverride::Parse("plant.mode=fast").value, "fast");
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

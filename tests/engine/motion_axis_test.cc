// Parameter units follow the diagram's axis (issue 40, item 8; engine/units.h AxisUnit, engine/parameters.h OnAxis):
// a block declares its parameters in linear SI units, and on a rotary diagram (rad, N·m) they read as their rotary
// analogues — a friction's viscous coefficient in N·m·s/rad, its Coulomb level in N·m, a mass as an inertia in kg·m² —
// while the numbers (what the block computes with) stay as they are.

#include <filesystem>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "engine/diagram_document.h"
#include "engine/diagram_loader.h"
#include "engine/parameters.h"
#include "engine/registry.h"
#include "engine/units.h"

namespace mb {
namespace {

using nlohmann::json;
using ::testing::HasSubstr;
using ::testing::Not;
namespace fs = std::filesystem;

const fs::path kRigidArm = fs::path(MB_SOURCE_DIR) / "diagrams" / "rotary" / "rigid_arm.json";
const fs::path kRigidRotor = fs::path(MB_SOURCE_DIR) / "diagrams" / "odrive" / "rigid_rotor.json";
const fs::path kOscillator = fs::path(MB_SOURCE_DIR) / "diagrams" / "duffing" / "linear_oscillator.json";
const fs::path kEmps = fs::path(MB_SOURCE_DIR) / "diagrams" / "emps" / "rigid_body.json";

const MotionAxis kRotary{"rad", "N·m"};

TEST(AxisUnit, ReadsAsTheRotaryAnalogueOnARotaryAxis) {
  EXPECT_EQ(AxisUnit("N·s/m", kRotary), "N·m·s/rad");
  EXPECT_EQ(AxisUnit("N*s/m", kRotary), "N·m·s/rad");
  EXPECT_EQ(AxisUnit("N", kRotary), "N·m");
  EXPECT_EQ(AxisUnit("kg", kRotary), "kg·m²");
  EXPECT_EQ(AxisUnit("m", kRotary), "rad");
  EXPECT_EQ(AxisUnit("m/s", kRotary), "rad/s");
  EXPECT_EQ(AxisUnit("N/m", kRotary), "N·m/rad");
  EXPECT_EQ(AxisUnit("N*s^2/m^2", kRotary), "N·m·s²/rad²");
  EXPECT_EQ(AxisUnit("1/m", kRotary), "1/rad");
  EXPECT_EQ(AxisUnit("N/V", kRotary), "N·m/V");
}

TEST(AxisUnit, TheSameQuantityInTheRotaryUnitsConvertsWithFactorOne) {
  // The SI value is unchanged: the rotary unit is the linear one's analogue, 1 ↔ 1.
  EXPECT_EQ(UnitFactor("N*m*s/rad", AxisUnit("N·s/m", kRotary)), 1.0);
  EXPECT_EQ(UnitFactor("kg*m^2", AxisUnit("kg", kRotary)), 1.0);
  EXPECT_NEAR(*UnitFactor("N·m·s/deg", AxisUnit("N·s/m", kRotary)), 180.0 / std::numbers::pi, 1e-9);
}

TEST(AxisUnit, ADriveAxisAndAVoltageAxisReadInTheirOwnUnits) {
  const MotionAxis drive{"rev", "A"};
  EXPECT_EQ(AxisUnit("N·s/m", drive), "A·s/rev");
  EXPECT_EQ(AxisUnit("N", drive), "A");
  EXPECT_EQ(AxisUnit("kg", drive), "A·s²/rev");
  const MotionAxis volts{"V", "V"};  // an electronic oscillator: a voltage stands for both
  EXPECT_EQ(AxisUnit("N·s/m", volts), "s");
  EXPECT_EQ(AxisUnit("kg", volts), "s²");
  EXPECT_EQ(AxisUnit("N/m", volts), "1");
}

TEST(AxisUnit, TheLinearAxisAndUnitsWithoutForceOrLengthStayAsDeclared) {
  EXPECT_EQ(AxisUnit("N*s/m", MotionAxis{}), "N*s/m");
  EXPECT_EQ(AxisUnit("kg", MotionAxis{}), "kg");
  for (const char* unit : {"s", "Hz", "rad", "", "not a unit"}) EXPECT_EQ(AxisUnit(unit, kRotary), unit) << unit;
}

TEST(DiagramAxis, FromTheConnectors) {
  const MotionAxis arm = DiagramAxis(DiagramDocument::Load(kRigidArm).json());
  EXPECT_EQ(arm.position, "rad");
  EXPECT_EQ(arm.force, "N·m");
  EXPECT_FALSE(arm.is_linear());
  const MotionAxis rotor = DiagramAxis(DiagramDocument::Load(kRigidRotor).json());
  EXPECT_EQ(rotor.ToString(), "rev, A");
  EXPECT_EQ(DiagramAxis(DiagramDocument::Load(kOscillator).json()).ToString(), "V, V");
  EXPECT_TRUE(DiagramAxis(DiagramDocument::Load(kEmps).json()).is_linear());
  // A rotary velocity alone: the torque is taken for the force; a diagram without connectors is linear.
  EXPECT_EQ(AxisOfConnectors({{"deg/s", ""}}).ToString(), "deg, N·m");
  EXPECT_TRUE(DiagramAxis(json::object()).is_linear());
}

// `motionblocks blocks friction` says how its linear units read on a rotary diagram.
TEST(BlockReferenceAxis, NamesTheRotaryUnitsOfTheMechanicalParameters) {
  EXPECT_THAT(BlockReference(BlockRegistry::Global().Get("friction")),
              HasSubstr("  on a rotary diagram (connectors in rad and N·m) the same numbers are in: viscous "
                        "[N·m·s/rad], coulomb [N·m], static [N·m], stribeck_velocity [rad/s]"));
  EXPECT_THAT(BlockReference(BlockRegistry::Global().Get("flexible_load")), HasSubstr("mass [kg·m²]"));
  EXPECT_THAT(BlockReference(BlockRegistry::Global().Get("gain")), Not(HasSubstr("on a rotary diagram")));
}

TEST(DiagramDocumentAxis, ParameterSpecsReadInTheDiagramsUnits) {
  const DiagramDocument arm = DiagramDocument::Load(kRigidArm);
  EXPECT_EQ(arm.ParameterSpec("friction", "viscous").unit, "N·m·s/rad");
  EXPECT_EQ(arm.ParameterSpec("friction", "viscous").linear_unit, "N·s/m");
  EXPECT_EQ(arm.ParameterSpec("friction", "coulomb").unit, "N·m");
  EXPECT_EQ(arm.ParameterSpec("friction", "stribeck_velocity").unit, "rad/s");
  EXPECT_EQ(arm.ParameterSpec("inertia", "gain").unit, "");  // a free gain has no unit anywhere
  EXPECT_EQ(DiagramDocument::Load(kEmps).ParameterSpec("friction", "viscous").unit, "N·s/m");
}

// The loader takes a rotary friction written in its own units (it refused "N*m*s/rad": unit mismatch with N·s/m),
// with the value unchanged; the linear unit still stands for it; a unit of another quantity is refused, naming both.
TEST(DiagramAxisLoading, ARotaryFrictionWrittenInRotaryUnitsLoadsWithItsValue) {
  DiagramDocument arm = DiagramDocument::Load(kRigidArm);
  arm.SetParameter("friction", "viscous", json{{"value", 0.75}, {"unit", "N*m*s/rad"}});
  arm.SetParameter("friction", "coulomb", json{{"value", 1.5}, {"unit", "N*m"}});
  EXPECT_DOUBLE_EQ(arm.Parameter("friction", "viscous").get<double>(), 0.75);
  EXPECT_DOUBLE_EQ(arm.ElementParameters("friction").Number("coulomb"), 1.5);
  EXPECT_NO_THROW(BuildDiagram(arm.json(), kRigidArm.parent_path(), kRigidArm.string()));

  arm.SetParameter("friction", "viscous", json{{"value", 0.5}, {"unit", "N·s/m"}});  // the linear stand-in
  EXPECT_DOUBLE_EQ(arm.Parameter("friction", "viscous").get<double>(), 0.5);
  EXPECT_EQ(arm.json()["elements"][1]["parameters"]["viscous"]["unit"], "N·m·s/rad");  // written in the axis's unit

  arm.SetParameter("friction", "viscous", json{{"value", 1.0}, {"unit", "N·m·s/deg"}});  // converted to per rad
  EXPECT_NEAR(arm.Parameter("friction", "viscous").get<double>(), 180.0 / std::numbers::pi, 1e-9);

  try {
    arm.SetParameter("friction", "coulomb", json{{"value", 1.0}, {"unit", "kg"}});
    FAIL() << "a mass for a Coulomb torque was taken";
  } catch (const std::exception& e) {
    EXPECT_THAT(e.what(), HasSubstr("unit mismatch: given 'kg', this parameter is in 'N·m' on this diagram's axis "
                                    "(SI; 'N' on a linear axis)"));
  }
}

TEST(DiagramAxisLoading, ALinearDiagramStillRefusesARotaryUnit) {
  DiagramDocument emps = DiagramDocument::Load(kEmps);
  EXPECT_THROW(emps.SetParameter("friction", "viscous", json{{"value", 1.0}, {"unit", "N*m*s/rad"}}), DiagramError);
}

// improve adds a suggested block with {"value", "unit"} in the linear units its template writes: on a rotary diagram
// the element is written in the axis's units, with the same values.
TEST(DiagramAxisLoading, AnAddedElementIsWrittenInTheAxissUnits) {
  DiagramDocument arm = DiagramDocument::Load(kRigidArm);
  ElementSpec stribeck;
  stribeck.name = "stribeck";
  stribeck.type = "friction";
  stribeck.parameters = {{"coulomb", {{"value", 0.4}, {"unit", "N"}}},
                         {"stribeck_velocity", {{"value", 0.02}, {"unit", "m/s"}}},
                         {"viscous", 0.1}};
  const std::string name = arm.Add(stribeck);
  const json& p = arm.json()["elements"].back()["parameters"];
  EXPECT_EQ(p["coulomb"], (json{{"value", 0.4}, {"unit", "N·m"}}));
  EXPECT_EQ(p["stribeck_velocity"], (json{{"value", 0.02}, {"unit", "rad/s"}}));
  EXPECT_EQ(p["viscous"], 0.1);  // a bare number is in the parameter's unit already
  EXPECT_DOUBLE_EQ(arm.Parameter(name, "coulomb").get<double>(), 0.4);
}

// --set on a rotary diagram keeps a rotary quantity's unit (ReplacedParameterSlot with the spec on the axis).
TEST(DiagramAxisLoading, SetOverridesKeepTheRotaryUnitWritten) {
  json arm = DiagramDocument::Load(kRigidArm).json();
  arm["elements"][1]["parameters"]["viscous"] = {{"value", 2.0}, {"unit", "N·m·s/deg"}};
  ApplyOverrides(&arm, {{"friction", "viscous", json(180.0 / std::numbers::pi)}}, "rigid_arm.json");  // SI: per rad
  EXPECT_EQ(arm["elements"][1]["parameters"]["viscous"]["unit"], "N·m·s/deg");
  EXPECT_NEAR(arm["elements"][1]["parameters"]["viscous"]["value"].get<double>(), 1.0, 1e-12);
}

}  // namespace
}  // namespace mb

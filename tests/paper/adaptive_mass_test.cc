// The adaptive mass feedforward (blocks/adaptive_mass_feedforward.h) in the paper's loop
// (diagrams/paper/gp_loop_adaptive_mass.json): its mass estimate converges to the payload the nominal model lacks,
// it takes the payload's error away, and the stability analysis says what it covers.
#include <string>

#include <gtest/gtest.h>

#include "engine/diagram_loader.h"
#include "engine/simulator.h"
#include "tests/error_message.h"
#include "tools/workflow/loop_from_diagram.h"

namespace mb {
namespace {

const std::string kAdaptive = std::string(MB_SOURCE_DIR) + "/diagrams/paper/gp_loop_adaptive_mass.json";
const std::string kGpLoop = std::string(MB_SOURCE_DIR) + "/diagrams/paper/gp_loop.json";

SimulationResult RunLoop(const std::string& diagram, const std::vector<std::string>& sets) {
  std::vector<ParameterOverride> overrides;
  for (const auto& s : sets) overrides.push_back(ParameterOverride::Parse(s));
  return Simulator(LoadDiagram(diagram, overrides)).Run();
}

TEST(AdaptiveMassFeedforwardTest, TheMassEstimateConvergesToThePayload) {
  // The twin (its own cogging, friction and encoder: not the block's model) with the moving mass doubled.
  const SimulationResult r = RunLoop(kAdaptive, {"plant.payload_mass=0.2621"});
  const auto& mass = r.log.Column("mass_ff.mass");
  EXPECT_NEAR(mass.back(), 0.2621, 0.1 * 0.2621);
  // Without the payload it stays small: 0.02–0.04 kg of what correlates with the acceleration in closed loop (the
  // residual cogging drives the acceleration it is regressed against; docs/paper.md), far from the payload's 0.26.
  const SimulationResult none = RunLoop(kAdaptive, {});
  EXPECT_NEAR(none.log.Column("mass_ff.mass").back(), 0.0, 0.06);
  // And it takes the payload's error away: the loop with the payload tracks within 20 % of the loop without it.
  const double without = RunLoop(kGpLoop, {}).metrics.at("tracking_rmse");
  EXPECT_LT(r.metrics.at("tracking_rmse"), 1.2 * without);
  EXPECT_GT(RunLoop(kGpLoop, {"plant.payload_mass=0.2621"}).metrics.at("tracking_rmse"), 1.2 * without);
}

TEST(AdaptiveMassFeedforwardTest, StabilityAnalysisSaysWhatItCovers) {
  const StabilityReport report = AnalyseStability(LoadDiagram(kAdaptive));
  EXPECT_TRUE(report.loop.has_adaptive_mass);
  EXPECT_EQ(report.loop.adaptive_mass_min, -0.1);
  EXPECT_EQ(report.loop.adaptive_mass_max, 1.0);
  // The designed loop stays stable at both ends of the clamp (mass scaled by 0.2621/0.1621 and 0.2621/1.2621).
  EXPECT_TRUE(report.adaptive_mass_loop_stable[0]);
  EXPECT_TRUE(report.adaptive_mass_loop_stable[1]);
  bool noted = false;
  for (const auto& note : report.notes) noted = noted || note.rfind("adaptive mass: with the command scaled", 0) == 0;
  EXPECT_TRUE(noted);
  EXPECT_FALSE(AnalyseStability(LoadDiagram(kGpLoop)).loop.has_adaptive_mass);
  // A clamp that lets M_n + Δm̂ reach zero is reported, not certified.
  const StabilityReport collapsed =
      AnalyseStability(LoadDiagram(kAdaptive, {ParameterOverride::Parse("mass_ff.min_mass=-0.2621")}));
  EXPECT_FALSE(collapsed.adaptive_mass_loop_stable[0]);
}

TEST(AdaptiveMassFeedforwardTest, RefusesAStartBeyondTheClamp) {
  const std::string message = testing::ErrorOf(
      [] { LoadDiagram(kAdaptive, {ParameterOverride::Parse("mass_ff.initial_mass=3")}); });
  EXPECT_NE(message.find("mass_ff/initial_mass: 3 kg is outside [min_mass, max_mass] = [-0.1, 1] kg: start inside "
                         "the clamp"),
            std::string::npos)
      << message;
  const std::string order = testing::ErrorOf(
      [] { LoadDiagram(kAdaptive, {ParameterOverride::Parse("mass_ff.min_mass=1")}); });
  EXPECT_NE(order.find("mass_ff/min_mass: 1 kg is not below max_mass 1 kg: give min_mass < max_mass"),
            std::string::npos)
      << order;
}

}  // namespace
}  // namespace mb

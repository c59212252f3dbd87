// A real record the project did not generate (issue 47): a friction damper (BRFD) driven through ±1 in at 0.5 Hz,
// its force measured (diagrams/brfd/data, CC BY-SA 4.0). The first model one writes — mass, viscous, Coulomb,
// offset — misses the damper's hysteresis: after each reversal its force changes over millimetres of stroke, set by
// displacement. Before the hysteresis term the diagnosis named a 135 ms time delay on the same device at 0.5 Hz.
#include <filesystem>

#include <gtest/gtest.h>

#include "engine/diagram_document.h"
#include "engine/diagram_loader.h"
#include "tools/workflow/comparison.h"
#include "tools/workflow/improve.h"
#include "tools/workflow/measurement.h"

namespace mb {
namespace {

namespace fs = std::filesystem;

const fs::path kDiagram = fs::path(MB_SOURCE_DIR) / "diagrams" / "brfd" / "friction_damper.json";

TEST(BrfdRecord, CompareNamesHysteresisFirstWithItsStrokeAndNoDelay) {
  const nlohmann::json diagram = ReadDiagramJson(kDiagram);
  const MeasurementSettings settings;
  const MeasurementLog log =
      ReadMeasurementFor(diagram, (kDiagram.parent_path() / "data" / "char_0p5Hz_30lb_1in.csv").string(), settings);
  const DiagnosedComparison c = CompareAndDiagnose(diagram, kDiagram.parent_path(), kDiagram.string(), log, settings,
                                                   DiagramDocument(diagram).FreeParameters());
  ASSERT_TRUE(c.diagnosis.has_value());
  ASSERT_FALSE(c.diagnosis->effects.empty()) << c.diagnosis->summary;
  const DiagnosedEffect& first = c.diagnosis->effects.front();
  EXPECT_EQ(first.effect, "hysteresis") << c.diagnosis->summary;
  // Measured 94.6 % of the held-out residual, the stroke 8.75 mm: the force settles over a third of the ±25 mm
  // stroke's half, neither a Coulomb step (0) nor a spring over the travel.
  EXPECT_GT(first.score, 0.8);
  ASSERT_TRUE(first.parameters.count("stroke"));
  EXPECT_GT(first.parameters.at("stroke"), 4e-3);
  EXPECT_LT(first.parameters.at("stroke"), 15e-3);
  for (const auto& e : c.diagnosis->effects) EXPECT_NE(e.effect, "time_delay") << c.diagnosis->summary;
  // Held out: the error falls by far more than the 40 % the issue asks of improve.
  EXPECT_LT(c.diagnosis->heldout_rmse_after, 0.6 * c.diagnosis->heldout_rmse_base);
}

// improve adds the hysteresis block and refits it with the base: measured held out 5912 → 1084 N (−82 %).
TEST(BrfdRecord, ImproveAddsTheHysteresisBlockAndTheHeldOutErrorFalls) {
  const nlohmann::json diagram = ReadDiagramJson(kDiagram);
  ImproveSettings settings;
  settings.max_effects = 1;
  const MeasurementLog log = ReadMeasurementFor(
      diagram, (kDiagram.parent_path() / "data" / "char_0p5Hz_30lb_1in.csv").string(), settings.measurement);
  const ImproveResult r =
      ImproveModel(DiagramDocument(diagram, kDiagram.parent_path(), kDiagram.string()), log, nullptr, settings);
  const ImproveStep& last = r.last_accepted();
  ASSERT_EQ(last.effect, "hysteresis") << r.stop_reason;
  EXPECT_LT(last.rmse_heldout, 0.6 * r.first().rmse_heldout);
}

}  // namespace
}  // namespace mb

// improve's non-parametric fallback as files (tools/report/improve_report.h, WriteImproveFallback): the GP model and
// the amended diagram written side by side into --out load from there wherever --out is (an absolute model path
// outside the diagram's folder was refused by the loader: improve exited 2 after its work), and a fallback that cannot
// be added to the diagram is a note in improve.json, not an error.

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "engine/diagram_loader.h"
#include "models/gpr/residual_gpr.h"
#include "tools/report/improve_report.h"
#include "tools/report/output_files.h"

namespace mb {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;

const fs::path kEmps = fs::path(MB_SOURCE_DIR) / "diagrams" / "emps";

// A residual periodic in position (2.5 mm, 0.5 N) over a back-and-forth motion, and the GP fitted to it.
ResidualGprResult FittedFallback() {
  const Eigen::Index n = 4000;
  DiagnosisSignals s;
  s.time = Eigen::VectorXd::LinSpaced(n, 0.0, 1e-3 * static_cast<double>(n - 1));
  const Eigen::ArrayXd phase = 2.0 * std::numbers::pi * 0.5 * s.time.array();
  s.position = (0.1 + 0.05 * phase.sin()).matrix();
  s.velocity = (0.05 * std::numbers::pi * phase.cos()).matrix();
  s.acceleration = (-0.05 * std::numbers::pi * std::numbers::pi * phase.sin()).matrix();
  s.residual = (0.5 * (2.0 * std::numbers::pi * s.position.array() / 0.0025).sin()).matrix();
  ResidualGprOptions options;
  options.period = 0.0025;
  return FitResidualGpr(s, s.residual, options);
}

// A finished loop's result with one step: `diagram` as the last accepted, compared at output "force".
ImproveResult OneStep(const json& diagram) {
  ImproveResult result;
  ImproveStep step;
  step.training.fitted_diagram = diagram;
  ComparedOutput force;
  force.connector = "force";
  step.training.after.push_back(force);
  result.steps.push_back(step);
  return result;
}

class ImproveFallbackTest : public ::testing::Test {
 protected:
  void SetUp() override {
    out_ = fs::temp_directory_path() / ("mb_improve_fallback_" + std::to_string(::getpid()));
    fs::remove_all(out_);
    fs::create_directories(out_);
    WriteJsonFile(json{{"steps", json::array()}}, out_ / "improve.json");
  }
  void TearDown() override { fs::remove_all(out_); }
  fs::path out_;
};

TEST_F(ImproveFallbackTest, TheAmendedDiagramLoadsItsModelFromTheOutputFolder) {
  FallbackOutcome fallback;
  fallback.attempted = true;
  fallback.gpr = FittedFallback();
  ASSERT_TRUE(fallback.gpr->model);
  const json record =
      WriteImproveFallback(OneStep(ReadDiagramJson(kEmps / "rigid_body.json")), fallback, out_, kEmps);
  ASSERT_TRUE(record.contains("diagram")) << record.dump();
  const json written = ReadDiagramJson(out_ / "improved_with_gp.json");
  EXPECT_NO_THROW(BuildDiagram(written, out_, "improved_with_gp.json"));
  std::ifstream in(out_ / "improve.json");
  EXPECT_EQ(json::parse(in)["nonparametric_fallback"]["diagram"], record["diagram"]);
}

TEST_F(ImproveFallbackTest, AFallbackThatCannotBeAddedIsANote) {
  FallbackOutcome fallback;
  fallback.attempted = true;
  fallback.gpr = FittedFallback();
  json diagram = ReadDiagramJson(kEmps / "rigid_body.json");
  diagram["connectors"].erase(0);  // no position input: the GP block cannot be wired
  const json record = WriteImproveFallback(OneStep(diagram), fallback, out_, kEmps);
  EXPECT_FALSE(record.contains("diagram"));
  EXPECT_THAT(record.value("diagram_skipped", ""), ::testing::HasSubstr("needs the position"));
  EXPECT_TRUE(fs::exists(out_ / "residual_gpr.json"));
}

}  // namespace
}  // namespace mb

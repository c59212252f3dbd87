// A rotary diagram's parameters in rotary units (issue 40, item 8): the shipped rotary arm
// (diagrams/rotary/rigid_arm.json: rad, N·m) fitted and compared against an arm record made here — its own simulator,
// not the blocks': a smooth Coulomb law tanh(ω/ω_c), viscous friction, an inertia, torque noise, two swing
// frequencies — must report its friction's viscous coefficient in N·m·s/rad and its Coulomb level in N·m (they were
// printed as N·s/m and N), with the SI numbers unchanged.

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include <unistd.h>

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "engine/diagram_document.h"
#include "tools/report/compare_report.h"
#include "tools/workflow/compare.h"
#include "tools/workflow/fit.h"
#include "tools/workflow/measurement.h"

namespace mb {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::Not;

const fs::path kRigidArm = fs::path(MB_SOURCE_DIR) / "diagrams" / "rotary" / "rigid_arm.json";

// The arm's truth: inertia J [kg·m²], viscous B [N·m·s/rad], Coulomb C [N·m], noise σ [N·m].
constexpr double kInertia = 0.12, kViscous = 0.35, kCoulomb = 0.8, kNoise = 0.02;

// 16 s at 1 kHz of an arm swung by two sines (±1.2 rad), the torque of the law above with Gaussian noise; the angle,
// angular velocity and acceleration as the diagram's connectors read them (angle_rad, velocity_rad_s, …).
fs::path WriteArmRecord(const fs::path& folder) {
  fs::create_directories(folder);
  const fs::path path = folder / "arm.csv";
  std::ofstream out(path);
  out << "time_s,angle_rad,velocity_rad_s,acceleration_rad_s2,torque_Nm\n";
  std::mt19937 rng(40);
  std::normal_distribution<double> noise(0.0, kNoise);
  const double w1 = 2.0 * M_PI * 0.35, w2 = 2.0 * M_PI * 0.9;
  for (int k = 0; k <= 16000; ++k) {
    const double t = 1e-3 * k;
    const double q = 0.9 * std::sin(w1 * t) + 0.3 * std::sin(w2 * t + 0.4);
    const double w = 0.9 * w1 * std::cos(w1 * t) + 0.3 * w2 * std::cos(w2 * t + 0.4);
    const double a = -0.9 * w1 * w1 * std::sin(w1 * t) - 0.3 * w2 * w2 * std::sin(w2 * t + 0.4);
    const double torque = kInertia * a + kViscous * w + kCoulomb * std::tanh(w / 0.02) + noise(rng);
    out << fmt::format("{:.6f},{:.9g},{:.9g},{:.9g},{:.9g}\n", t, q, w, a, torque);
  }
  return path;
}

MeasurementSettings ArmSettings() {
  MeasurementSettings s;
  s.position_column = "angle_rad";
  return s;
}

const nlohmann::json* FitParameter(const nlohmann::json& fit, const std::string& name) {
  for (const auto& p : fit.at("parameters")) {
    if (p.at("name") == name) return &p;
  }
  return nullptr;
}

class RotaryUnits : public ::testing::Test {
 protected:
  void SetUp() override {
    folder_ = fs::temp_directory_path() /
              fmt::format("mb_rotary_units_{}_{}", ::testing::UnitTest::GetInstance()->current_test_info()->name(),
                          static_cast<long>(::getpid()));
    record_ = WriteArmRecord(folder_);
  }
  void TearDown() override { fs::remove_all(folder_); }
  fs::path folder_, record_;
};

TEST_F(RotaryUnits, FitReportsTheFrictionInNewtonMetres) {
  const DiagramDocument arm = DiagramDocument::Load(kRigidArm);
  FitSettings settings;
  settings.measurement = ArmSettings();
  const MeasurementLog log = ReadMeasurementFor(arm.json(), record_.string(), settings.measurement);
  const nlohmann::json fit = FitToMeasurement(arm, log, record_.string(), settings).ToJson();

  const nlohmann::json* viscous = FitParameter(fit, "friction.viscous");
  const nlohmann::json* coulomb = FitParameter(fit, "friction.coulomb");
  const nlohmann::json* inertia = FitParameter(fit, "inertia.gain");
  ASSERT_TRUE(viscous && coulomb && inertia) << fit.dump(1);
  EXPECT_EQ(viscous->at("unit"), "N·m·s/rad");
  EXPECT_EQ(coulomb->at("unit"), "N·m");
  EXPECT_EQ(inertia->at("unit"), "");  // a gain: its unit is the diagram's to say (J [kg·m²] in its description)
  // The numbers are the SI values per radian: the truth within a few per cent (the smooth Coulomb law is not the
  // model's sign, so the two share a little).
  EXPECT_NEAR(viscous->at("estimate").get<double>(), kViscous, 0.05 * kViscous);
  EXPECT_NEAR(coulomb->at("estimate").get<double>(), kCoulomb, 0.05 * kCoulomb);
  EXPECT_NEAR(inertia->at("estimate").get<double>(), kInertia, 0.02 * kInertia);
  EXPECT_THAT(fit.dump(), Not(HasSubstr("N·s/m")));
}

TEST_F(RotaryUnits, CompareReportShowsTheRotaryUnitsAndNoLinearOnes) {
  const DiagramDocument arm = DiagramDocument::Load(kRigidArm);
  CompareSettings settings;
  settings.measurement = ArmSettings();
  settings.gpr_fallback = false;
  const MeasurementLog log = ReadMeasurementFor(arm.json(), record_.string(), settings.measurement);
  const CompareOutcome outcome = Compare(arm, log, settings);
  CompareFiles files;
  files.diagram = kRigidArm.string();
  files.measurement = record_.string();
  files.out = folder_ / "compare";
  files.position_column = "angle_rad";
  const nlohmann::json written = WriteCompareResults(outcome, log, files);
  EXPECT_EQ(FitParameter(written.at("fit"), "friction.viscous")->at("unit"), "N·m·s/rad");

  std::ifstream in(files.out / "report.html");
  std::stringstream html;
  html << in.rdbuf();
  // The fitted-parameter table and the diagram's block panel: per radian, in N·m.
  EXPECT_THAT(html.str(), HasSubstr("<td>N·m·s/rad</td>"));
  EXPECT_THAT(html.str(), HasSubstr(R"("name":"viscous","unit":"N·m·s/rad")"));
  EXPECT_THAT(html.str(), HasSubstr(R"("name":"coulomb","unit":"N·m")"));
  EXPECT_THAT(html.str(), HasSubstr(R"("name":"stribeck_velocity","unit":"rad/s")"));
  EXPECT_THAT(html.str(), Not(HasSubstr("N·s/m")));
}

}  // namespace
}  // namespace mb

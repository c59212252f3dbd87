// A diagram whose position is no length (issue 25, item 1): an electronic Duffing oscillator logged in volts, its
// output voltage standing for the position ("quantity": "position" on diagrams/duffing/linear_oscillator.json). The
// record comes from the generator below, which shares no code with the project: an analog-computer Duffing circuit
// a·ẍ + b·ẋ + k·x + c·x³ = u integrated by RK4 on 0.1 ms sub-steps, driven by a multi-sine, its output read by a
// 16-bit ADC on ±10 V and the drive with 5 mV of noise. The linear model leaves out the multiplier's cubic stiffness
// c·x³; compare must name it (position_dependent_force, a smooth force of the position), and improve must add it on
// the volts connector (it refused: "needs the position: add an input connector with unit m") and reach the floor.

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <optional>
#include <random>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "engine/diagram_loader.h"
#include "models/diagnosis/signal_processing.h"
#include "tools/workflow/comparison.h"
#include "tools/workflow/improve.h"
#include "tools/workflow/measurement.h"

namespace mb {
namespace {

namespace fs = std::filesystem;

// The circuit: ω0 = 2π·5 Hz, ζ = 0.1 (a = 1/ω0², b = 2ζ/ω0), k = 1, c = 0.08 /V², offset 12 mV.
constexpr double kOmega0 = 2.0 * 3.14159265358979323846 * 5.0;
constexpr double kA = 1.0 / (kOmega0 * kOmega0), kB = 2.0 * 0.1 / kOmega0, kK = 1.0, kC = 0.08, kOffset = 0.012;

double Drive(double t, const std::array<double, 5>& phases) {
  static constexpr std::array<double, 5> kHz{0.7, 1.9, 3.1, 4.3, 6.1};
  static constexpr std::array<double, 5> kVolts{1.2, 0.9, 0.6, 0.35, 0.3};
  double u = 0.0;
  for (std::size_t i = 0; i < kHz.size(); ++i) u += kVolts[i] * std::sin(2.0 * 3.14159265358979323846 * kHz[i] * t + phases[i]);
  return u;
}

// Writes time_s, x_V, drive_V at `rate` [Hz] for `seconds` and returns the path.
fs::path WriteDuffingLog(const fs::path& path, unsigned seed, double seconds = 16.0, double rate = 1000.0) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> phase(0.0, 6.283185307179586);
  std::normal_distribution<double> drive_noise(0.0, 5e-3);
  const std::array<double, 5> phases{phase(rng), phase(rng), phase(rng), phase(rng), phase(rng)};
  const auto acceleration = [&](double t, double x, double v) {
    return (Drive(t, phases) - kOffset - kB * v - kK * x - kC * x * x * x) / kA;
  };
  constexpr double kLsb = 20.0 / 65536.0, kSub = 1e-4;
  std::ofstream out(path);
  out << "time_s,x_V,drive_V\n";
  double x = 0.0, v = 0.0, t = 0.0;
  const int samples = static_cast<int>(seconds * rate);
  const int sub_steps = static_cast<int>(std::lround(1.0 / (rate * kSub)));
  for (int k = 0; k < samples; ++k) {
    out << fmt::format("{:.6f},{:.9g},{:.9g}\n", t, kLsb * std::round(x / kLsb), Drive(t, phases) + drive_noise(rng));
    for (int s = 0; s < sub_steps; ++s) {  // RK4 on (x, v)
      const double k1x = v, k1v = acceleration(t, x, v);
      const double k2x = v + 0.5 * kSub * k1v, k2v = acceleration(t + 0.5 * kSub, x + 0.5 * kSub * k1x, k2x);
      const double k3x = v + 0.5 * kSub * k2v, k3v = acceleration(t + 0.5 * kSub, x + 0.5 * kSub * k2x, k3x);
      const double k4x = v + kSub * k3v, k4v = acceleration(t + kSub, x + kSub * k3x, k4x);
      x += kSub / 6.0 * (k1x + 2.0 * k2x + 2.0 * k3x + k4x);
      v += kSub / 6.0 * (k1v + 2.0 * k2v + 2.0 * k3v + k4v);
      t += kSub;
    }
    t = (k + 1) / rate;
  }
  return path;
}

class VoltsOscillator : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() / fmt::format("mb_volts_oscillator_{}", ::testing::UnitTest::GetInstance()->random_seed());
    fs::create_directories(dir_);
    diagram_ = ReadDiagramJson(kFolder / "linear_oscillator.json");
    settings_.measurement.position_column = "x_V";
    training_.emplace(ReadMeasurementFor(diagram_, WriteDuffingLog(dir_ / "training.csv", 11).string(), settings_.measurement));
    validation_.emplace(ReadMeasurementFor(diagram_, WriteDuffingLog(dir_ / "validation.csv", 23).string(), settings_.measurement));
  }
  void TearDown() override { fs::remove_all(dir_); }

  // The truth's drive evaluated on the motion as compare derives it, filtered at the derivative cut-off, against the
  // logged drive: what the best model reaches.
  double NoiseFloor(const MeasurementLog& log) const {
    const Eigen::VectorXd x = log.column("x_V"), v = log.column("velocity_V_s"), a = log.column("acceleration_V_s2");
    const Eigen::VectorXd truth = (kA * a + kB * v + kK * x + kC * x.array().cube().matrix()).array() + kOffset;
    const Eigen::VectorXd filtered =
        ZeroPhaseLowPass(truth, MedianTimeStep(log.time()), DerivativeCutoffHz(settings_.measurement, log));
    return Rmse(log.column("drive_V"), filtered);
  }

  const fs::path kFolder = fs::path(MB_SOURCE_DIR) / "diagrams" / "duffing";
  fs::path dir_;
  nlohmann::json diagram_;
  ImproveSettings settings_;
  std::optional<MeasurementLog> training_, validation_;
};

TEST_F(VoltsOscillator, TheDerivedColumnsKeepTheVoltsAndTheDiagramLoads) {
  EXPECT_TRUE(training_->has_column("velocity_V_s"));
  EXPECT_TRUE(training_->has_column("acceleration_V_s2"));
  const double swing = training_->column("x_V").cwiseAbs().maxCoeff();
  EXPECT_GT(swing, 1.5) << "the cubic stiffness must matter: c·x³ against k·x";
}

TEST_F(VoltsOscillator, CompareNamesTheCubicStiffnessAsAForceOfThePosition) {
  const DiagnosedComparison compared = CompareAndDiagnose(diagram_, kFolder, "linear_oscillator.json", *training_,
                                                          settings_.measurement, diagram_["free"]);
  ASSERT_TRUE(compared.diagnosis.has_value()) << compared.diagnosis_skipped;
  ASSERT_FALSE(compared.diagnosis->effects.empty()) << compared.diagnosis->summary;
  fmt::print("{}\n", compared.diagnosis->summary);
  std::string notes;
  for (const auto& n : compared.diagnosis->notes) notes += n + "\n";
  EXPECT_EQ(compared.diagnosis->effects.front().effect, "position_dependent_force") << compared.diagnosis->summary << notes;
  EXPECT_EQ(compared.diagnosis->summary.find(" mm"), std::string::npos) << "a voltage is no length: "
                                                                        << compared.diagnosis->summary;
}

// The same circuit logged at 40 Hz, eight samples per period of its resonance (a fast oscillation sampled at a few
// times its frequency, as the Silverbox benchmark is): each sample-to-sample step is a good part of the travel. The
// polynomial's guard once measured the travel in median steps and skipped it without a note (issue 45).
TEST_F(VoltsOscillator, CompareNamesItSampledAtAFewTimesItsFrequency) {
  const MeasurementLog coarse =
      ReadMeasurementFor(diagram_, WriteDuffingLog(dir_ / "coarse.csv", 31, 240.0, 40.0).string(), settings_.measurement);
  const DiagnosedComparison compared =
      CompareAndDiagnose(diagram_, kFolder, "linear_oscillator.json", coarse, settings_.measurement, diagram_["free"]);
  ASSERT_TRUE(compared.diagnosis.has_value()) << compared.diagnosis_skipped;
  std::string notes;
  for (const auto& n : compared.diagnosis->notes) notes += n + "\n";
  ASSERT_FALSE(compared.diagnosis->effects.empty()) << compared.diagnosis->summary << notes;
  EXPECT_EQ(compared.diagnosis->effects.front().effect, "position_dependent_force") << compared.diagnosis->summary << notes;
}

TEST_F(VoltsOscillator, ImproveAddsItOnTheVoltsConnectorAndReachesTheFloor) {
  const ImproveResult improved =
      ImproveModel(DiagramDocument(diagram_, kFolder, "linear_oscillator.json"), *training_, &*validation_, settings_);
  const double floor = NoiseFloor(*validation_);
  const double before = improved.first().rmse_heldout, after = improved.last_accepted().rmse_heldout;
  fmt::print("held-out RMSE {:.4f} V → {:.4f} V (floor {:.4f} V): {}\n", before, after, floor, improved.stop_reason);
  EXPECT_TRUE(std::any_of(improved.steps.begin(), improved.steps.end(), [](const ImproveStep& s) {
    return s.accepted && s.effect == "position_dependent_force";
  })) << improved.stop_reason;
  EXPECT_LT(after, 0.2 * before);
  EXPECT_LE(after, 1.3 * floor) << "before " << before << " V, floor " << floor << " V";
}

}  // namespace
}  // namespace mb

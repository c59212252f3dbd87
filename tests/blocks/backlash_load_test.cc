// backlash_load (the block `improve` adds for a diagnosed load behind a play) against the physics it models, each
// case checked by what does not depend on the block's stepping scheme: inside the play the load is not touched and
// the force is zero; the load is picked up when the motor has crossed half the gap; without a play and well below
// the shaft's mode the load follows rigidly, f = m_L·a. And its parameter checks.

#include <cmath>
#include <numbers>
#include <vector>

#include "tests/blocks/block_test_util.h"

namespace mb {
namespace {

using nlohmann::json;
using testing::Build;
using testing::BuildError;
using testing::Connect;
using testing::Element;
using testing::MakeDiagram;
using ::testing::HasSubstr;

using testing::kTwoPi;

constexpr double kTs = 1e-3, kMotorHz = 1.0, kLoadMass = 5.0;

// The block's force over 1 s with the motor at x = 0.1 + A·(1 − cos 2πf_m·t) (starting at rest), v its derivative, the
// block's sample time (and the diagram's step) ts [s].
std::vector<double> Force(double amplitude, const json& load, double ts = kTs, double motor_hz = kMotorHz) {
  json parameters = load;
  parameters["mass"] = kLoadMass;
  const json j = MakeDiagram(
      {Element("x", "sine",
               {{"amplitude", -amplitude}, {"bias", 0.1 + amplitude}, {"frequency_hz", motor_hz},
                {"phase", 0.5 * std::numbers::pi}}),
       Element("v", "sine", {{"amplitude", amplitude * kTwoPi * motor_hz}, {"frequency_hz", motor_hz}}),
       Element("load", "backlash_load", parameters, {ts, 0.0})},
      {Connect("x.y", "load.x"), Connect("v.y", "load.v")}, {"load.f"}, 1.0, ts);
  return Simulator(Build(j)).Run().log.Column("load.f");
}

double Time(std::size_t i) { return kTs * static_cast<double>(i); }

TEST(BacklashLoadTest, InsideThePlayTheLoadIsNotTouched) {
  // A 0.4 mm stroke inside a 1 mm play that the load starts centred in: no contact, no force, ever.
  const std::vector<double> f =
      Force(0.2e-3, {{"frequency_hz", 20.0}, {"damping_ratio", 0.1}, {"backlash", 1e-3}, {"load_damping", 0.5}});
  for (std::size_t i = 0; i < f.size(); ++i) EXPECT_EQ(f[i], 0.0) << "t = " << Time(i);
}

TEST(BacklashLoadTest, TheLoadIsPickedUpOnceTheMotorHasCrossedHalfThePlay) {
  // A 1 mm play: contact when A·(1 − cos 2πf_m·t) = 0.5 mm with A = 1 mm, at t = 1/6 s; the load is then pushed
  // forward (f > 0, the sign of the drive force).
  const std::vector<double> f =
      Force(1e-3, {{"frequency_hz", 20.0}, {"damping_ratio", 0.1}, {"backlash", 1e-3}, {"load_damping", 0.0}});
  const double contact = 1.0 / 6.0;
  for (std::size_t i = 0; Time(i) < contact - 2 * kTs; ++i) EXPECT_EQ(f[i], 0.0) << "t = " << Time(i);
  const std::size_t after = static_cast<std::size_t>(std::lround((contact + 0.01) / kTs));
  EXPECT_GT(f[after], 0.0);
}

TEST(BacklashLoadTest, WithoutAPlayAndFarBelowItsModeTheLoadFollowsRigidly) {
  // f_m/f_r = 1/50: the load's lag is (f_m/f_r)² and 2ζ(f_m/f_r)³ of the rigid force m_L·a, under 1 %; the start's
  // ring (ζ = 0.7) has died out after 0.1 s.
  const double amplitude = 1e-3;
  const std::vector<double> f =
      Force(amplitude, {{"frequency_hz", 50.0}, {"damping_ratio", 0.7}, {"backlash", 0.0}, {"load_damping", 0.0}});
  const double w = kTwoPi * kMotorHz, peak = kLoadMass * amplitude * w * w;
  for (std::size_t i = 100; i < f.size(); ++i) {
    EXPECT_NEAR(f[i], peak * std::cos(w * Time(i)), 0.02 * peak) << "t = " << Time(i);
  }
}

TEST(BacklashLoadTest, ItsImpactsAtAMillisecondAgreeWithAHundredTimesFinerStep) {
  // The motor 20 mm forth and back three times a second (up to 0.19 m/s) across a 1.2 mm play to an 18 Hz shaft
  // (ζ = 0.1, β = 0.6 /s): after each reversal the load crosses the play and meets the other side with an impact. At
  // 1 ms the block takes one Runge–Kutta sub-step a sample (ω·Ts = 0.11), and a step across the instant the load meets
  // or leaves a side is first order there (the damper's force jumps): 3.5 % of the force's RMS from the 10 µs run.
  // Redoing those steps in 8 micro-steps gave 0.07 % (commit ab0534d; tried and left out, docs/diagnosis.md "A load
  // behind a play"). The bound keeps the block from drifting further.
  const json load = {{"frequency_hz", 18.0}, {"damping_ratio", 0.1}, {"backlash", 1.2e-3}, {"load_damping", 0.6}};
  constexpr int kFiner = 100;
  constexpr double kAmplitude = 10e-3, kHz = 3.0;
  const std::vector<double> f = Force(kAmplitude, load, kTs, kHz), fine = Force(kAmplitude, load, kTs / kFiner, kHz);
  double error = 0.0, power = 0.0;
  for (std::size_t i = 0; i < f.size(); ++i) {
    error += std::pow(f[i] - fine[i * kFiner], 2);
    power += std::pow(fine[i * kFiner], 2);
  }
  ASSERT_GT(power, 0.0);
  EXPECT_LT(std::sqrt(error / power), 0.05) << "the force's RMS error against the 10 µs run, relative to its RMS";
}

TEST(BacklashLoadTest, RefusesANonPositiveModeANegativePlayAndNoSampleTime) {
  auto error = [](const json& parameters, const json& sample_time) {
    return BuildError(MakeDiagram(
        {Element("x", "constant", {{"value", 0.1}}), Element("v", "constant", {{"value", 0.0}}),
         Element("load", "backlash_load", parameters, sample_time)},
        {Connect("x.y", "load.x"), Connect("v.y", "load.v")}, json::array(), 0.1, kTs));
  };
  const json ts = json::array({kTs, 0.0});
  EXPECT_THAT(error({{"mass", 1.0}, {"frequency_hz", 0.0}, {"backlash", 1e-3}}, ts),
              HasSubstr("frequency_hz must be a finite value > 0"));
  EXPECT_THAT(error({{"mass", 1.0}, {"frequency_hz", 20.0}, {"backlash", -1e-3}}, ts),
              HasSubstr("backlash must be a finite value >= 0"));
  EXPECT_THAT(error({{"mass", 1.0}, {"frequency_hz", 20.0}, {"backlash", 1e-3}}, nullptr), HasSubstr("sampleTime"));
  EXPECT_EQ(error({{"mass", 1.0}, {"frequency_hz", 20.0}, {"backlash", 1e-3}}, ts), "");
}

}  // namespace
}  // namespace mb

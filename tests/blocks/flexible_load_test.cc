// flexible_load (the block `compare --suggest` inserts for a diagnosed resonance) against its header's equation:
// the two-mass model's force for a step of the motor acceleration, and its parameter checks.

#include <cmath>
#include <numbers>

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

// a = A from t = 0, load at rest: e(t) = −(A/ω²)(1 − e^{−ζωt}(cos ω_d t + ζω/ω_d sin ω_d t)),
// ė(t) = −(A/ω_d) e^{−ζωt} sin ω_d t, f = −m(ω² e + 2ζω ė): rings at ω_d around m·A, settles at m·A.
TEST(FlexibleLoadTest, StepOfTheAccelerationRingsAndSettlesAtTheLoadTimesA) {
  const double mass = 6.0, f_r = 31.7, zeta = 0.02, accel = 2.0;
  const json j = MakeDiagram({Element("a", "constant", {{"value", accel}}),
                              Element("load", "flexible_load",
                                      {{"mass", mass}, {"frequency_hz", f_r}, {"damping_ratio", zeta}})},
                             Connect("a.y", "load.a"), {"load.f"}, 1.0, 1e-3, {{"type", "rk4"}, {"step", 1e-4}});
  const auto r = Simulator(Build(j)).Run();
  const auto& f = r.log.Column("load.f");
  const double w = kTwoPi * f_r, wd = w * std::sqrt(1.0 - zeta * zeta);
  for (std::size_t i = 0; i < f.size(); ++i) {
    const double t = r.log.time[i], decay = std::exp(-zeta * w * t);
    const double e = -(accel / (w * w)) * (1.0 - decay * (std::cos(wd * t) + zeta * w / wd * std::sin(wd * t)));
    const double de = -(accel / wd) * decay * std::sin(wd * t);
    EXPECT_NEAR(f[i], -mass * (w * w * e + 2.0 * zeta * w * de), 1e-6 * mass * accel) << "t = " << t;
  }
  EXPECT_NEAR(f.front(), 0.0, 1e-12);  // no feedthrough: the load needs time to follow
  EXPECT_NEAR(f.back(), mass * accel, 0.05 * mass * accel);
}

TEST(FlexibleLoadTest, RejectsANonPositiveFrequencyOrDamping) {
  auto error = [](const json& parameters) {
    return BuildError(MakeDiagram({Element("a", "constant", {{"value", 1.0}}), Element("load", "flexible_load", parameters)},
                                  Connect("a.y", "load.a"), json::array(), 0.1, 1e-3));
  };
  EXPECT_THAT(error({{"mass", 1.0}, {"frequency_hz", 0.0}}), HasSubstr("frequency_hz must be a finite value > 0"));
  EXPECT_THAT(error({{"mass", 1.0}, {"frequency_hz", 40.0}, {"damping_ratio", 0.0}}),
              HasSubstr("damping_ratio must be a finite value > 0"));
  EXPECT_THAT(error({{"frequency_hz", 40.0}}), HasSubstr("mass"));
  EXPECT_EQ(error({{"mass", -2.0}, {"frequency_hz", 40.0}}), "");
}

}  // namespace
}  // namespace mb

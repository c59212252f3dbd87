// The backlash_friction block (blocks/backlash_friction.h) against the play operator written out here: a motor moving
// x = 0.1 + 2 mm·sin(2πt), v = its derivative, through a 1 mm play; the load's 4 N friction is felt only once the
// play is taken up after each reversal.

#include <algorithm>
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

TEST(BacklashFrictionTest, FrictionIsFeltOnlyOnceThePlayIsTakenUp) {
  const double ts = 1e-3, amplitude = 2e-3, gap = 1e-3, load = 4.0, dead_band = 1e-4;
  const json j = MakeDiagram(
      {Element("x", "sine", {{"amplitude", amplitude}, {"bias", 0.1}}),
       Element("v", "sine", {{"amplitude", kTwoPi * amplitude}, {"phase", std::numbers::pi / 2}}),
       Element("play", "backlash_friction", {{"gap", gap}, {"load_friction", load}, {"dead_band", dead_band}},
               {ts, 0.0})},
      {Connect("x.y", "play.x"), Connect("v.y", "play.v")}, {"play.f"}, 2.0, ts);
  const auto r = Simulator(Build(j)).Run();
  const auto& f = r.log.Column("play.f");
  double far = 0.1;  // the play starts centred on x(0)
  int engaged = 0, free_travel = 0;
  for (std::size_t i = 0; i < f.size(); ++i) {
    const double t = r.log.time[i];
    const double x = 0.1 + amplitude * std::sin(kTwoPi * t), v = kTwoPi * amplitude * std::cos(kTwoPi * t);
    far = std::clamp(far, x - 0.5 * gap, x + 0.5 * gap);
    const bool taken_up = std::abs(x - far) >= 0.5 * gap * (1.0 - 1e-6);
    const double sign = std::abs(v) <= dead_band ? 0.0 : (v > 0.0 ? 1.0 : -1.0);
    EXPECT_NEAR(f[i], taken_up ? load * sign : 0.0, 1e-12) << "t = " << t;
    (taken_up ? engaged : free_travel) += 1;
  }
  // After each reversal the motor crosses the 1 mm gap of a 4 mm stroke: the load is free for a good part of it.
  EXPECT_GT(free_travel, 300);
  EXPECT_GT(engaged, 1000);
}

TEST(BacklashFrictionTest, NeedsASampleTimeAndAPositiveGap) {
  EXPECT_THAT(BuildError(MakeDiagram({Element("p", "backlash_friction", {{"gap", 1e-3}})}, json::array(), json::array(),
                                     0.1, 1e-3)),
              HasSubstr("sampleTime"));
  EXPECT_THAT(BuildError(MakeDiagram({Element("p", "backlash_friction", {{"gap", 0.0}}, {1e-3, 0.0})}, json::array(),
                                     json::array(), 0.1, 1e-3)),
              HasSubstr("gap"));
}

}  // namespace
}  // namespace mb

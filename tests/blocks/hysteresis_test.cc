// The hysteresis block (blocks/hysteresis.h) against two elasto-slide elements written out here, on a position
// x = 0.1 + 3 mm·sin(2πft): the force follows the stroke since the last reversal, saturating element by element, and
// the loop is the same at 1 Hz and 4 Hz (rate independence: set by displacement, not by time).

#include <algorithm>
#include <cmath>
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

constexpr double kAmplitude = 3e-3;
const std::vector<double> kDisplacements = {0.5e-3, 2e-3}, kForces = {4.0, 10.0};

// The block's output over one second of x = 0.1 + A·sin(2πf·t), sampled at 1 kHz.
std::vector<double> Loop(double frequency) {
  const double ts = 1e-3;
  const json j = MakeDiagram(
      {Element("x", "sine", {{"amplitude", kAmplitude}, {"bias", 0.1}, {"frequency_hz", frequency}}),
       Element("h", "hysteresis", {{"breakaway_displacements", kDisplacements}, {"breakaway_forces", kForces}},
               {ts, 0.0})},
      {Connect("x.y", "h.x")}, {"h.f"}, 1.0, ts);
  return Simulator(Build(j)).Run().log.Column("h.f");
}

TEST(HysteresisTest, EachElementFollowsTheStrokeSinceTheLastReversalUpToItsBreakawayForce) {
  const double frequency = 1.0;
  const std::vector<double> f = Loop(frequency);
  std::vector<double> play(kDisplacements.size(), 0.1);  // every element relaxed at x(0)
  double at_top = 0.0, at_bottom = 0.0;
  for (std::size_t i = 0; i < f.size(); ++i) {
    const double t = 1e-3 * static_cast<double>(i);
    const double x = 0.1 + kAmplitude * std::sin(kTwoPi * frequency * t);
    double expected = 0.0;
    for (std::size_t k = 0; k < play.size(); ++k) {
      play[k] = std::clamp(play[k], x - kDisplacements[k], x + kDisplacements[k]);
      expected += kForces[k] * (x - play[k]) / kDisplacements[k];
    }
    EXPECT_NEAR(f[i], expected, 1e-9) << "t = " << t;
    if (std::abs(t - 0.25) < 1e-9) at_top = f[i];
    if (std::abs(t - 0.75) < 1e-9) at_bottom = f[i];
  }
  // A 6 mm stroke saturates both elements: ±(4 + 10) N at the ends of the stroke.
  EXPECT_NEAR(at_top, 14.0, 1e-9);
  EXPECT_NEAR(at_bottom, -14.0, 1e-9);
}

TEST(HysteresisTest, TheLoopIsTheSameAtAnySpeed) {
  const std::vector<double> slow = Loop(1.0), fast = Loop(4.0);
  // The same phase of the second half of each cycle (past the first loading): t = 0.5 + s at 1 Hz, 0.125 + s/4 at 4 Hz.
  // The fast loop's samples miss the top of the stroke by up to 0.24 µm (a quarter of a 1 ms step at 4 Hz): 2 mN.
  for (int k = 0; k < 250; k += 10) {
    EXPECT_NEAR(slow[static_cast<std::size_t>(500 + 2 * k)], fast[static_cast<std::size_t>(125 + k / 2)], 0.01) << k;
  }
}

TEST(HysteresisTest, RefusesMismatchedElementsAndNeedsASampleTime) {
  const auto build = [](const json& parameters, const json& sample_time) {
    return BuildError(MakeDiagram({Element("h", "hysteresis", parameters, sample_time)}, json::array(), json::array(),
                                  0.1, 1e-3));
  };
  const json one = {{"breakaway_displacements", json::array({1e-3})}, {"breakaway_forces", json::array({1.0})}};
  const json two_one = {{"breakaway_displacements", json::array({1e-3, 2e-3})},
                        {"breakaway_forces", json::array({1.0})}};
  const json zero = {{"breakaway_displacements", json::array({0.0})}, {"breakaway_forces", json::array({1.0})}};
  const json ts = json::array({1e-3, 0.0});
  EXPECT_THAT(build(one, nullptr), HasSubstr("sampleTime"));
  EXPECT_THAT(build(two_one, ts), HasSubstr("one force per element"));
  EXPECT_THAT(build(zero, ts), HasSubstr("breakaway_displacements[0]"));
}

}  // namespace
}  // namespace mb

// The grammar-draw generator (tests/diagnosis/grammar_draws.h): its own checks, and a quick subset of draws through
// compare (the full benchmark, 300 draws with improve: bench_grammar, `make bench-grammar`).
#include <cmath>
#include <filesystem>
#include <string>

#include <gtest/gtest.h>

#include "tests/diagnosis/grammar_bench.h"
#include "tests/diagnosis/grammar_draws.h"

namespace mb::grammar {
namespace {

TEST(GrammarDraws, NinetyFourPairsAreDrawn) {
  int pairs = 0;
  for (const auto& mu : MultiplierIds()) {
    for (const auto& mo : ModulatorIds()) pairs += IsDrawnPair(mu, mo) ? 1 : 0;
  }
  EXPECT_EQ(pairs, 94);
  EXPECT_FALSE(IsDrawnPair("slip", "constant"));
  EXPECT_TRUE(IsDrawnPair("velocity_speed", "constant"));
}

TEST(GrammarDraws, ADrawIsItsSeedsAlone) {
  const GrammarDraw a = Draw(7), b = Draw(7);
  EXPECT_EQ(a.pair(), b.pair());
  EXPECT_EQ(a.amplitude, b.amplitude);
  const Record r = Simulate(a, Run::kTraining), twin = Simulate(a, Run::kTraining, false);
  ASSERT_EQ(r.time.size(), twin.time.size());
  EXPECT_EQ(r.reference, twin.reference);             // the same trajectory
  EXPECT_GT(r.effect_force.cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ(twin.effect_force.cwiseAbs().maxCoeff(), 0.0);
  EXPECT_TRUE(r.force.allFinite());
  EXPECT_TRUE(Draw(kNoiseOnlySeedBase + 1).noise_only);
}

// The first eight seeds and one noise-only draw through compare, as a user runs it. The benchmark names about
// two thirds of the draws right (docs/diagnosis.md, "Random draws from the grammar"); this fails when the quick subset
// falls below five of eight, or when the noise-only draw names anything with a share of 2 % or more.
TEST(GrammarDraws, AQuickSubsetIsNamedAndTheNoiseOnlyDrawNamesNothing) {
  const std::filesystem::path folder = std::filesystem::temp_directory_path() / "mb_grammar_draws_test";
  int named = 0;
  std::string misses;
  for (unsigned seed = 1; seed <= 8; ++seed) {
    const DrawResult r = RunDraw(Draw(seed), folder / std::to_string(seed), false);
    named += r.named_right ? 1 : 0;
    if (!r.named_right) misses += " " + r.draw.Describe() + " -> " + r.named_pair + ";";
  }
  EXPECT_GE(named, 5) << "missed:" << misses;
  const DrawResult noise = RunDraw(Draw(kNoiseOnlySeedBase + 1), folder / "noise", false);
  EXPECT_TRUE(noise.clean) << noise.named_first << " named at " << noise.named_score;
  std::filesystem::remove_all(folder);
}

}  // namespace
}  // namespace mb::grammar

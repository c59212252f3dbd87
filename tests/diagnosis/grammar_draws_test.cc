// The grammar-draw generator (tests/diagnosis/grammar_draws.h): its own checks, and a quick subset of draws through
// compare (the full benchmark: bench_grammar, tests/diagnosis/grammar_bench.h).
#include <cmath>
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

}  // namespace
}  // namespace mb::grammar

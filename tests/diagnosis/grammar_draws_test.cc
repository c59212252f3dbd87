// The grammar-draw generator (tests/diagnosis/grammar_draws.h): its own checks, and a quick subset of draws through
// compare (the full benchmark, 300 draws with improve: bench_grammar, `make bench-grammar`).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <initializer_list>
#include <regex>
#include <string>
#include <string_view>
#include <vector>

#include <Eigen/Core>
#include <fmt/format.h>
#include <gtest/gtest.h>

#include "models/diagnosis/factors.h"
#include "tests/diagnosis/grammar_bench.h"
#include "tests/diagnosis/grammar_draws.h"

namespace mb::grammar {
namespace {

// Each seed through compare, as a user runs it (a folder of its own, removed after): the drawn pair named first and,
// where `with_parameter`, its key shape parameter within tolerance. Returns the results in the seeds' order.
std::vector<DrawResult> ExpectNamedRight(std::initializer_list<unsigned> seeds, const std::string& folder_name,
                                         bool with_parameter) {
  const std::filesystem::path folder = std::filesystem::temp_directory_path() / folder_name;
  std::vector<DrawResult> results;
  for (unsigned seed : seeds) {
    const GrammarDraw draw = Draw(seed);
    results.push_back(RunDraw(draw, folder / std::to_string(seed), false));
    const DrawResult& r = results.back();
    EXPECT_TRUE(r.named_right) << draw.Describe() << " -> " << r.named_pair;
    if (with_parameter) {
      EXPECT_TRUE(r.parameter_right) << draw.Describe() << " -> " << r.parameter;
    }
  }
  std::filesystem::remove_all(folder);
  return results;
}

// The first of `details` that holds every one of `parts`, or "" when none does.
std::string DetailWith(const DrawResult& r, std::initializer_list<std::string_view> parts) {
  for (const std::string& d : r.details) {
    if (std::all_of(parts.begin(), parts.end(), [&](std::string_view p) { return d.find(p) != std::string::npos; })) {
      return d;
    }
  }
  return "";
}

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

// A draw's effect stands 4–30 × its floor, within the machine's physical limits. Seed 95 hides a force constant that
// saturates (A·u·|u|): it was drawn at 0.0 × its floor, measured at A = 1 where Effect's ±50 % bound made it u·0.5 (the
// base's own column) and then capped at a 30 % change; the ratio is now measured where the bound does not bind, and the
// record is made quieter where the cap holds the effect below the drawn ratio.
TEST(GrammarDraws, AnEffectStandsAtItsDrawnRatioWithinThePhysicalLimits) {
  const GrammarDraw d = Draw(95);
  ASSERT_EQ(d.pair(), "model_force_abs×constant");
  EXPECT_GE(d.target_ratio, 0.95 * 4.0);
  EXPECT_LE(d.target_ratio, 30.0);
  EXPECT_LT(d.noise_scale, 1.0) << "the 30 % cap binds on this machine";
  EXPECT_GE(d.noise_scale, 0.01);
  const Record twin = Simulate(d, Run::kTraining, false);
  const Eigen::VectorXd effect =
      EffectForce(d, Run::kTraining, twin.time, twin.true_position, twin.velocity, twin.acceleration, twin.command);
  double share = 0.0;  // the force constant's change, |A·|u|·mod|, at its largest
  for (Eigen::Index i = 0; i < twin.command.size(); ++i) {
    if (std::abs(twin.command(i)) > 0.0) share = std::max(share, std::abs(effect(i) / twin.command(i)));
  }
  EXPECT_GT(share, 0.05);
  EXPECT_LE(share, 0.3 + 1e-9) << "a force constant within ±30 % on the training twin's motion";
}

// A shape the record cannot show is drawn again, the rest of the draw kept: seed 752's first bump (one × a stretch of the
// travel around 0.149 m) left the point-to-point moves' force in the base's span, and Draw threw. Its second stands
// on the record at the drawn ratio.
TEST(GrammarDraws, AShapeTheRecordCannotShowIsDrawnAgain) {
  const GrammarDraw d = Draw(752);
  ASSERT_EQ(d.pair(), "one×position_local");
  EXPECT_GT(std::abs(d.shape.center - 0.14892), 1e-3) << "the first centre, which vanishes on the record";
  EXPECT_GE(d.target_ratio, 0.95 * 4.0);
  const Record twin = Simulate(d, Run::kTraining, false);
  EXPECT_GT(RmsBeyondBase(d, twin, EffectForce(d, Run::kTraining, twin.time, twin.true_position, twin.velocity,
                                               twin.acceleration, twin.command)),
            0.0);
}

// Draws with memory (issue 47, item 5): a Dahl element makes 90 % of its swing over the drawn stroke after a
// reversal, whatever the speed — checked on a synthetic stroke, slow and fast — and a vibration's frequency drifts.
TEST(GrammarDraws, AHysteresisDrawMakesNinetyPercentOfItsSwingOverItsStroke) {
  unsigned seed = kMemorySeedBase + 1;
  GrammarDraw d = Draw(seed);
  while (d.effect != "hysteresis") d = Draw(++seed);
  ASSERT_TRUE(d.memory);
  EXPECT_EQ(d.pair(), "hysteresis");
  EXPECT_EQ(d.key_parameter, "stroke");
  EXPECT_GT(d.amplitude, 0.0) << "it resists the motion";
  for (double speed : {0.1, 10.0}) {  // travel units per second
    const double h = 1e-3 * d.shape.stroke;
    const int up = 5000, down = 1000;   // 5 strokes up, then 1 stroke back
    const Eigen::Index n = up + down + 1;
    Eigen::VectorXd t(n), x(n), zero = Eigen::VectorXd::Zero(n);
    for (Eigen::Index i = 0; i < n; ++i) {
      x(i) = static_cast<double>(i <= up ? i : 2 * up - i) * h;
      t(i) = static_cast<double>(i) * h / speed;
    }
    const Eigen::VectorXd f = EffectForce(d, Run::kTraining, t, x, zero, zero, zero);
    const double swing = (f(up) - f(n - 1)) / (2.0 * d.amplitude);  // the share of the swing from +1 toward −1
    EXPECT_NEAR(swing, 0.9, 0.01) << "at " << speed;
  }
  unsigned chirp = kMemorySeedBase + 1;
  GrammarDraw v = Draw(chirp);
  while (v.modulator != "time_chirp") v = Draw(++chirp);
  EXPECT_EQ(v.key_parameter, "drift_rate");
  const double ratio = 1.0 + v.shape.drift_rate * v.duration / v.shape.frequency_hz;
  EXPECT_GE(std::max(ratio, 1.0 / ratio), 1.5 - 1e-9) << "f₀ " << v.shape.frequency_hz << " Hz";
}

// A load behind a play: while the motor stays within half the play of where the load sits (centred at the start),
// nothing touches it and the effect is 0; once the motor has crossed it, the shaft pushes the load (a positive force,
// the load's mass times its acceleration; after the impact the load may bounce ahead into the play again).
TEST(GrammarDraws, ALoadBehindAPlayIsTouchedOnlyOnceThePlayIsCrossed) {
  unsigned seed = kMemorySeedBase + 1;
  GrammarDraw d = Draw(seed);
  while (d.effect != "backlash_load") d = Draw(++seed);
  EXPECT_EQ(d.pair(), "backlash_load");
  EXPECT_EQ(d.key_parameter, "backlash");
  EXPECT_GT(d.amplitude, 0.0) << "a mass";
  // The motor ramps at constant speed from rest: it reaches half the play at t = g/(2·speed).
  const double speed = 0.1 * d.travel(), half = 0.5 * d.shape.gap, dt = 1e-4;
  const Eigen::Index n = static_cast<Eigen::Index>(std::ceil(4.0 * half / speed / dt));
  Eigen::VectorXd t(n), x(n), v(n), zero = Eigen::VectorXd::Zero(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    t(i) = static_cast<double>(i) * dt;
    x(i) = speed * t(i);
    v(i) = speed;
  }
  v(0) = 0.0;  // the load starts at rest with the motor, centred in the play
  const Eigen::VectorXd f = EffectForce(d, Run::kTraining, t, x, v, zero, zero);
  for (Eigen::Index i = 0; i < n; ++i) {
    if (x(i) < 0.99 * half) {
      EXPECT_EQ(f(i), 0.0) << "t = " << t(i);
    }
  }
  EXPECT_GT(f.maxCoeff(), 0.0) << "the play crossed: the shaft pushes the load";
}

// Four draws with memory through compare: hysteresis named with its stroke, a friction vibrating at a drifting
// frequency with its rate, a load behind a play (linear and rotary) with its play (`bench_grammar --memory=60` runs
// sixty).
TEST(GrammarDraws, HysteresisADriftingVibrationAndALoadBehindAPlayAreNamedWithTheirParameters) {
  ExpectNamedRight({kMemorySeedBase + 5, kMemorySeedBase + 10, kMemorySeedBase + 1, kMemorySeedBase + 12},
                   "mb_grammar_memory_test", true);
}

// Six of the first eight seeds and one noise-only draw through compare, as a user runs it; seeds 2 and 8, at 4.5 and
// 4.2 kHz, are left to the benchmark (under the sanitizers they took half of this test's 200 s). The benchmark names
// five in six of the draws right (docs/diagnosis.md, "Random draws from the grammar"; five of these six: seed 4 is
// named a force constant × its column); this fails when the quick subset falls below four of six, or when the
// noise-only draw names anything with a share of 2 % or more. A
// change time named right comes with the stretch the record places it in (DiagnosedEffect::time_intervals), which holds
// the drawn time: seed 3's window opens at 3.191 s, placed within a sample; seed 6's drag steps at 3.489 s while the
// axis decelerates into a dwell, placed in a stretch of about a tenth of the record and named at its posterior median,
// 3.657 s (its best single fit, 3.238 s, is one end of that stretch).
TEST(GrammarDraws, AQuickSubsetIsNamedAndTheNoiseOnlyDrawNamesNothing) {
  const std::filesystem::path folder = std::filesystem::temp_directory_path() / "mb_grammar_draws_test";
  int named = 0, intervals = 0;
  std::string misses;
  for (const unsigned seed : {1u, 3u, 4u, 5u, 6u, 7u}) {
    const DrawResult r = RunDraw(Draw(seed), folder / std::to_string(seed), false);
    named += r.named_right ? 1 : 0;
    if (!r.named_right) misses += fmt::format(" {} -> {};", r.draw.Describe(), r.named_pair);
    if (r.interval_judged) {
      ++intervals;
      EXPECT_TRUE(r.interval_holds) << r.draw.Describe() << " -> " << r.parameter;
    }
  }
  EXPECT_GE(named, 4) << "missed:" << misses;
  EXPECT_GE(intervals, 1);  // seeds 3 and 6 named right: the check ran
  const DrawResult noise = RunDraw(Draw(kNoiseOnlySeedBase + 1), folder / "noise", false);
  EXPECT_TRUE(noise.clean) << noise.named_first << " named at " << noise.named_score;
  std::filesystem::remove_all(folder);
}

// A multiplier that is no parameter of the base carries its constant part in each of its pairs (MultiplierRow::
// own_level), and the pair is chosen over that constant alone only where its modulation is significant. Seed 26 hides a
// friction of the transmitted force drifting from −a to +a over the record: without the level the ramp from 0 to 1
// cannot fit it and the pair was named as the force constant's drift. Seed 2 hides a quadratic drag constant over the
// record: with the level, a drag drifting by next to nothing fits the noise a little better and was named first.
// Every chosen product's multiplier is reconsidered, and a note says how, also where no other product fits better
// (multiplier_reconsideration.h): on seed 26 the force constant drifting is the best other and its BIC is higher.
TEST(GrammarDraws, APairCarriesItsMultipliersConstantPartAndMustEarnItsModulation) {
  const std::vector<DrawResult> r = ExpectNamedRight({26u, 2u}, "mb_grammar_level_test", false);
  ASSERT_EQ(r.size(), 2u);
  EXPECT_NE(DetailWith(r[0], {"load_friction_drift kept: of the other products of its modulator, the best, "
                              "force_constant_drift,", "has a BIC", "higher"}), "");
}

// The ranking's order is what each effect removed of the base's residual (DiagnosedEffect::base_share), not its score:
// on seed 258 a viscous step removes 95 % of it, and a Coulomb warm-up chosen after it 98.7 % of the 5 % left; the step
// is named first. Seed 296 hides a saturating force constant that is the same over the record: a window of it fits
// best; the window holds a step and the step its multiplier × 1 (ModulatorRow::nests), and the larger is chosen only
// where it beats the smaller significantly (here t = 0.62 and 0.63): the constant is named. The larger one's shape was
// scanned by the grammar's search, so it must pass the search's family-wise bar, as it would if the smaller were in
// the model first: seed 256 hides a Coulomb-like force of the speed constant over the record, and a step of it at
// 4.1 s beat it at t = 2.39 (above 2.33, below the 3.65 of one of 77 pairs searched) and was named. Either way a note
// says so: on seed 258 a saturating force constant over a stretch of the travel beats the same constant everywhere at
// t = 2.65, short of the bar of 64 pairs searched.
TEST(GrammarDraws, TheFirstNamedRemovedMostOfTheBaseResidualAndAWindowMustBeatTheShapesItHolds) {
  const std::vector<DrawResult> r = ExpectNamedRight({258u, 296u, 256u}, "mb_grammar_order_test", true);
  ASSERT_EQ(r.size(), 3u);
  EXPECT_NE(DetailWith(r[0], {"local_force_constant_saturation not chosen over force_constant_saturation,",
                              "is not significant", "pairs searched"}), "");
  EXPECT_NE(DetailWith(r[1], {"force_constant_saturation_step not chosen over force_constant_saturation,",
                              "is not significant"}), "");
  EXPECT_NE(DetailWith(r[2], {"speed_force_step not chosen over speed_force,", "pairs searched"}), "");
}

// The scans that place a change in time leave out the samples at the record's ends where the derived motion is still
// its derivative filter's edge transient (TimeScanFit, factor_tables.cc). Seed 261 hides an inertia settling with
// T = 3.36 s on a 10.8 s sweep that starts with the controller's first kick: with those samples the settling time's
// scan ended at its long end (10.8 s) and the inertia was named drifting over the record.
TEST(GrammarDraws, ATimeScanLeavesOutTheDerivativeFiltersEdges) {
  ExpectNamedRight({261u}, "mb_grammar_edge_test", true);
}

// A time scan's edge is refined on a finer grid before golden section (RefineTime, factor_tables.cc): the error of a
// time scan is flat over a dwell, where the motion is zero, and golden section alone drew seed 20's mass window end into
// the dwell before the move it ends in, 7.13 s for 7.57 s. That is within the draws' tolerance (5 % of the record), but
// the validation record moves there: improve stalled at 4.6 × the floor. Both edges now within 1 % of the record.
TEST(GrammarDraws, AWindowsEdgeIsNotDrawnIntoTheDwellBeforeItsMove) {
  const GrammarDraw draw = Draw(20);
  ASSERT_EQ(draw.modulator, "time_window");
  const std::filesystem::path folder = std::filesystem::temp_directory_path() / "mb_grammar_window_edge_test";
  const DrawResult r = RunDraw(draw, folder, false);
  std::filesystem::remove_all(folder);
  EXPECT_TRUE(r.named_right) << draw.Describe() << " -> " << r.named_pair;
  EXPECT_NEAR(r.parameter, draw.shape.on_time, 0.01 * draw.duration);
  EXPECT_NEAR(r.second_parameter, draw.shape.off_time, 0.01 * draw.duration);
}

// A chosen change time is placed, and given with its stretch, only where its scan searched (TimeScanRange: a step's
// middle 80 % of the record, a window's middle 90 %; PlaceChangeTimes). Seed 14 hides a quadratic drag that steps on
// at 7.876 s. Beside the two windows chosen with it the drag step's profile is nearly flat, and its posterior median
// over the whole record put it at 0.804 s, before the scan's start (0.943 s), where a step is a constant: the scan
// had found 7.876 s. Every change time named now lies inside its scan's stretch, and the drag step at its drawn time.
TEST(GrammarDraws, AChangeTimeIsPlacedOnlyWhereItsScanSearched) {
  const GrammarDraw draw = Draw(14);
  ASSERT_EQ(draw.modulator, "time_step");
  ASSERT_EQ(draw.multiplier, "velocity_speed");
  const std::filesystem::path folder = std::filesystem::temp_directory_path() / "mb_grammar_scan_stretch_test";
  const DrawResult r = RunDraw(draw, folder, false);
  std::filesystem::remove_all(folder);
  const Eigen::Vector2d record(0.0, draw.duration);
  const std::regex time_parameter(R"re(\("(change_time|on_time|off_time)", ([-+0-9.eE]+)\))re");
  int times = 0;
  for (const std::string& d : r.details) {
    if (d.find(": score ") == std::string::npos) continue;
    for (auto it = std::sregex_iterator(d.begin(), d.end(), time_parameter); it != std::sregex_iterator(); ++it) {
      const auto [low, high] = TimeScanRange((*it)[1].str(), record);
      const double t = std::stod((*it)[2].str());
      EXPECT_GE(t, low - 0.01) << d;  // a sample's leeway: the record ends within one of draw.duration
      EXPECT_LE(t, high + 0.01) << d;
      ++times;
    }
  }
  EXPECT_GE(times, 1) << "no change time named";
  const std::string step = DetailWith(r, {"drag_step: score", "change_time"});
  ASSERT_FALSE(step.empty()) << "the drag step is not among the named";
  std::smatch at;
  ASSERT_TRUE(std::regex_search(step, at, time_parameter)) << step;
  EXPECT_NEAR(std::stod(at[2].str()), draw.key_value, 0.01 * draw.duration) << step;
}

// The chosen products' multipliers chosen again with the friction laws and the other effects refit with each
// (models/diagnosis/multiplier_reconsideration.h). Seed 103 hides a friction of the transmitted force vibrating at
// 26.8 Hz: the greedy path named a viscous friction vibrating (held-out MSE 1.41), the load friction refit in its place
// has 0.417 (t = 5.9). Seed 171 hides a force constant that changes smoothly along the travel: it was named the
// friction of the transmitted force along the travel, which the force constant refit in its place beats (t = 3.3).
TEST(GrammarDraws, AMultiplierIsChosenAgainWithTheLawsAndTheOtherEffectsRefit) {
  ExpectNamedRight({103u, 171u}, "mb_grammar_reconsider_test", true);
}

// A chosen effect is compared again with its rivals of the same round, each at its refined shape
// (models/diagnosis/rival_reconsideration.h). Seed 878 hides a quadratic drag vibrating at 34.9 Hz on a point-to-point
// record: a 1.3 ms actuator lag, its lag scanned finely, was chosen over the vibration at the periodogram's frequency;
// refit in the lag's place, the vibration leaves a lower held-out error (0.971 against 1.174) and is named.
TEST(GrammarDraws, AChosenEffectIsComparedWithItsRivalsEachRefined) {
  const std::vector<DrawResult> r = ExpectNamedRight({878u}, "mb_grammar_rival_test", true);
  ASSERT_EQ(r.size(), 1u);
  EXPECT_NE(DetailWith(r[0], {"actuator_lag replaced by its rival drag_vibration, refined"}), "");
}

// A force constant's effect acts on the force the drive gives: the generator's machine is u·(1 + δ(t)) = ŷ, so the
// residual is −δ·u, linear in the command u and not in ŷ, and beside ŷ a warm-up fitted to −δ·ŷ/(1 + δ) comes out
// distorted. The shapes of ŷ's pairs are scanned on the command the model predicts with each in
// (DiagnosisSignals::command_with). Seed 84 hides a force constant settling with T = 1.719 s: 2.05 s beside ŷ (19 %
// off), 1.749 s now. Seed 201 hides a friction of the transmitted force, |u|·tanh(v/v_s), settling with T = 2.887 s:
// 3.90 s beside ŷ (35 % off), 3.24 s now.
TEST(GrammarDraws, AForceConstantsShapeIsScannedOnTheCommandTheModelPredicts) {
  const std::vector<DrawResult> r = ExpectNamedRight({84u, 201u}, "mb_grammar_command_test", true);
  ASSERT_EQ(r.size(), 2u);
  ASSERT_EQ(r[0].draw.multiplier + "×" + r[0].draw.modulator, "model_force×time_warm_up");
  EXPECT_NEAR(r[0].parameter, r[0].draw.shape.time_constant, 0.05 * r[0].draw.shape.time_constant);
  ASSERT_EQ(r[1].draw.multiplier + "×" + r[1].draw.modulator, "load_slip×time_warm_up");
  EXPECT_NEAR(r[1].parameter, r[1].draw.shape.time_constant, 0.2 * r[1].draw.shape.time_constant);
}

// A third factor (models/diagnosis/amplitude_factor.h): the pair's amplitude follows time or a further logged column.
// Seed 15 hides a drag vibrating at 9.5 Hz whose amplitude grows as 1 + β·(2t/T − 1): its relative slope is 2β/T per
// second. Seed 80 hides a viscous friction along the travel whose amplitude follows the winding temperature. Each is
// named as the pair with its amplitude following the right source, the slope with the drawn sign (and, in time, within
// 25 %).
TEST(GrammarDraws, AnAmplitudeThatFollowsTimeOrAColumnIsTheThirdFactor) {
  const std::filesystem::path folder = std::filesystem::temp_directory_path() / "mb_grammar_third_test";
  const GrammarDraw in_time = Draw(15);
  ASSERT_EQ(in_time.third_factor, "time");
  const DrawResult r = RunDraw(in_time, folder / "15", false);
  EXPECT_TRUE(r.named_right) << in_time.Describe() << " -> " << r.named_pair;
  EXPECT_EQ(r.third_found, "time");
  const double truth = 2.0 * in_time.third_depth / in_time.duration;
  EXPECT_NEAR(r.third_slope, truth, 0.25 * std::abs(truth));

  const GrammarDraw following = Draw(80);
  ASSERT_EQ(following.third_factor, "column");
  const DrawResult c = RunDraw(following, folder / "80", false);
  EXPECT_TRUE(c.named_right) << following.Describe() << " -> " << c.named_pair;
  EXPECT_EQ(c.third_found, following.third_column.name);
  EXPECT_GT(c.third_slope * following.third_depth, 0.0) << "the amplitude changes the drawn way";
  std::filesystem::remove_all(folder);
}

// A third factor that another pair imitated before it was tried. Seed 158 hides a force that steps at 3.79 s and whose
// amplitude drifts with time (1 × a step × (1 + β·(2t/T − 1))): the ranking chose the step and beside it a force
// settling in time, which took the drift's share, so that the step's amplitude following time gained nothing beside
// it. Left out, the modulation is significant and the settling force no longer earns its place beside it: the step
// with its amplitude following time is named, the settling force left out with the note that says why.
TEST(GrammarDraws, AnAmplitudeFactorTakesOverWhatAnotherPairImitated) {
  const std::filesystem::path folder = std::filesystem::temp_directory_path() / "mb_grammar_takeover_test";
  const GrammarDraw draw = Draw(158);
  ASSERT_EQ(draw.multiplier + "×" + draw.modulator, "one×time_step");
  ASSERT_EQ(draw.third_factor, "time");
  const DrawResult r = RunDraw(draw, folder, false);
  EXPECT_TRUE(r.named_right) << draw.Describe() << " -> " << r.named_pair;
  EXPECT_EQ(r.third_found, "time") << fmt::format("{}", fmt::join(r.details, "\n"));
  EXPECT_FALSE(DetailWith(r, {"force_step's amplitude following time takes over what force_warm_up explained",
                              "force_warm_up left out"})
                   .empty())
      << fmt::format("{}", fmt::join(r.details, "\n"));
  const double truth = 2.0 * draw.third_depth / draw.duration;
  EXPECT_NEAR(r.third_slope, truth, 0.25 * std::abs(truth));
  std::filesystem::remove_all(folder);
}

// Where the training record cannot tell two products of one modulator apart (DiagnosedEffect::alike_effects), improve
// tries both and the held-out record decides. Seed 76 hides a force of time alone that settles (1 × a warm-up of
// T = 0.89 s) on a sweep: over its training record the drive's force ŷ follows the motion's sign and size closely
// enough that ŷ × the warm-up explains as much (93.7 % against 94.0 %), and compare names it with the note. The
// validation record tells them apart: the force constant's block leaves 1.18 N held out, the force's own 0.146 N, at
// the draw's floor.
TEST(GrammarDraws, AProductTheTrainingRecordCannotTellIsDecidedOnTheHeldOutRecord) {
  const std::filesystem::path folder = std::filesystem::temp_directory_path() / "mb_grammar_alike_test";
  const GrammarDraw draw = Draw(76);
  ASSERT_EQ(draw.multiplier + "×" + draw.modulator, "one×time_warm_up");
  const DrawResult r = RunDraw(draw, folder, true);
  EXPECT_FALSE(DetailWith(r, {"the training record could not tell", "the held-out one prefers force_warm_up"}).empty())
      << fmt::format("{}", fmt::join(r.details, "\n"));
  EXPECT_FALSE(DetailWith(r, {"force_warm_up: accepted"}).empty());
  EXPECT_TRUE(r.floor_reached) << r.heldout_after << " against the floor " << r.noise_floor;
  std::filesystem::remove_all(folder);
}

}  // namespace
}  // namespace mb::grammar

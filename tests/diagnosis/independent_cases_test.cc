// The independent hidden-effect data (issue 13, item 5; tests/diagnosis/independent_plant.h): the generator's own
// properties (what makes it a test of data the project did not generate). The cases themselves — a log per hidden
// effect, diagnosed with the EMPS rigid body as the user's model — are measured by bench_diagnosis
// (docs/diagnosis.md, "Independent hidden-effect cases"); the cases that `compare` passes are tests here too
// (IndependentCase.*: named first outside the friction-law replacements, key parameter within tolerance; `improve` and
// its noise floor are measured by the benchmark only — under ASan it takes minutes per case).
#include <algorithm>
#include <cctype>
#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>

#include <gtest/gtest.h>

#include "tests/diagnosis/independent_bench.h"
#include "tests/diagnosis/independent_plant.h"

namespace mb::independent {
namespace {

const GeneratorSettings kJittered{.duration = 4.0, .jitter = 0.05, .seed = 3};

TEST(IndependentPlant, SameSeedSameRecordOtherSeedAnother) {
  const Record a = Generate(Hidden::kNone, kJittered), b = Generate(Hidden::kNone, kJittered);
  EXPECT_EQ(a.force, b.force);
  EXPECT_EQ(a.position, b.position);
  GeneratorSettings other = kJittered;
  other.seed = 4;
  EXPECT_NE(Generate(Hidden::kNone, other).position, a.position);
}

TEST(IndependentPlant, LogsAsAJitteredQuantisedNoisyLoggerWould) {
  const Record r = Generate(Hidden::kNone, kJittered);
  ASSERT_EQ(r.time.size(), 4000);
  const Eigen::ArrayXd step = r.time.tail(r.time.size() - 1) - r.time.head(r.time.size() - 1);
  EXPECT_GE(step.minCoeff(), 0.9e-3 - 1e-12);  // ±5 % on each instant: steps within 1 ms ± 10 %
  EXPECT_LE(step.maxCoeff(), 1.1e-3 + 1e-12);
  EXPECT_GT(step.maxCoeff() - step.minCoeff(), 0.1e-3);  // and really jittered
  const Eigen::ArrayXd counts = r.position.array() / kJittered.encoder_step;
  EXPECT_LT((counts - counts.round()).abs().maxCoeff(), 1e-6);  // on the encoder's grid
  const Eigen::ArrayXd noise = (r.force - r.true_force).array();
  const double sd = std::sqrt((noise - noise.mean()).square().mean());
  EXPECT_NEAR(sd, kJittered.force_noise, 0.05 * kJittered.force_noise);
  EXPECT_NEAR(noise.mean(), 0.0, 0.05);
}

TEST(IndependentPlant, PointToPointMovesDwellAtRestAndStayInTheTravel) {
  const Record r = Generate(Hidden::kNone, {.duration = 16.0, .jitter = 0.0, .seed = 11});
  Eigen::Index at_rest = 0;
  for (Eigen::Index i = 50; i < r.position.size(); ++i) {
    if (std::abs(r.position(i) - r.position(i - 50)) < 1e-5) ++at_rest;  // < 10 µm in 50 ms: dwelling
  }
  const double share = static_cast<double>(at_rest) / static_cast<double>(r.position.size());
  EXPECT_GT(share, 0.1);
  EXPECT_LT(share, 0.7);
  EXPECT_GT(r.position.minCoeff(), 0.0);
  EXPECT_LT(r.position.maxCoeff(), 0.2);
}

// The controller runs at the log's rate up to 1 kHz, at 1 kHz below it; the closed-loop diagram that models it takes its
// period and its velocity estimate's cut-off from these (RunCaseInSimulation): the fixture's 129.53 Hz at 1 kHz.
TEST(IndependentPlant, TheControllersRateAndItsVelocityEstimateFollowTheLog) {
  EXPECT_DOUBLE_EQ(ControlPeriod(1e-3), 1e-3);
  EXPECT_DOUBLE_EQ(ControlPeriod(5e-4), 5e-4);
  EXPECT_DOUBLE_EQ(ControlPeriod(1e-2), 1e-3);
  EXPECT_NEAR(VelocityEstimateCutoffHz(1e-3), 129.53, 0.01);
  // The pole exp(−2π·f·T) is the generator's 1 − α at either rate.
  for (double period : {5e-4, 1e-3}) {
    const double alpha = period / (period + 1.0 / (2.0 * std::numbers::pi * 200.0));
    EXPECT_NEAR(std::exp(-2.0 * std::numbers::pi * VelocityEstimateCutoffHz(period) * period), 1.0 - alpha, 1e-12);
  }
}

TEST(IndependentPlant, EachCaseNamesACatalogueEffectAndATolerance) {
  ASSERT_EQ(Cases().size(), 45U);
  for (const auto& c : Cases()) {
    EXPECT_EQ(c.parameter.empty(), c.tolerance == 0.0) << c.name;
    // The idle column acts on nothing: like kNone, nothing may be named.
    EXPECT_EQ(c.effect.empty(), c.hidden == Hidden::kNone || c.hidden == Hidden::kIdleColumn) << c.name;
  }
}

// Every case, each on its full 16 s training record as the benchmark runs it (docs/diagnosis.md's table), the force
// read as the held command it is (--intersample zoh). The six cases IndependentImprove runs (below) are compared there,
// their parameter checked the same way: they are not compared twice.
class IndependentCase : public ::testing::TestWithParam<std::string> {};

TEST_P(IndependentCase, NamedFirstWithItsParameter) {
  const auto cases = Cases();  // spec points into it
  const CaseSpec* spec = nullptr;
  for (const auto& c : cases) {
    if (c.name == GetParam()) spec = &c;
  }
  ASSERT_NE(spec, nullptr) << GetParam();
  std::string folder = spec->name;
  for (char& c : folder) if (c == ' ' || c == '(' || c == ')' || c == '+') c = '_';
  const auto dir = std::filesystem::temp_directory_path() / "mb_independent_cases" / folder;
  const CaseResult r = RunCase(*spec, dir, /*run_improve=*/false);
  std::string named;
  for (const auto& n : r.named) named += n + "; ";
  EXPECT_TRUE(r.named_right) << named;
  EXPECT_TRUE(r.parameter_right) << spec->parameter << " = " << r.parameter << " (truth " << spec->truth << ")";
  // The gearboxes' loads (a light bearing, 0.6 /s) rattle in their plays while the motor rests, and the diagnosis says
  // so: where such a load comes to rest turns on sub-micrometre detail (docs/diagnosis.md, "A load behind a play").
  // No other case says it.
  const bool rattles = std::any_of(r.details.begin(), r.details.end(), [](const std::string& d) {
    return d.find("the load rattles in its play while the motor rests") != std::string::npos;
  });
  EXPECT_EQ(rattles, spec->effect == "backlash_load") << named;
  std::filesystem::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(ComparePasses, IndependentCase,
                         ::testing::Values("position ripple", "speed-dependent ripple", "Stribeck", "delay",
                                           "vibration (decoy)", "resonance", "position-dependent force", "backlash", "payload",
                                           "ripple + delay", "drive saturation", "short stroke",
                                           "rotary gravity", "mains hum", "friction drift", "noisy stamps",
                                           "nothing missing", "nothing missing, 100 Hz", "nothing missing, 2 kHz",
                                           // Effects no catalogue entry describes (issue 40): the grammar's products,
                                           // a place in the travel, an unread log column, and one that does not act.
                                           "pitch friction, 6 cycles",
                                           "force-constant ripple", "friction at one spot",
                                           "idle extra column",
                                           "damping along the pitch", "viscosity follows oil temperature",
                                           "friction along the travel", "damping at one stretch",
                                           "coupled axis (its velocity logged)", "mass along the travel (a linkage)",
                                           "dashpot orifice drag",
                                           // The force constant × a place, the travel, an unread column.
                                           "weak magnet", "magnet temperature (extra column)",
                                           // A limit that is a function of the speed: the winding's back-EMF (k).
                                           "back-EMF voltage limit",
                                           // A force with memory (issue 47): hysteresis of a preloaded guide,
                                           // and a vibration whose frequency drifts (a fan speeding up).
                                           "hysteresis (a preloaded guide)", "drifting vibration",
                                           // The same two on the rotary axis (rad, N·m).
                                           "rotary hysteresis", "rotary drifting vibration",
                                           // A load behind a play (issue 47), linear and rotary: the play's width.
                                           "load behind a play", "rotary load behind a play"),
                         [](const ::testing::TestParamInfo<std::string>& case_info) {
                           std::string name;
                           for (char c : case_info.param) if (std::isalnum(static_cast<unsigned char>(c))) name += c;
                           return name;
                         });

// A parameter that changes is named with its values (issue 25: change time 0.5 s and values 5 %): the mass picked up
// and the viscous friction's drift over the record, beside the change time the table checks.
TEST(IndependentValues, PayloadStepAndDriftReportTheChange) {
  const auto cases = Cases();
  const auto dir = std::filesystem::temp_directory_path() / "mb_independent_values";
  for (const auto& [name, truth] : {std::pair{"payload step", 31.0}, std::pair{"friction drift", -50.0}}) {
    const auto spec = std::find_if(cases.begin(), cases.end(), [&](const CaseSpec& c) { return c.name == name; });
    ASSERT_NE(spec, cases.end()) << name;
    const CaseResult r = RunCase(*spec, dir / (spec->effect), /*run_improve=*/false);
    ASSERT_TRUE(r.named_right) << name;
    ASSERT_TRUE(r.parameters.count("change")) << name;
    EXPECT_NEAR(r.parameters.at("change"), truth, 0.05 * std::abs(truth)) << name;
  }
  std::filesystem::remove_all(dir);
}

// A delay against hysteresis, by speed (issue 47, item 2): a delay's transition takes a stroke that grows with the
// speed, hysteresis' does not. On the delay case the delay explains the residual below and above the median speed
// alike and hysteresis falls off at speed; on the preloaded guide the reverse. Each record's note says which and why.
TEST(IndependentValues, ADelayAndHysteresisAreToldApartBySpeed) {
  const auto cases = Cases();
  const auto dir = std::filesystem::temp_directory_path() / "mb_independent_delay_hysteresis";
  for (const auto& [name, verdict] : {std::pair{"delay", "told apart by speed: a delay"},
                                      std::pair{"hysteresis (a preloaded guide)", "told apart by speed: hysteresis"}}) {
    const auto spec = std::find_if(cases.begin(), cases.end(), [&](const CaseSpec& c) { return c.name == name; });
    ASSERT_NE(spec, cases.end()) << name;
    const CaseResult r = RunCase(*spec, dir / spec->effect, /*run_improve=*/false);
    ASSERT_TRUE(r.named_right) << name;
    EXPECT_TRUE(std::any_of(r.details.begin(), r.details.end(),
                            [&](const std::string& d) { return d.find(verdict) != std::string::npos; }))
        << name << ": no note \"" << verdict << "\"";
  }
  std::filesystem::remove_all(dir);
}

// The effects off the linear-stage template, added by improve: the held-out error falls to the noise floor (within
// 1.3 ×, the benchmark's criterion). A quick subset, one of each kind of block improve adds (a transport delay on the
// command path, a switched gain, a ripple × the direction of slip, an input connector on a log column, a warm-up of
// time, the force constant × a smooth table of the position): under ASan an improve takes ~25 s, and the whole list
// (all 43 cases with improve, in Release) is `make bench-diagnosis`, which exits 1 on a miss.
class IndependentImprove : public ::testing::TestWithParam<std::string> {};

TEST_P(IndependentImprove, ReachesTheNoiseFloor) {
  const auto cases = Cases();
  const auto spec = std::find_if(cases.begin(), cases.end(), [](const CaseSpec& c) { return c.name == GetParam(); });
  ASSERT_NE(spec, cases.end()) << GetParam();
  std::string folder = spec->name;
  for (char& c : folder) if (!std::isalnum(static_cast<unsigned char>(c))) c = '_';
  const auto dir = std::filesystem::temp_directory_path() / "mb_independent_improve" / folder;
  const CaseResult r = RunCase(*spec, dir, /*run_improve=*/true);
  EXPECT_TRUE(r.named_right) << r.named_first;
  EXPECT_TRUE(r.parameter_right) << spec->parameter << " = " << r.parameter << " (truth " << spec->truth << ")";
  EXPECT_LE(r.heldout_after, 1.3 * r.noise_floor) << "before " << r.heldout_before;
  EXPECT_GE(r.heldout_after, 0.7 * r.noise_floor) << "below the floor: a leak";
  EXPECT_LT(r.heldout_after, 0.2 * r.heldout_before);
  std::filesystem::remove_all(dir);
}

INSTANTIATE_TEST_SUITE_P(OffTheLinearStage, IndependentImprove,
                         ::testing::Values("actuator lag", "payload step", "friction along the pitch",
                                           "coupled axis (extra column)", "grease warm-up", "air gap along the track"),
                         [](const ::testing::TestParamInfo<std::string>& case_info) {
                           std::string name;
                           for (char c : case_info.param) if (std::isalnum(static_cast<unsigned char>(c))) name += c;
                           return name;
                         });

}  // namespace
}  // namespace mb::independent

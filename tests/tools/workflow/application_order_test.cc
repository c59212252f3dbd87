// One ranking, one loop (issue 27 item 6): the order compare reports, compare --suggest applies and improve tries
// (EffectsInApplicationOrder, tools/workflow/suggest.h), and the significance rule that refuses an improve step whose
// coefficients fitted noise (NotSignificantReason, tools/workflow/improve.h).
#include <cmath>
#include <string>
#include <vector>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "tools/workflow/improve.h"
#include "tools/workflow/suggest.h"

namespace mb {
namespace {

using ::testing::ElementsAre;
using ::testing::HasSubstr;

DiagnosedEffect Effect(const std::string& name, double score, double cumulative, int selection_order) {
  DiagnosedEffect e;
  e.effect = name;
  e.score = score;
  e.cumulative_share = cumulative;
  e.selection_order = selection_order;
  return e;
}

std::vector<std::string> Names(const std::vector<const DiagnosedEffect*>& order) {
  std::vector<std::string> names;
  for (const DiagnosedEffect* e : order) names.push_back(e->effect);
  return names;
}

// DiagnosisResult::effects keeps the missing effects by score and the laws last (the summary's order); applied, the
// laws come first and the missing effects in the order the selection chose them, so that cumulative shares rise.
TEST(ApplicationOrder, FrictionLawsFirstThenMissingEffectsAsTheSelectionChoseThem) {
  DiagnosisResult d;
  d.effects = {Effect("velocity_dependent_ripple", 0.091, 0.150, 2), Effect("time_delay", 0.064, 0.205, 3),
               Effect("position_periodic", 0.030, 0.230, 4), Effect("stribeck_friction", 0.029, 0.065, 1),
               Effect("regularized_coulomb_friction", 0.040, 0.040, 0)};
  d.friction_law = {"regularized_coulomb_friction", "stribeck_friction"};
  const auto order = EffectsInApplicationOrder(d);
  EXPECT_THAT(Names(order), ElementsAre("regularized_coulomb_friction", "stribeck_friction",
                                        "velocity_dependent_ripple", "time_delay", "position_periodic"));
  for (std::size_t i = 1; i < order.size(); ++i) {
    EXPECT_LT(order[i - 1]->cumulative_share, order[i]->cumulative_share) << i;
  }
  // Pointers into the result, not copies.
  EXPECT_EQ(order.front(), &d.effects[4]);
}

TEST(ApplicationOrder, ScoreOrderAndSelectionOrderMayDifferTheSelectionWins) {
  DiagnosisResult d;
  // The second effect chosen explains more of what was left than the first did of the whole: listed by score it would
  // come first, and the cumulative column would fall.
  d.effects = {Effect("time_delay", 0.30, 0.44, 1), Effect("position_periodic", 0.20, 0.20, 0)};
  EXPECT_THAT(Names(EffectsInApplicationOrder(d)), ElementsAre("position_periodic", "time_delay"));
}

// An effect kept for its significance after one that explains nearly all can lower the cumulative share (grammar
// seed 92: a speed force drifting explains 99.9 %, a local damping chosen after it −0.3 % of what it left). The
// order is the selection's, not the cumulative share's: sorted by that, the drift came after the three others and
// improve, trying three per round, never tried it (held out 13 × the floor).
TEST(ApplicationOrder, AnEffectThatLowersTheCumulativeShareStillComesAfterTheOnesChosenBeforeIt) {
  DiagnosisResult d;
  d.effects = {Effect("speed_force_drift", 0.9990, 0.99905, 0), Effect("load_friction_ripple", 0.019, 0.99907, 1),
               Effect("local_damping", -0.003, 0.99904, 2), Effect("friction_ripple", -0.011, 0.99903, 3)};
  EXPECT_THAT(Names(EffectsInApplicationOrder(d)),
              ElementsAre("speed_force_drift", "load_friction_ripple", "local_damping", "friction_ripple"));
}

TEST(ApplicationOrder, NothingDiagnosedGivesNothing) {
  EXPECT_TRUE(EffectsInApplicationOrder(DiagnosisResult{}).empty());
}

// A fit of base parameters and one added element "ripple" (two coefficients and its period).
FitResult RippleFit(double cos_estimate, double cos_std, double sin_estimate, double sin_std) {
  FitResult fit;
  fit.parameters = {{"plant", "mass", -1, "plant.mass", "kg"},
                    {"ripple", "cos_coefficients", 0, "ripple.cos_coefficients[0]", "N"},
                    {"ripple", "sin_coefficients", 0, "ripple.sin_coefficients[0]", "N"},
                    {"ripple", "period", -1, "ripple.period", "m"}};
  fit.estimate = Eigen::Vector4d(95.0, cos_estimate, sin_estimate, 4.21e-3);
  fit.standard_error = Eigen::Vector4d(0.1, cos_std, sin_std, 1e-6);
  return fit;
}

TEST(StepSignificance, CoefficientsWhoseIntervalsHoldZeroAreRefusedNamingThem) {
  // EMPS's refused ripple: coefficients of about 0.001 N with standard errors of 0.004 N.
  const std::string why = NotSignificantReason(RippleFit(0.001, 0.004, -0.0008, 0.004), "ripple", {"period"});
  EXPECT_THAT(why, HasSubstr("not significant"));
  EXPECT_THAT(why, HasSubstr("ripple.cos_coefficients[0] = 0.001"));
  EXPECT_THAT(why, HasSubstr("ripple.sin_coefficients[0]"));
  EXPECT_THAT(why, ::testing::Not(HasSubstr("period")));  // exempt: a period is never near zero
  EXPECT_THAT(why, ::testing::Not(HasSubstr("plant.mass")));  // not the element's
}

TEST(StepSignificance, OneCoefficientOutsideItsIntervalIsEnough) {
  // The cosine holds zero (the ripple's phase), the sine does not: 1.5 ± 1.96·0.2 excludes zero.
  EXPECT_EQ(NotSignificantReason(RippleFit(0.001, 0.004, 1.5, 0.2), "ripple", {"period"}), "");
  // Just inside the interval: 0.39 < 1.96·0.2 = 0.392.
  EXPECT_NE(NotSignificantReason(RippleFit(0.001, 0.004, 0.39, 0.2), "ripple", {"period"}), "");
}

TEST(StepSignificance, AnUnestimatedCoefficientIsNotSignificant) {
  // A parameter the log cannot estimate has an infinite standard error (FitResult::identifiable).
  EXPECT_NE(NotSignificantReason(RippleFit(3.0, INFINITY, 2.0, INFINITY), "ripple", {"period"}), "");
  // Without the exemption the period (4.21 mm ± 2 µm) alone would count as significant.
  EXPECT_EQ(NotSignificantReason(RippleFit(3.0, INFINITY, 2.0, INFINITY), "ripple", {}), "");
}

TEST(StepSignificance, AFitWithoutTheElementHasNothingToRefuse) {
  EXPECT_EQ(NotSignificantReason(RippleFit(0.001, 0.004, 0.0, 0.004), "delay", {}), "");
}

}  // namespace
}  // namespace mb

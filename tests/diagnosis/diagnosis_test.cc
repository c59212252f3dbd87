// The diagnosis on data with a hidden effect: the code is not told which effect was injected.
#include "models/diagnosis/diagnosis.h"

#include <cmath>
#include <map>
#include <filesystem>
#include <numbers>
#include <random>

#include <Eigen/Dense>
#include <fmt/format.h>
#include <fmt/ranges.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "models/diagnosis/amplitude_factor.h"
#include "models/diagnosis/measurement_log.h"

namespace mb {
namespace {

using ::testing::HasSubstr;
constexpr double kTwoPi = 2.0 * std::numbers::pi;

// A rigid-body axis moving back and forth over 0..0.2 m with a speed that changes from stroke to stroke
// (1 kHz), with the force of a nominal model M a + Fv v + Fc sign(v) + c.
struct Scenario {
  DiagnosisSignals s;
  Eigen::VectorXd nominal_force;
  std::mt19937 rng{42};
  std::normal_distribution<double> n01;

  explicit Scenario(Eigen::Index n) {
    s.time = Eigen::VectorXd::LinSpaced(n, 0.0, 1e-3 * static_cast<double>(n - 1));
    s.position.resize(n);
    s.velocity.resize(n);
    s.acceleration.resize(n);
    const double w1 = kTwoPi * 0.15, w2 = kTwoPi * 0.05, m = 0.45;
    for (Eigen::Index i = 0; i < n; ++i) {
      const double t = s.time(i);
      const double phi = w1 * t + m * std::sin(w2 * t);
      const double dphi = w1 + m * w2 * std::cos(w2 * t);
      const double ddphi = -m * w2 * w2 * std::sin(w2 * t);
      s.position(i) = 0.1 + 0.1 * std::sin(phi);
      s.velocity(i) = 0.1 * std::cos(phi) * dphi;
      s.acceleration(i) = 0.1 * (-std::sin(phi) * dphi * dphi + std::cos(phi) * ddphi);
    }
    nominal_force = 94.0 * s.acceleration + 195.0 * s.velocity + 21.0 * Sign() + Eigen::VectorXd::Constant(n, -0.5);
  }
  Eigen::VectorXd Sign() const { return s.velocity.unaryExpr([](double v) { return v > 0 ? 1.0 : (v < 0 ? -1.0 : 0.0); }); }
  Eigen::VectorXd Noise(double sigma) {
    Eigen::VectorXd e(s.time.size());
    for (auto& v : e) v = sigma * n01(rng);
    return e;
  }
  // Base regressors by letter: a (mass), v (viscous), s (Coulomb), 1 (offset).
  BaseRegressors Base(const std::string& which) const {
    BaseRegressors b;
    std::vector<Eigen::VectorXd> cols;
    for (char c : which) {
      if (c == 'a') { cols.push_back(s.acceleration); b.names.push_back("mass"); }
      if (c == 'v') { cols.push_back(s.velocity); b.names.push_back("viscous"); }
      if (c == 's') { cols.push_back(Sign()); b.names.push_back("coulomb"); }
      if (c == '1') { cols.push_back(Eigen::VectorXd::Ones(s.time.size())); b.names.push_back("offset"); }
    }
    b.columns.resize(s.time.size(), static_cast<Eigen::Index>(cols.size()));
    for (std::size_t j = 0; j < cols.size(); ++j) b.columns.col(static_cast<Eigen::Index>(j)) = cols[j];
    return b;
  }
};

std::string Names(const DiagnosisResult& r) {
  std::string out;
  for (const auto& e : r.effects) out += fmt::format("{} ({:.3f}); ", e.effect, e.score);
  return out + " | " + r.summary;
}

bool Named(const DiagnosisResult& r, const std::string& effect) {
  for (const auto& e : r.effects) if (e.effect == effect) return true;
  return false;
}

TEST(Diagnosis, PositionPeriodicRippleIsFoundWithItsPeriodAndShare) {
  Scenario sc(15000);
  const double period = 2.5e-3;
  const Eigen::VectorXd ripple = sc.s.position.unaryExpr([&](double x) {
    return 0.5 * std::sin(kTwoPi * x / period) + 0.15 * std::cos(2.0 * kTwoPi * x / period);
  });
  sc.s.residual = ripple + sc.Noise(0.25);
  const DiagnosisResult r = DiagnoseMissingEffects(sc.s, sc.Base("avs1"));
  ASSERT_TRUE(r.missing_effect_found) << r.summary;
  const auto& top = r.effects.front();
  EXPECT_EQ(top.effect, "position_periodic") << Names(r);
  EXPECT_NEAR(top.parameters.at("period"), period, 0.02 * period);
  EXPECT_GE(top.parameters.at("harmonics"), 2.0);
  // True share of the residual energy: ripple variance / (ripple + noise variance).
  const double truth = (0.125 + 0.01125) / (0.125 + 0.01125 + 0.0625);
  EXPECT_NEAR(top.score, truth, 0.03) << Names(r);
  EXPECT_NEAR(r.rmse_after, 0.25, 0.01);  // the joint refit reaches the noise floor
  EXPECT_FALSE(r.position_time_indistinguishable);
  EXPECT_THAT(r.summary, HasSubstr("Missing: position_periodic"));
  EXPECT_THAT(top.description, HasSubstr("held-out residual energy"));
}

TEST(Diagnosis, ViscousFrictionMissingFromTheBase) {
  Scenario sc(12000);
  sc.s.residual = 150.0 * sc.s.velocity + sc.Noise(0.5);
  const DiagnosisResult r = DiagnoseMissingEffects(sc.s, sc.Base("as1"));
  ASSERT_TRUE(r.missing_effect_found) << r.summary;
  EXPECT_EQ(r.effects.front().effect, "viscous_friction") << Names(r);
  EXPECT_NEAR(r.effects.front().coefficients(0), 150.0, 1.0);
  EXPECT_GT(r.effects.front().score, 0.9);
}

TEST(Diagnosis, CoulombFrictionMissingFromTheBase) {
  Scenario sc(12000);
  sc.s.residual = 20.0 * sc.Sign() + sc.Noise(0.5);
  const DiagnosisResult r = DiagnoseMissingEffects(sc.s, sc.Base("av1"));
  ASSERT_TRUE(r.missing_effect_found) << r.summary;
  EXPECT_EQ(r.effects.front().effect, "coulomb_friction") << Names(r);
  EXPECT_NEAR(r.effects.front().coefficients(0), 20.0, 0.5);
}

// Nothing refit (`compare --no-fit`): no base regressors at all. The diagnosis still ranks, and nothing counts as
// already in the model (this crashed once: Eigen's QR of an N × 0 matrix).
TEST(Diagnosis, WithoutBaseRegressorsNothingIsAlreadyInTheModel) {
  Scenario sc(12000);
  sc.s.residual = 20.0 * sc.Sign() + sc.Noise(0.5);
  const DiagnosisResult r = DiagnoseMissingEffects(sc.s, sc.Base(""));
  ASSERT_TRUE(r.missing_effect_found) << r.summary;
  EXPECT_EQ(r.effects.front().effect, "coulomb_friction") << Names(r);
  for (const auto& n : r.notes) EXPECT_EQ(n.find("already in the model"), std::string::npos) << n;
}

TEST(Diagnosis, MassMismatch) {
  Scenario sc(12000);
  sc.s.residual = 21.0 * sc.s.acceleration + sc.Noise(0.3);  // payload of 21 kg not in the model
  const DiagnosisResult r = DiagnoseMissingEffects(sc.s, sc.Base("vs1"));
  ASSERT_TRUE(r.missing_effect_found) << r.summary;
  EXPECT_EQ(r.effects.front().effect, "mass_mismatch") << Names(r);
  EXPECT_NEAR(r.effects.front().coefficients(0), 21.0, 0.5);
}

// The scenario's nominal force (M = 94 kg, Fv = 195 N·s/m, Fc = 21 N, offset −0.5 N) at t − delay, from the
// analytic motion (not interpolated).
Eigen::VectorXd NominalForceDelayedBy(const Scenario& sc, double delay) {
  Eigen::VectorXd force(sc.s.time.size());
  for (Eigen::Index i = 0; i < force.size(); ++i) {
    const double t = std::max(0.0, sc.s.time(i) - delay);
    const double w1 = kTwoPi * 0.15, w2 = kTwoPi * 0.05, m = 0.45;
    const double phi = w1 * t + m * std::sin(w2 * t), dphi = w1 + m * w2 * std::cos(w2 * t);
    const double ddphi = -m * w2 * w2 * std::sin(w2 * t);
    const double v = 0.1 * std::cos(phi) * dphi, a = 0.1 * (-std::sin(phi) * dphi * dphi + std::cos(phi) * ddphi);
    force(i) = 94.0 * a + 195.0 * v + 21.0 * (v > 0 ? 1.0 : -1.0) - 0.5;
  }
  return force;
}

TEST(Diagnosis, TimeDelayAndItsValue) {
  Scenario sc(12000);
  const double delay = 0.006;
  sc.s.model_output = sc.nominal_force;
  // Measured force = the model's force 6 ms later.
  sc.s.residual = NominalForceDelayedBy(sc, delay) - sc.nominal_force + sc.Noise(0.2);
  const DiagnosisResult r = DiagnoseMissingEffects(sc.s, sc.Base("avs1"));
  ASSERT_TRUE(r.missing_effect_found) << r.summary;
  EXPECT_EQ(r.effects.front().effect, "time_delay") << Names(r);
  EXPECT_NEAR(r.effects.front().parameters.at("delay"), delay, 0.03 * delay);
}

// An axis that strokes for 5 s (three cycles of 0.6 Hz, 0.1 m), rests for 2 s, then strokes again for 5 s (1 kHz);
// the logged force carries a payload of 15 kg picked up at `pick_up`. While the axis rests its acceleration is zero, so
// a pick-up anywhere in the rest fits the record as well: the interval the diagnosis gives spans the rest, and the time
// it names is the profile's posterior median, the rest's middle, not whichever end the noise favoured. Picked up while
// the axis strokes, the record places it within a few hundredths of the record.
DiagnosisResult PayloadPickedUpAt(double pick_up) {
  const Eigen::Index n = 12000;
  DiagnosisSignals s;
  s.time = Eigen::VectorXd::LinSpaced(n, 0.0, 1e-3 * static_cast<double>(n - 1));
  s.position.resize(n);
  s.velocity.resize(n);
  s.acceleration.resize(n);
  const double w = kTwoPi * 0.6;
  for (Eigen::Index i = 0; i < n; ++i) {
    const double t = s.time(i);
    const bool rests = t >= 5.0 && t < 7.0;
    const double tau = t < 5.0 ? t : t - 7.0;
    s.position(i) = rests ? 0.0 : 0.05 * (1.0 - std::cos(w * tau));
    s.velocity(i) = rests ? 0.0 : 0.05 * w * std::sin(w * tau);
    s.acceleration(i) = rests ? 0.0 : 0.05 * w * w * std::cos(w * tau);
  }
  std::mt19937 rng(7);
  std::normal_distribution<double> noise(0.0, 0.3);
  s.residual.resize(n);
  for (Eigen::Index i = 0; i < n; ++i) {
    s.residual(i) = (s.time(i) >= pick_up ? 15.0 * s.acceleration(i) : 0.0) + noise(rng);
  }
  BaseRegressors base;
  base.names = {"mass", "viscous", "coulomb", "offset"};
  base.columns.resize(n, 4);
  base.columns.col(0) = s.acceleration;
  base.columns.col(1) = s.velocity;
  base.columns.col(2) = s.velocity.unaryExpr([](double v) { return v > 0.0 ? 1.0 : (v < 0.0 ? -1.0 : 0.0); });
  base.columns.col(3).setOnes();
  return DiagnoseMissingEffects(s, base);
}

TEST(Diagnosis, AChangeTimeIsGivenAsTheStretchTheRecordPlacesItIn) {
  for (const double pick_up : {6.0, 2.6}) {
    const DiagnosisResult r = PayloadPickedUpAt(pick_up);
    ASSERT_TRUE(r.missing_effect_found) << r.summary;
    const DiagnosedEffect& e = r.effects.front();
    ASSERT_EQ(e.effect, "mass_change") << Names(r);
    ASSERT_TRUE(e.time_intervals.count("change_time")) << e.description;
    const auto [low, high] = e.time_intervals.at("change_time");
    EXPECT_LE(low, e.parameters.at("change_time"));
    EXPECT_GE(high, e.parameters.at("change_time"));
    EXPECT_LE(low, pick_up) << e.description;
    EXPECT_GE(high, pick_up) << e.description;
    if (pick_up == 6.0) {  // anywhere in the rest, and nowhere the axis strokes
      EXPECT_LE(low, 5.2) << e.description;
      EXPECT_GE(high, 6.8) << e.description;
      EXPECT_GE(low, 4.8) << e.description;
      EXPECT_LE(high, 7.2) << e.description;
      EXPECT_NEAR(e.parameters.at("change_time"), 6.0, 0.25) << e.description;
      EXPECT_THAT(e.description, HasSubstr("given at its posterior median")) << e.description;
    } else {
      EXPECT_LT(high - low, 0.3) << e.description;
    }
    EXPECT_THAT(e.description, HasSubstr("The record places the time it changes between")) << e.description;
  }
}

// Only 30 % of the force lags by 6 ms (say, one phase of a drive): the residual is 0.3·(ŷ(t − d) − ŷ(t)), which a
// transport delay on the whole output cannot produce. It must not be named time_delay, and the notes say why.
TEST(Diagnosis, APartialLagIsNotCalledATimeDelay) {
  Scenario sc(12000);
  const double delay = 0.006;
  sc.s.model_output = sc.nominal_force;
  sc.s.residual = 0.3 * (NominalForceDelayedBy(sc, delay) - sc.nominal_force) + sc.Noise(0.2);
  const DiagnosisResult r = DiagnoseMissingEffects(sc.s, sc.Base("avs1"));
  EXPECT_FALSE(Named(r, "time_delay")) << Names(r);
  bool said_why = false;
  for (const auto& n : r.notes) said_why = said_why || n.find("time_delay (delay") != std::string::npos;
  EXPECT_TRUE(said_why) << r.summary;
}

TEST(Diagnosis, TimePeriodicVibrationIsNotCalledPositionPeriodic) {
  Scenario sc(15000);
  sc.s.residual = 0.5 * (kTwoPi * 23.0 * sc.s.time.array()).sin().matrix() + sc.Noise(0.25);
  const DiagnosisResult r = DiagnoseMissingEffects(sc.s, sc.Base("avs1"));
  ASSERT_TRUE(r.missing_effect_found) << r.summary;
  EXPECT_EQ(r.effects.front().effect, "time_periodic") << Names(r);
  EXPECT_NEAR(r.effects.front().parameters.at("frequency_hz"), 23.0, 0.02);
  EXPECT_FALSE(Named(r, "position_periodic")) << Names(r);
  EXPECT_FALSE(r.position_time_indistinguishable);
}

TEST(Diagnosis, ConstantSpeedCannotTellPositionFromTime) {
  const Eigen::Index n = 8000;
  DiagnosisSignals s;
  s.time = Eigen::VectorXd::LinSpaced(n, 0.0, 1e-3 * static_cast<double>(n - 1));
  s.velocity = Eigen::VectorXd::Constant(n, 0.025);
  s.position = 0.01 + 0.025 * s.time.array();
  s.acceleration = Eigen::VectorXd::Zero(n);
  std::mt19937 rng(8);
  std::normal_distribution<double> n01;
  s.residual = s.position.unaryExpr([&](double x) { return 0.4 * std::sin(kTwoPi * x / 5e-3) + 0.2 * n01(rng); });
  BaseRegressors base{Eigen::MatrixXd::Ones(n, 1), {"offset"}};
  const DiagnosisResult r = DiagnoseMissingEffects(s, base);
  ASSERT_TRUE(r.missing_effect_found) << r.summary;
  const std::string top = r.effects.front().effect;
  // At one speed |v|·sin(2πx/P) is sin(2πx/P) scaled: the speed-dependent ripple is the same column, and which of the
  // three wins is a matter of round-off. What must hold is that the record cannot tell them apart.
  EXPECT_TRUE(top == "position_periodic" || top == "time_periodic" || top == "velocity_dependent_ripple") << Names(r);
  EXPECT_NEAR(r.effects.front().parameters.count("period") ? r.effects.front().parameters.at("period")
                                                           : 0.025 / r.effects.front().parameters.at("frequency_hz"),
              5e-3, 5e-5);
  EXPECT_TRUE(r.position_time_indistinguishable) << Names(r);
  EXPECT_THAT(r.summary, HasSubstr("cannot tell position-periodic from time-periodic"));
}

TEST(Diagnosis, WhiteNoiseResidualMeansNothingIsMissing) {
  Scenario sc(12000);
  sc.s.residual = sc.Noise(0.4);
  sc.s.model_output = sc.nominal_force;
  sc.s.input = sc.nominal_force / 35.15;
  const DiagnosisResult r = DiagnoseMissingEffects(sc.s, sc.Base("avs1"));
  EXPECT_FALSE(r.missing_effect_found) << Names(r);
  EXPECT_TRUE(r.effects.empty());
  EXPECT_THAT(r.summary, HasSubstr("No missing effect"));
  EXPECT_TRUE(r.whiteness_before.white);
  ASSERT_FALSE(r.position_peaks.empty());
  EXPECT_FALSE(r.position_peaks.front().significant);
  EXPECT_NEAR(r.explained_share, 0.0, 1e-12);
}

bool HasNote(const DiagnosisResult& r, const std::string& text) {
  for (const auto& n : r.notes) if (n.find(text) != std::string::npos) return true;
  return false;
}

// A force that depends on the direction of travel and grows towards the ends of the travel (a loop against position,
// not a constant Coulomb level): the hysteresis note; a white residual: none.
// A residual that loops against position — forward minus back a force of the position — is the grammar's
// friction_along_travel when it is smooth over the travel (issue 40: it was only a note); what the grammar leaves of a
// loop gets the hysteresis note.
TEST(Diagnosis, AResidualThatLoopsAgainstPositionIsNamedOrNoted) {
  Scenario sc(12000);
  const Eigen::ArrayXd xi = (sc.s.position.array() - 0.1) / 0.1;
  sc.s.model_output = sc.nominal_force;
  sc.s.input = sc.nominal_force / 35.15;
  sc.s.residual = (3.0 * xi.square()).matrix().cwiseProduct(sc.Sign()) + sc.Noise(0.4);
  const DiagnosisResult smooth = DiagnoseMissingEffects(sc.s, sc.Base("avs1"));
  ASSERT_FALSE(smooth.effects.empty());
  EXPECT_EQ(smooth.effects.front().effect, "friction_along_travel") << Names(smooth);
  EXPECT_GT(smooth.effects.front().score, 0.5) << Names(smooth);
  EXPECT_FALSE(HasNote(smooth, "hysteresis")) << Names(smooth);
  sc.s.residual = (3.0 * (xi * 6.0).sin()).matrix().cwiseProduct(sc.Sign()) + sc.Noise(0.4);
  const DiagnosisResult wavy = DiagnoseMissingEffects(sc.s, sc.Base("avs1"));
  EXPECT_TRUE(HasNote(wavy, "hysteresis: the residual loops against position")) << Names(wavy);
  sc.s.residual = sc.Noise(0.4);
  EXPECT_FALSE(HasNote(DiagnoseMissingEffects(sc.s, sc.Base("avs1")), "hysteresis"));
}

TEST(Diagnosis, CorrectionTransfersToANewRecordAndJsonHasTheFields) {
  Scenario fit(12000), val(9000);
  auto ripple = [](const Eigen::VectorXd& x) { return x.unaryExpr([](double p) { return 0.3 * std::cos(kTwoPi * p / 4e-3); }); };
  fit.s.residual = ripple(fit.s.position) + 5.0 * fit.s.velocity + fit.Noise(0.1);
  val.s.residual = ripple(val.s.position) + 5.0 * val.s.velocity + val.Noise(0.1);
  const DiagnosisResult r = DiagnoseMissingEffects(fit.s, fit.Base("avs1"));
  ASSERT_TRUE(r.missing_effect_found);
  const Eigen::VectorXd corrected = val.s.residual - PredictCorrection(r, val.s, val.Base("avs1"));
  EXPECT_LT(Rmse(corrected, Eigen::VectorXd::Zero(corrected.size())), 0.11);
  EXPECT_NEAR(r.base_coefficients(1), 5.0, 0.1);  // the viscous correction went to the base parameter
  const nlohmann::json j = r.ToJson();
  EXPECT_EQ(j.at("effects").at(0).at("effect"), "position_periodic");
  EXPECT_TRUE(j.at("missing_effect_found").get<bool>());
  EXPECT_EQ(j.at("base_parameters").size(), 4u);
  EXPECT_TRUE(j.at("effects").at(0).at("parameters").contains("period"));
}

// A third factor (amplitude_factor.h): a cogging whose amplitude grows 30 % from the middle of the record to its end
// is named as the ripple with its amplitude following time, 3 %/s; its columns are the ripple's and the ripple's force
// times z̃ = (t − t₀)/h, and a diagram's two parts (the ripple at t₀, its part proportional to t − t₀) add up to it.
TEST(Diagnosis, ARippleWhoseAmplitudeDriftsCarriesAThirdFactorOfTime) {
  Scenario sc(20000);
  const Eigen::VectorXd phase = kTwoPi * sc.s.position / 0.0225;
  const Eigen::VectorXd ripple = 3.0 * phase.array().cos() - 1.0 * phase.array().sin();
  const Eigen::VectorXd z = (sc.s.time.array() - 10.0) / 10.0;  // the record runs 0..20 s
  sc.s.residual = ripple.cwiseProduct((1.0 + 0.3 * z.array()).matrix()) + sc.Noise(0.2);
  const DiagnosisResult r = DiagnoseMissingEffects(sc.s, sc.Base("avs1"), DiagnosisOptions{});
  ASSERT_FALSE(r.effects.empty()) << Names(r);
  const DiagnosedEffect& e = r.effects.front();
  EXPECT_EQ(e.effect, "position_periodic") << Names(r);
  ASSERT_TRUE(e.parameters.count("amplitude_with")) << e.description;
  EXPECT_EQ(e.parameters.at("amplitude_with"), -1.0);
  EXPECT_NEAR(e.parameters.at("amplitude_slope"), 0.03, 0.0045) << e.description;
  EXPECT_THAT(e.description, HasSubstr("Its amplitude changes with time: +"));

  // The columns, and the two parts a diagram adds.
  const EffectRegressors reg = BuildEffectRegressors({e.effect, e.parameters}, sc.s);
  ASSERT_EQ(reg.columns.cols(), e.coefficients.size());
  EXPECT_EQ(reg.column_names.back(), "position_periodic:amplitude");
  const Eigen::Index k = reg.columns.cols() - 1;
  const Eigen::VectorXd w = AmplitudeWeights(e.parameters);
  const Eigen::VectorXd zz = (sc.s.time.array() - e.parameters.at("amplitude_origin")) / e.parameters.at("amplitude_scale");
  EXPECT_LT((reg.columns.col(k) - (reg.columns.leftCols(k) * w).cwiseProduct(zz)).cwiseAbs().maxCoeff(), 1e-12);
  const AmplitudeParts parts = SplitAmplitudeFactor(e);
  ASSERT_TRUE(parts.part.has_value());
  EXPECT_EQ(parts.main.column_names.size(), static_cast<std::size_t>(k));
  EXPECT_FALSE(parts.main.parameters.count("amplitude_with"));
  const Eigen::VectorXd whole = reg.columns * e.coefficients;
  const Eigen::VectorXd added = reg.columns.leftCols(k) * parts.main.coefficients +
                                (reg.columns.leftCols(k) * parts.part->coefficients)
                                    .cwiseProduct((sc.s.time.array() - e.parameters.at("amplitude_origin")).matrix());
  EXPECT_LT((whole - added).cwiseAbs().maxCoeff(), 1e-9 * whole.cwiseAbs().maxCoeff());

  // Without the drift, no third factor.
  sc.s.residual = ripple + sc.Noise(0.2);
  const DiagnosisResult steady = DiagnoseMissingEffects(sc.s, sc.Base("avs1"), DiagnosisOptions{});
  ASSERT_FALSE(steady.effects.empty());
  EXPECT_FALSE(steady.effects.front().parameters.count("amplitude_with")) << steady.effects.front().description;
}

// A third factor's parameters that cannot make its column are refused with the reason, not guessed.
TEST(Diagnosis, AThirdFactorWithoutItsParametersIsRefusedWithTheReason) {
  Scenario sc(2000);
  sc.s.residual = sc.Noise(0.1);
  const std::map<std::string, double> ripple{{"period", 0.0225}, {"harmonics", 1}};
  const auto message = [&](std::map<std::string, double> extra) {
    std::map<std::string, double> p = ripple;
    p.insert(extra.begin(), extra.end());
    try {
      BuildEffectRegressors({"position_periodic", p}, sc.s);
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("accepted");
  };
  const std::map<std::string, double> whole{{"amplitude_with", -1.0}, {"amplitude_origin", 1.0},
                                            {"amplitude_scale", 1.0}, {"amplitude_weight.0", 1.0},
                                            {"amplitude_weight.1", 0.0}};
  EXPECT_EQ(message(whole), "accepted");
  std::map<std::string, double> no_scale = whole;
  no_scale.erase("amplitude_scale");
  EXPECT_THAT(message(no_scale), HasSubstr("no finite 'amplitude_scale'"));
  std::map<std::string, double> zero_scale = whole;
  zero_scale["amplitude_scale"] = 0.0;
  EXPECT_THAT(message(zero_scale), HasSubstr("scale 0 must be > 0"));
  std::map<std::string, double> one_weight = whole;
  one_weight.erase("amplitude_weight.1");
  EXPECT_THAT(message(one_weight), HasSubstr("1 weights for 2 columns"));
  std::map<std::string, double> no_column = whole;
  no_column["amplitude_with"] = 3.0;
  EXPECT_THAT(message(no_column), HasSubstr("names no unread log column"));
}

TEST(Diagnosis, BinnedResidualShowsTheFrictionShape) {
  Scenario sc(6000);
  const Eigen::VectorXd r = 20.0 * sc.Sign();
  const BinnedResidual b = BinResidual(sc.s.velocity, r, 10);
  ASSERT_EQ(b.centers.size(), 10);
  EXPECT_DOUBLE_EQ(b.mean(0), -20.0);
  EXPECT_DOUBLE_EQ(b.mean(9), 20.0);
  EXPECT_DOUBLE_EQ(b.std(0), 0.0);
  EXPECT_EQ(b.count.sum(), 6000);
  EXPECT_THROW(BinResidual(Eigen::VectorXd::Ones(5), Eigen::VectorXd::Ones(5), 3), std::invalid_argument);
}

TEST(Diagnosis, RejectsInconsistentInput) {
  Scenario sc(1000);
  sc.s.residual = sc.Noise(1.0);
  sc.s.velocity.resize(999);
  try {
    DiagnoseMissingEffects(sc.s, {});
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("'velocity' has 999 samples but 'time' has 1000"));
  }
  EXPECT_THROW(BuildEffectRegressors({"cogging", {}}, sc.s), std::invalid_argument);
}

TEST(Diagnosis, RejectsRobustOptionsOutOfRange) {
  Scenario sc(1000);
  sc.s.residual = sc.Noise(1.0);
  DiagnosisOptions options;
  options.huber_k = -1.0;
  try {
    DiagnoseMissingEffects(sc.s, sc.Base("avs1"), options);
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_STREQ(e.what(), "DiagnoseMissingEffects: huber_k = -1 and significance_t = 2.33 must be >= 0 and "
                           "significance_batches = 40 >= 2");
  }
}

// The user's model has sign(v) friction, the machine a smooth law, and it dwells at rest: the residual chatters ±F_c
// on the dwell samples. The law is replaced (regularized_coulomb_friction, its v_c), not called a missing Coulomb
// force, and the ripple behind it is named first.
TEST(Diagnosis, ASmoothFrictionLawAtRestIsReplacedAndTheRippleBehindItNamed) {
  Scenario sc(12000);
  const Eigen::Index n = sc.s.time.size();
  for (Eigen::Index i = 0; i < n; ++i) {  // dwell: 0.4 s at rest every 2 s, velocity noise only
    if (std::fmod(sc.s.time(i), 2.0) < 0.4) {
      sc.s.velocity(i) = 2e-5 * sc.n01(sc.rng);
      sc.s.acceleration(i) = 0.0;
    }
  }
  const Eigen::VectorXd smooth = (sc.s.velocity.array() / 5e-4).tanh();
  const Eigen::VectorXd sign = sc.Sign();
  const Eigen::VectorXd ripple = 1.5 * (kTwoPi * sc.s.position.array() / 0.006).sin();
  sc.s.residual = 21.0 * (smooth - sign) + ripple + sc.Noise(0.5);
  const DiagnosisResult r = DiagnoseMissingEffects(sc.s, sc.Base("avs1"));
  ASSERT_TRUE(r.missing_effect_found) << Names(r);
  ASSERT_FALSE(r.friction_law.empty()) << Names(r);
  EXPECT_EQ(r.friction_law.front(), "regularized_coulomb_friction") << Names(r);
  EXPECT_FALSE(Named(r, "coulomb_friction")) << Names(r);
  EXPECT_EQ(r.effects.front().effect, "position_periodic") << Names(r);
  EXPECT_NEAR(r.effects.front().parameters.at("period"), 0.006, 0.03 * 0.006);
  EXPECT_THAT(r.summary, HasSubstr("The friction law near zero velocity is wrong: regularized_coulomb_friction"));
  // The smooth law is the whole Coulomb law: it takes over the base's sign(v) parameter; the ripple adds to the model.
  for (const auto& e : r.effects) {
    EXPECT_EQ(e.replaced_parameter, e.effect == "regularized_coulomb_friction" ? "coulomb" : "") << e.effect;
  }
}

// The real EMPS data (IDIM-LS style): position low-passed at 50 Hz and differentiated, the force through
// the same zero-phase filter (parallel filtering), rigid body + viscous + Coulomb + offset fitted to the
// force by least squares. The screw-lead ripple (position-periodic, 2.5 mm) must be found; the printed
// figures go to the report (see docs/diagnosis.md).
TEST(Diagnosis, EmpsScrewLeadRipple) {
  const std::string dir = std::string(MB_SOURCE_DIR) + "/diagrams/emps/data/";
  ASSERT_TRUE(std::filesystem::exists(dir + "DATA_EMPS.csv")) << "the repository's EMPS record is missing in " << dir;
  constexpr double kCutoffHz = 50.0;
  struct Prepared {
    DiagnosisSignals s;
    BaseRegressors base;
    Eigen::VectorXd force;
  };
  auto prepare = [](const MeasurementLog& log) {
    Prepared p;
    p.s.time = log.time();
    const MotionDerivatives m = DeriveMotion(log.time(), log.column("position_m"), kCutoffHz);
    p.s.position = m.position;
    p.s.velocity = m.velocity;
    p.s.acceleration = m.acceleration;
    p.s.input = log.column("input_V");
    p.force = ZeroPhaseLowPass(log.column("force_N"), MedianTimeStep(log.time()), kCutoffHz);
    const Eigen::Index n = p.force.size();
    p.base.columns.resize(n, 4);
    p.base.columns << m.acceleration, m.velocity,
        m.velocity.unaryExpr([](double v) { return v > 0 ? 1.0 : (v < 0 ? -1.0 : 0.0); }), Eigen::VectorXd::Ones(n);
    p.base.names = {"mass", "viscous", "coulomb", "offset"};
    return p;
  };
  Prepared est = prepare(ReadMeasurementLog(dir + "DATA_EMPS.csv", {.required_columns = {"position_m", "force_N"}}));
  const Eigen::VectorXd theta = est.base.columns.colPivHouseholderQr().solve(est.force);
  EXPECT_NEAR(theta(0), 94.0, 5.0);
  EXPECT_NEAR(theta(1), 195.0, 15.0);
  EXPECT_NEAR(theta(2), 21.0, 3.0);
  est.s.model_output = est.base.columns * theta;
  est.s.residual = est.force - est.s.model_output;
  const DiagnosisResult r = DiagnoseMissingEffects(est.s, est.base);
  ASSERT_TRUE(r.missing_effect_found) << r.summary;
  std::cout << "EMPS fit (M, Fv, Fc, offset) = " << theta.transpose() << "\n"
            << "EMPS diagnosis: " << r.summary << "\n";
  for (const auto& e : r.effects) std::cout << "  " << e.description << "\n";
  for (const auto& n : r.notes) std::cout << "  note: " << n << "\n";
  // The screw lead: a chosen position-periodic ripple at 2.5 mm (±2 %; plain or growing with |v|), and
  // the strongest position period in the searched band. (It is not ranked first: the low-velocity
  // friction carries more of the residual energy — see the report.)
  const DiagnosedEffect* lead = nullptr;
  for (const auto& e : r.effects) {
    if ((e.effect == "position_periodic" || e.effect == "velocity_dependent_ripple") &&
        std::abs(e.parameters.at("period") - 2.5e-3) < 0.02 * 2.5e-3) {
      lead = &e;
    }
  }
  ASSERT_NE(lead, nullptr) << Names(r);
  EXPECT_GT(lead->score, 0.02);
  ASSERT_FALSE(r.position_peaks.empty());
  EXPECT_NEAR(r.position_peaks.front().period, 2.5e-3, 0.02 * 2.5e-3);
  // Measured: 2.364 → 2.221 N in-sample. The bound was 0.8 while two effects of the wrong name scored here:
  // coulomb_friction on its dead band alone (13.6 %; now dropped, F_c is in the base) and a −1.33 ms time_delay
  // (7 %) whose coefficient is 0.26, not the 1 of a delay (now dropped: a scaled dŷ/dt, not a lag).
  EXPECT_LT(r.rmse_after, 0.95 * r.rmse_before);

  const std::string val_path = dir + "DATA_EMPS_PULSES.csv";
  if (std::filesystem::exists(val_path)) {
    Prepared val = prepare(ReadMeasurementLog(val_path, {.required_columns = {"position_m", "force_N"}}));
    val.s.model_output = val.base.columns * theta;
    val.s.residual = val.force - val.s.model_output;
    const Eigen::VectorXd zero = Eigen::VectorXd::Zero(val.force.size());
    const double before = Rmse(val.s.residual, zero);
    const double after = Rmse(val.s.residual - PredictCorrection(r, val.s, val.base), zero);
    std::cout << fmt::format("EMPS held out (PULSES): RMSE {:.4f} N -> {:.4f} N ({:.1f} % of the energy)\n", before,
                             after, 100.0 * (1.0 - after * after / (before * before)));
    EXPECT_LT(after, before);
  }
}

// A rotary axis turned once, slowly and speeding up, its speed pulled ±50 % by a 7-per-revolution cogging (as the
// ODrive records of issue 13): one revolution holds only 7 cycles. Position in rev, sampled every 2.27 ms.
struct OneRevolution {
  DiagnosisSignals s;
  explicit OneRevolution(double depth = 0.5) {
    const double dt = 2.27e-3, v0 = 0.03;
    const auto n = static_cast<Eigen::Index>(1.0 / v0 / dt);
    s.time = Eigen::VectorXd::LinSpaced(n, 0.0, dt * static_cast<double>(n - 1));
    s.position.resize(n);
    s.velocity.resize(n);
    s.acceleration.resize(n);
    double x = 0.0;
    for (Eigen::Index i = 0; i < n; ++i) {
      // The mean speed rises from 0.5 to 1.5 × v0 over the revolution: at one steady speed a period in position is
      // a period in time, and no record can tell them apart.
      const double v = v0 * (0.5 + x) * (1.0 + depth * std::sin(kTwoPi * 7.0 * x));
      s.position(i) = x;
      s.velocity(i) = v;
      s.acceleration(i) = v * v0 * ((1.0 + depth * std::sin(kTwoPi * 7.0 * x)) +
                                    (0.5 + x) * depth * std::cos(kTwoPi * 7.0 * x) * kTwoPi * 7.0);
      x += v * dt;
    }
  }
  // Only an offset: the speed ripple is a sinusoid of 7x itself, so v and a as base regressors would span the
  // ripple's fundamental (the refit would take it as viscous friction and inertia).
  BaseRegressors Base() const { return {Eigen::MatrixXd::Ones(s.size(), 1), {"offset"}}; }
};

Eigen::VectorXd WhiteNoise(Eigen::Index n, double sigma, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> n01;
  Eigen::VectorXd e(n);
  for (auto& v : e) v = sigma * n01(rng);
  return e;
}

TEST(Diagnosis, SevenCyclesPerRevolutionOnOneRevolutionAreFoundWithHarmonics) {
  OneRevolution rev;
  const Eigen::VectorXd& x = rev.s.position;
  rev.s.residual = (0.8 * (kTwoPi * 7.0 * x.array()).sin() + 0.3 * (kTwoPi * 14.0 * x.array()).cos() +
                    0.15 * (kTwoPi * 28.0 * x.array()).sin()).matrix() + WhiteNoise(x.size(), 0.05, 5);
  DiagnosisOptions options;
  options.position_unit = "rev";
  const DiagnosisResult r = DiagnoseMissingEffects(rev.s, rev.Base(), options);
  ASSERT_TRUE(r.missing_effect_found) << r.summary;
  const DiagnosedEffect& top = r.effects.front();
  ASSERT_EQ(top.effect, "position_periodic") << Names(r);
  EXPECT_NEAR(top.parameters.at("period"), 1.0 / 7.0, 0.03 / 7.0) << Names(r) << ::testing::PrintToString(r.notes);
  EXPECT_GE(top.parameters.at("harmonics"), 2.0);
  EXPECT_THAT(r.summary, HasSubstr(" rev (")); // "period 0.1429 rev (7.000 per revolution)"
  EXPECT_THAT(r.summary, HasSubstr(" per revolution)"));
  // Told from a vibration by how the residual follows the speed, not by the speed's spread.
  EXPECT_FALSE(r.position_time_indistinguishable) << Names(r);
  bool followed = false;
  for (const auto& n : r.notes) followed = followed || n.find("follows the position, not time") != std::string::npos;
  EXPECT_TRUE(followed) << ::testing::PrintToString(r.notes);
}

TEST(Diagnosis, AVibrationOnTheSameSlowRevolutionStaysTimePeriodic) {
  OneRevolution rev;
  rev.s.residual = 0.8 * (kTwoPi * 0.21 * rev.s.time.array()).sin().matrix() + WhiteNoise(rev.s.size(), 0.05, 6);
  DiagnosisOptions options;
  options.position_unit = "rev";
  const DiagnosisResult r = DiagnoseMissingEffects(rev.s, rev.Base(), options);
  ASSERT_TRUE(r.missing_effect_found) << r.summary;
  ASSERT_EQ(r.effects.front().effect, "time_periodic") << Names(r);
  EXPECT_NEAR(r.effects.front().parameters.at("frequency_hz"), 0.21, 0.03 * 0.21);
  EXPECT_FALSE(r.position_time_indistinguishable) << Names(r);
}

TEST(Diagnosis, APeriodogramTheRecordCannotSupportIsSkippedWithANote) {
  // Position steps as large as the travel: the position periodogram's period range is empty.
  const Eigen::Index n = 4000;
  DiagnosisSignals s;
  s.time = Eigen::VectorXd::LinSpaced(n, 0.0, 1e-3 * static_cast<double>(n - 1));
  s.position = Eigen::VectorXd::NullaryExpr(n, [](Eigen::Index i) { return 0.01 * static_cast<double>(i % 2); });
  s.velocity = WhiteNoise(n, 0.1, 7);
  s.acceleration = WhiteNoise(n, 1.0, 8);
  s.residual = 0.5 * s.velocity + WhiteNoise(n, 0.1, 9);
  BaseRegressors base{Eigen::MatrixXd::Ones(n, 1), {"offset"}};
  DiagnosisResult r;
  ASSERT_NO_THROW(r = DiagnoseMissingEffects(s, base));
  bool noted = false;
  for (const auto& note : r.notes) {
    // In the user's words: no internal function name (issue 40, item 8).
    noted = noted || note.find("the position periodogram (position-periodic candidates) skipped on this record: "
                               "the period range") != std::string::npos;
    EXPECT_EQ(note.find("LombScarglePeriodogram"), std::string::npos) << note;
  }
  EXPECT_TRUE(noted) << ::testing::PrintToString(r.notes);
  ASSERT_TRUE(r.missing_effect_found) << r.summary;
  EXPECT_EQ(r.effects.front().effect, "viscous_friction") << Names(r);
}

// Negative controls at scale (issue 40, item 6): with the grammar's products, the unread log columns and the command
// built regressors among the candidates, nothing may be named on noise. Twenty seeds of a white residual in
// equation-error mode (the logged command the nominal force plus the noise, an idle extra column logged): no effect
// explains 2 % of the held-out residual, drive_saturation (its regressor built from the logged command) is never
// proposed, and the noise floor is the noise.
TEST(Diagnosis, NothingIsNamedOnTwentyNoiseOnlySeeds) {
  constexpr double kSigma = 0.5;
  int named = 0;
  for (unsigned seed = 1; seed <= 20; ++seed) {
    Scenario sc(6000);
    sc.rng.seed(seed);
    const Eigen::VectorXd noise = sc.Noise(kSigma);
    sc.s.residual = noise;
    sc.s.model_output = sc.nominal_force;
    sc.s.logged_command = sc.nominal_force + noise;
    sc.s.extra_names = {"temperature_C"};
    sc.s.extra_columns = {(22.0 + 0.5 * (kTwoPi * sc.s.time.array() / 7.0).sin()).matrix() + sc.Noise(0.01)};
    const DiagnosisResult r = DiagnoseMissingEffects(sc.s, sc.Base("avs1"));
    for (const auto& e : r.effects) {
      EXPECT_LT(e.score, 0.02) << "seed " << seed << ": " << Names(r);
      ++named;
    }
    for (const auto& c : r.candidates) {  // built from the compared output: not even a candidate (physical test)
      EXPECT_NE(c.name, "drive_saturation") << "seed " << seed;
      EXPECT_NE(c.name, "drive_voltage_limit") << "seed " << seed;
    }
    EXPECT_GE(r.noise_floor.rms, 0.7 * kSigma) << "seed " << seed;  // a lower estimate of the noise
    EXPECT_LE(r.noise_floor.rms, 1.0 * kSigma) << "seed " << seed;
  }
  RecordProperty("effects_named_over_20_seeds", named);
}

// The leak guard (issue 40, item 5): a candidate whose held-out error would fall below 0.7 × the noise floor fits the
// noise. A residual of noise and a column that IS that noise on three quarters of the samples (what drive_saturation's
// excess was on half the samples of a record that never saturates): refused, with the reason in the notes.
TEST(Diagnosis, ACandidateThatFitsTheNoiseIsRefusedAsALeak) {
  Scenario sc(6000);
  const Eigen::VectorXd noise = sc.Noise(0.5);
  sc.s.residual = noise;
  // The extra column is the residual itself on three samples in four: a regressor built from the compared output.
  Eigen::VectorXd echo = noise;
  for (Eigen::Index i = 0; i < echo.size(); i += 4) echo(i) = 0.0;
  sc.s.extra_names = {"echo_of_the_output"};
  sc.s.extra_columns = {echo};
  const DiagnosisResult r = DiagnoseMissingEffects(sc.s, sc.Base("avs1"));
  EXPECT_FALSE(Named(r, "logged_column")) << Names(r);
  bool refused = false;
  for (const auto& note : r.notes) refused = refused || (note.find("logged_column refused") != std::string::npos &&
                                                         note.find("noise floor") != std::string::npos);
  EXPECT_TRUE(refused) << fmt::format("{}", fmt::join(r.notes, "\n"));
  // Without the guard the same column is chosen: the test can fail.
  DiagnosisOptions off;
  off.leak_floor_ratio = 0.0;
  EXPECT_TRUE(Named(DiagnoseMissingEffects(sc.s, sc.Base("avs1"), off), "logged_column"));
}

// What a residual depends on (issue 40, item 4): a friction that changes along the travel — a smooth function of the
// position times the direction of travel — and noise. Position and the direction of travel are relevant, time and an
// idle log column are not, and the words say so.
TEST(SignalRelevance, NamesWhatTheResidualDependsOnAndWhatNot) {
  Scenario sc(8000);
  sc.s.extra_names = {"temperature_C"};
  sc.s.extra_columns = {(22.0 + 0.5 * (kTwoPi * sc.s.time.array() / 31.0).sin()).matrix()};
  const Eigen::VectorXd friction = (3.0 * (1.0 + (kTwoPi * sc.s.position.array() / 0.2).cos())).matrix();
  const Eigen::VectorXd r = friction.cwiseProduct(sc.Sign()) + sc.Noise(0.3);
  const std::vector<SignalRelevance> rel = RankSignalRelevance(sc.s, r);
  ASSERT_FALSE(rel.empty());
  std::map<std::string, double> share;
  for (const auto& s : rel) share[s.signal] = s.heldout_share;
  EXPECT_GT(share.at("direction of travel"), 0.3);
  EXPECT_LT(share.at("time"), 0.02);
  EXPECT_LT(share.at("temperature_C"), 0.02);
  const std::string words = DescribeRelevance(rel);
  EXPECT_THAT(words, HasSubstr("depends on"));
  EXPECT_THAT(words, HasSubstr("not on"));
  EXPECT_THAT(words, HasSubstr("time ("));
  EXPECT_THROW(RankSignalRelevance(sc.s, r.head(10)), std::invalid_argument);
}

}  // namespace
}  // namespace mb

// Section 4.2: ρ (eq. 58) and the α_max bound (eq. 62) on numbers checkable by hand, the γ terms of simple
// filters in closed form, eq. 6/12 identities for P = P_n, and the analysis of the conventional diagram.

#include <cmath>
#include <numbers>

#include <gtest/gtest.h>

#include "engine/diagram_loader.h"
#include "models/stability/dob_design.h"
#include "models/stability/stability.h"

namespace mb {
namespace {

constexpr double kPi = std::numbers::pi;

TEST(StabilityTest, RhoAndAlphaMaxByHand) {
  SmallGainTerms t;
  t.gamma_d_to_x = 0.01;  // m/N
  t.gamma_q = 2.0;
  t.gamma_q_filter = 1.0;
  t.gamma_x_to_u = 3.0;
  t.gamma_g = 1.0;
  t.alpha_max = 0.5;
  t.lipschitz_x = 4.0;
  t.lipschitz_xdot = 0.5;
  t.gamma_xdot = 10.0;
  // K = 4 + 0.5·10 = 9; ρ = 0.01·(2·(1 + 3) + 1·0.5·9) = 0.01·12.5 = 0.125.
  EXPECT_DOUBLE_EQ(LipschitzGain(t), 9.0);
  EXPECT_DOUBLE_EQ(RhoPaper(t), 0.125);
  // ρ' = 0.01·(2 + 1·3 + 4.5) = 0.095.
  EXPECT_DOUBLE_EQ(RhoConsistent(t), 0.095);
  // α_max < (1/0.01 − 2·4)/(1·9) = 92/9.
  EXPECT_DOUBLE_EQ(AlphaMaxBoundPaper(t), 92.0 / 9.0);
  // At the bound ρ = 1 exactly.
  SmallGainTerms at = t;
  at.alpha_max = AlphaMaxBoundPaper(t);
  EXPECT_NEAR(RhoPaper(at), 1.0, 1e-12);
  // The 'dob' form: α < 1/(γ_d→x γ_g K) = 1/0.09.
  EXPECT_DOUBLE_EQ(AlphaMaxBoundDob(t), 1.0 / 0.09);
  // No GP path (K = 0): no bound on α.
  SmallGainTerms no_gp = t;
  no_gp.lipschitz_x = no_gp.lipschitz_xdot = 0.0;
  EXPECT_TRUE(std::isinf(AlphaMaxBoundPaper(no_gp)));
}

TEST(StabilityTest, FilterGainsInClosedForm) {
  // γ_ẋ of the velocity estimator: 2(1 − a)/Ts; γ_g of a first-order ZOH low-pass: 1.
  const double ts = 1e-3, a = std::exp(-2.0 * kPi * 100.0 * ts);
  EXPECT_NEAR(L1Norm(VelocityEstimatorFilter(100.0, ts)), 2.0 * (1.0 - a) / ts, 1e-6);
  EXPECT_NEAR(L1Norm(Discretize(BinomialLowPass(100.0, 1), ts, Discretization::kZeroOrderHold)), 1.0, 1e-9);
  // γ_x→u = ‖C_FB‖₁ of the PD: h[0] = K_p + K_d(1 − a)/Ts, h[k ≥ 1] = −K_d(1 − a)² a^(k−1)/Ts, so
  // ‖C_FB‖₁ = K_p + 2 K_d (1 − a)/Ts.
  const double kp = 100.0, kd = 2.0;
  const double expected = kp + kd * (1.0 - a) / ts + kd * (1.0 - a) / ts;
  EXPECT_NEAR(L1Norm(PdFilter(kp, kd, 100.0, ts)), expected, 1e-6 * expected);
}

TEST(StabilityTest, NominalPlantGivesUnitReferenceResponseAndDhatEqualsQ) {
  PaperLoop l;
  l.kp = 16000.0;
  l.kd = 90.0;
  for (const BodePoint& b : ClosedLoopBode(l, {0.5, 5.0, 50.0})) {
    const std::complex<double> s(0.0, 2.0 * kPi * b.frequency_hz);
    const std::complex<double> q = BinomialLowPass(l.q_cutoff_hz, 2).Evaluate(s);
    EXPECT_NEAR(std::abs(b.xd_to_x_continuous - 1.0), 0.0, 1e-12) << b.frequency_hz;  // eq. 6 with P = P_n
    EXPECT_NEAR(std::abs(b.d_to_dhat_continuous - q), 0.0, 1e-12) << b.frequency_hz;  // eq. 12 = Q
  }
}

TEST(StabilityTest, GammaBoundsTheGainAtEveryFrequency) {
  PaperLoop l;
  l.kp = 16000.0;
  l.kd = 90.0;
  const StabilityReport r = AnalyseStability(l);
  ASSERT_TRUE(r.inner_loop_stable);
  ASSERT_TRUE(r.dob_loop_stable);
  // ‖G‖₁ ≥ sup_ω |G(e^{jωT})|, and the inner PD loop's DC gain is 1/K_p.
  for (const BodePoint& b : r.bode) {
    EXPECT_GE(r.dob.gamma_d_to_x, std::abs(b.d_to_x_discrete) * (1.0 - 1e-9));
  }
  EXPECT_GE(r.paper.gamma_d_to_x, 1.0 / l.kp);
  // The 'paper' decomposition cannot certify a PD loop: γ_d→x·‖C_FB‖₁ ≥ 1.
  EXPECT_GE(r.paper.gamma_d_to_x * r.paper.gamma_x_to_u, 1.0);
  EXPECT_GE(r.rho_paper, 1.0);
  // Without a GP model the 'dob' decomposition has ρ = 0 and no bound on α.
  EXPECT_EQ(r.rho_dob, 0.0);
  EXPECT_TRUE(std::isinf(r.alpha_max_bound_dob));
  const nlohmann::json j = ToJson(r);
  EXPECT_TRUE(j["dob"]["alpha_max_bound"].is_null());
  EXPECT_EQ(j["bode"].size(), r.bode.size());
}

TEST(StabilityTest, ReadsTheConventionalDiagram) {
  const Diagram d = LoadDiagram(std::string(MB_SOURCE_DIR) + "/diagrams/paper/conventional.json");
  const PaperLoop l = PaperLoopFromDiagram(d);
  EXPECT_DOUBLE_EQ(l.sample_time, 0.001);
  EXPECT_DOUBLE_EQ(l.nominal_mass, 0.2621);
  EXPECT_DOUBLE_EQ(l.nominal_damping, 3.0);
  EXPECT_GT(l.kp, 0.0);
  EXPECT_GT(l.kd, 0.0);
  const StabilityReport r = AnalyseStability(d);
  EXPECT_TRUE(r.dob_loop_stable);
  EXPECT_TRUE(std::isfinite(r.dob.gamma_d_to_x));
}

}  // namespace
}  // namespace mb

// Section 4.2: ρ (eq. 58) and the α_max bound (eq. 62) on numbers checkable by hand, the γ terms of simple
// filters in closed form, eq. 6/12 identities for P = P_n, and the analysis of the conventional diagram.

#include <cmath>
#include <limits>
#include <numbers>
#include <string>

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "engine/diagram_loader.h"
#include "models/gpr/gpr_io.h"
#include "models/stability/dob_design.h"
#include "models/stability/stability.h"
#include "tests/paper/paper_util.h"
#include "tools/workflow/loop_from_diagram.h"

namespace mb {
namespace {

using paper_testing::kPi;

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

TEST(StabilityTest, BoundsInWordsAreNeverNegativeOrMinusInfinity) {
  constexpr double kInf = std::numeric_limits<double>::infinity();
  EXPECT_EQ(AlphaBoundText(4.23106, true), "α_max < 4.231");
  EXPECT_EQ(AlphaBoundText(-2.093e4, true), "no α > 0 is certified: ρ ≥ 1 already at α = 0");
  EXPECT_EQ(AlphaBoundText(0.0, true), "no α > 0 is certified: ρ ≥ 1 already at α = 0");
  EXPECT_EQ(AlphaBoundText(-kInf, false), "no α > 0 is certified: ρ ≥ 1 already at α = 0");
  EXPECT_EQ(AlphaBoundText(kInf, true), "any α is certified (K = 0)");
  EXPECT_EQ(AlphaBoundText(kInf, false), "α not bounded without a GPR model (K unknown)");
}

// The verdict of the 'dob' decomposition on a loop checkable by hand: ρ_dob = γ_d→x γ_g α K is linear in α, so the
// α bound is where ρ = 1, and a weight on either side of it is certified or not.
TEST(StabilityTest, VerdictNamesTheFailingConditionAndTheLargestAlpha) {
  const std::string dir = std::string(MB_SOURCE_DIR) + "/diagrams/paper";
  const GprModel model = LoadGprModel(dir + "/models/gpr_ps_d2.json");
  StabilityOptions options;
  options.impulse_samples = 2000;
  options.bode_points = 4;
  PaperLoop l;
  l.kp = 16000.0;
  l.kd = 90.0;
  l.gp_weight = 1.0;
  const StabilityReport one = AnalyseStability(l, &model, options);
  const double bound = one.alpha_max_bound_dob;
  ASSERT_TRUE(std::isfinite(bound));
  ASSERT_GT(bound, 0.0);
  EXPECT_NEAR(one.rho_dob * bound, 1.0, 1e-12);  // ρ(α) = α ρ(1)

  l.gp_weight = 2.0 * bound;
  const StabilityReport over = AnalyseStability(l, &model, options);
  EXPECT_FALSE(over.verdict.certified);
  EXPECT_EQ(over.verdict.failing_condition, StabilityCondition::kSmallGain);
  EXPECT_DOUBLE_EQ(over.verdict.alpha_used, 2.0 * bound);
  EXPECT_DOUBLE_EQ(over.verdict.alpha_max, bound);
  EXPECT_EQ(over.verdict.line,
            fmt::format("NOT certified: ρ = 2 ≥ 1 at α = {:g} (small gain, DOB loop closed); the largest certified α: "
                        "α < {:.4g}",
                        2.0 * bound, bound));
  const nlohmann::json j = ToJson(over)["verdict"];
  EXPECT_EQ(j["certified"], false);
  EXPECT_EQ(j["failing_condition"], "small_gain");
  EXPECT_EQ(j["decomposition"], "dob");
  EXPECT_DOUBLE_EQ(j["alpha_used"].get<double>(), 2.0 * bound);
  EXPECT_DOUBLE_EQ(j["alpha_max"].get<double>(), bound);
  EXPECT_EQ(j["line"], over.verdict.line);
  // The α used is named as such, not as a maximum.
  EXPECT_DOUBLE_EQ(ToJson(over)["dob"]["alpha_used"].get<double>(), 2.0 * bound);
  EXPECT_FALSE(ToJson(over)["dob"].contains("alpha_max"));

  l.gp_weight = 0.5 * bound;
  const StabilityReport under = AnalyseStability(l, &model, options);
  EXPECT_TRUE(under.verdict.certified);
  EXPECT_EQ(under.verdict.failing_condition, StabilityCondition::kNone);
  EXPECT_EQ(under.verdict.line.rfind("certified: ρ = 0.5 < 1 at α = ", 0), 0u) << under.verdict.line;
  EXPECT_TRUE(ToJson(under)["verdict"]["failing_condition"].is_null());
  // The 'paper' bound is negative (it cannot certify a DOB loop): 0 in the JSON, never a negative bound or null.
  EXPECT_LT(under.alpha_max_bound_paper, 0.0);
  EXPECT_EQ(ToJson(under)["paper"]["alpha_max_bound"], 0.0);
}

TEST(StabilityTest, VerdictOfAnUnstableLoopOrAGpPathWithoutItsModel) {
  StabilityOptions options;
  options.impulse_samples = 2000;
  options.bode_points = 4;
  PaperLoop l;
  l.kp = 16000.0;
  l.kd = 90.0;
  const StabilityReport conventional = AnalyseStability(l, nullptr, options);
  EXPECT_TRUE(conventional.verdict.certified);
  EXPECT_EQ(conventional.verdict.line,
            "certified: the conventional FF/FB/DOB loop is stable and the GP path is off (α = 0); the largest "
            "certified α is unknown without a GPR model (--gpr)");
  EXPECT_TRUE(ToJson(conventional)["verdict"]["alpha_max"].is_null());

  l.gp_weight = 0.9;
  const StabilityReport no_model = AnalyseStability(l, nullptr, options);
  EXPECT_FALSE(no_model.verdict.certified);
  EXPECT_EQ(no_model.verdict.failing_condition, StabilityCondition::kGprModelGiven);
  EXPECT_EQ(no_model.verdict.line,
            "NOT certified: the GP path (α = 0.9) is not bounded without its GPR model: give --gpr MODEL (K = L_x + "
            "L_ẋ·γ_ẋ); the largest certified α is unknown without a GPR model (--gpr)");
  EXPECT_EQ(ToJson(no_model)["verdict"]["failing_condition"], "gpr_model_given");

  l.kp = 1e8;  // far beyond what 1 ms sampling allows: the loop itself is unstable
  const StabilityReport unstable = AnalyseStability(l, nullptr, options);
  ASSERT_FALSE(unstable.dob_loop_stable);
  EXPECT_FALSE(unstable.verdict.certified);
  EXPECT_EQ(unstable.verdict.failing_condition, StabilityCondition::kLoopStable);
  EXPECT_EQ(unstable.verdict.alpha_max, 0.0);
  EXPECT_EQ(unstable.verdict.line,
            "NOT certified: the conventional FF/FB/DOB loop (GP path open) is not stable; no α ≥ 0 is certified");
  EXPECT_EQ(ToJson(unstable)["verdict"]["alpha_max"], 0.0);
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


// Every element of the diagram renamed "renamed_<name>" — in the elements, connections, roles, log and metrics.
nlohmann::json RenameEveryElement(nlohmann::json j) {
  const auto renamed = [](const std::string& s) { return s.empty() ? s : "renamed_" + s; };
  for (auto& e : j["elements"]) e["name"] = renamed(e["name"].get<std::string>());
  for (auto& c : j["connections"]) {
    c["startElement"] = renamed(c.value("startElement", ""));
    c["endElement"] = renamed(c.value("endElement", ""));
  }
  for (auto& [role, element] : j["roles"].items()) element = renamed(element.get<std::string>());
  for (auto& s : j["log"]) s = renamed(s.get<std::string>());
  for (auto& m : j["metrics"]) m["signal"] = renamed(m["signal"].get<std::string>());
  return j;
}

TEST(StabilityTest, FindsTheLoopByRoleNotByName) {
  const std::string dir = std::string(MB_SOURCE_DIR) + "/diagrams/paper";
  for (const char* file : {"/conventional.json", "/gp_loop.json"}) {
    const nlohmann::json j = ReadDiagramJson(dir + file);
    const PaperLoop original = PaperLoopFromDiagram(BuildDiagram(j, dir, file));
    const Diagram renamed = BuildDiagram(RenameEveryElement(j), dir, file);
    ASSERT_LT(renamed.FindBlock("pd_p"), 0);
    const nlohmann::json a = ToJson(AnalyseStability(original));
    const nlohmann::json b = ToJson(AnalyseStability(renamed));
    EXPECT_EQ(a["loop"], b["loop"]) << file;  // every number of the loop
    EXPECT_EQ(a["paper"], b["paper"]) << file;
    EXPECT_EQ(a["dob"], b["dob"]) << file;
  }
  // The paper's loop as conventional.json writes it: K_p, K_d and the derivative cut-off of its PD gains.
  const PaperLoop l = PaperLoopFromDiagram(LoadDiagram(dir + "/conventional.json"));
  EXPECT_TRUE(l.has_dob);
  EXPECT_TRUE(l.has_feedforward);
  EXPECT_DOUBLE_EQ(l.q_cutoff_hz, 30.0);
  const PaperLoop gp = PaperLoopFromDiagram(LoadDiagram(dir + "/gp_loop.json"));
  EXPECT_GT(gp.gp_weight, 0.0);
  EXPECT_EQ(gp.kp, l.kp);
}

// Issue 14: the gpr block's confidence weight reaches the analysis through the "gp" role, and K then uses
// the Lipschitz constants of g·d̂.
TEST(StabilityTest, ConfidenceWeightingOfTheGprBlockChangesTheLipschitzConstants) {
  const std::string dir = std::string(MB_SOURCE_DIR) + "/diagrams/paper";
  nlohmann::json j = ReadDiagramJson(dir + "/gp_loop.json");
  EXPECT_FALSE(PaperLoopFromDiagram(BuildDiagram(j, dir, "gp_loop.json")).gp_confidence_weighting);
  for (auto& e : j["elements"]) {
    if (e["name"] == "gpr") e["parameters"]["confidence_weighting"] = true;
  }
  const PaperLoop weighted = PaperLoopFromDiagram(BuildDiagram(j, dir, "gp_loop.json"));
  EXPECT_TRUE(weighted.gp_confidence_weighting);
  PaperLoop plain = weighted;
  plain.gp_confidence_weighting = false;
  const GprModel model = LoadGprModel(dir + "/models/gpr_ps_d2.json");
  StabilityOptions options;
  options.impulse_samples = 2000;
  options.bode_points = 4;
  const StabilityReport a = AnalyseStability(plain, &model, options);
  const StabilityReport b = AnalyseStability(weighted, &model, options);
  EXPECT_NE(a.dob.lipschitz_x, b.dob.lipschitz_x);
  EXPECT_EQ(b.dob.lipschitz_x, model.ConfidenceWeightedLipschitzConstants(options.weighted_lipschitz_grid).position);
  EXPECT_EQ(ToJson(b)["loop"]["gp_confidence_weighting"], true);
}

TEST(StabilityTest, AnalysesThePdLoopOfTheHilDiagram) {
  // diagrams/hil/pd_rigid_body.json: a discrete pd_controller (K_p 9300, K_d 69, T_f 0.5 ms, backward Euler, 1 ms)
  // around a rigid body in a subsystem; no DOB, no feedforward.
  const Diagram d = LoadDiagram(std::string(MB_SOURCE_DIR) + "/diagrams/hil/pd_rigid_body.json");
  const PaperLoop l = PaperLoopFromDiagram(d);
  EXPECT_FALSE(l.has_dob);
  EXPECT_FALSE(l.has_feedforward);
  EXPECT_DOUBLE_EQ(l.sample_time, 0.001);
  EXPECT_DOUBLE_EQ(l.mass, 0.2621);
  EXPECT_DOUBLE_EQ(l.damping, 3.0);
  EXPECT_DOUBLE_EQ(l.kp, 9300.0);
  EXPECT_DOUBLE_EQ(l.kd, 69.0);
  // a = T_f/(T_f + Ts) = 1/3 ⇒ the cut-off with exp(−2π f Ts) = 1/3.
  EXPECT_NEAR(std::exp(-2.0 * kPi * l.derivative_cutoff_hz * l.sample_time), 1.0 / 3.0, 1e-12);
  const StabilityReport r = AnalyseStability(d);
  EXPECT_TRUE(r.inner_loop_stable);
  EXPECT_TRUE(r.dob_loop_stable);
  EXPECT_EQ(r.paper.gamma_q, 0.0);
  EXPECT_EQ(r.dob.gamma_d_to_x, r.paper.gamma_d_to_x);  // without a DOB both decompositions close the same loop
  // ‖C_FB‖₁ = K_p + 2 K_d (1 − a)/Ts = 9300 + 2·69/(T_f + Ts).
  EXPECT_NEAR(r.paper.gamma_x_to_u, 9300.0 + 2.0 * 69.0 / 0.0015, 1e-6);
  for (const BodePoint& b : r.bode) {
    EXPECT_EQ(std::abs(b.d_to_dhat_discrete), 0.0);
    EXPECT_GE(r.paper.gamma_d_to_x, std::abs(b.d_to_x_discrete) * (1.0 - 1e-9));
  }
}

// r → e = r − x → PD → rigid body: the smallest loop the analysis reads.
nlohmann::json PdLoop(const nlohmann::json& pd) {
  nlohmann::json j = {
      {"schemaVersion", "1.0"},
      {"elements",
       {{{"name", "r"}, {"type", "constant"}, {"parameters", {{"value", 0.001}}}},
        {{"name", "e"}, {"type", "sum"}, {"parameters", {{"signs", "+-"}}}},
        pd,
        {{"name", "body"}, {"type", "rigid_body"}, {"parameters", {{"mass", 1.0}, {"damping", 1.0}}}}}},
      {"connections",
       {{{"startElement", "r"}, {"startConnector", "y"}, {"endElement", "e"}, {"endConnector", "u1"}},
        {{"startElement", "body"}, {"startConnector", "x"}, {"endElement", "e"}, {"endConnector", "u2"}},
        {{"startElement", "e"}, {"startConnector", "y"}, {"endElement", pd["name"]}, {"endConnector", "e"}},
        {{"startElement", pd["name"]}, {"startConnector", "u"}, {"endElement", "body"}, {"endConnector", "f"}}}}};
  return j;
}

std::string LoopError(const nlohmann::json& j) {
  try {
    PaperLoopFromDiagram(BuildDiagram(j, ".", "loop.json"));
  } catch (const std::invalid_argument& e) {
    return e.what();
  }
  return "no error";
}

TEST(StabilityTest, LoopErrorsSayWhatIsMissingAndHowToName) {
  const nlohmann::json pd = {{"name", "c"}, {"type", "pd_controller"}, {"sampleTime", {0.001, 0.0}},
                             {"parameters", {{"kp", 100.0}, {"kd", 5.0}, {"derivative_filter", 0.001}}}};
  EXPECT_EQ(LoopError(PdLoop(pd)), "no error");
  EXPECT_DOUBLE_EQ(PaperLoopFromDiagram(BuildDiagram(PdLoop(pd), ".", "loop.json")).mass, 1.0);

  nlohmann::json continuous = pd;
  continuous.erase("sampleTime");
  EXPECT_THAT(LoopError(PdLoop(continuous)),
              ::testing::HasSubstr("the PD 'c' is continuous; the analysis is of the sampled loop: give it a "
                                   "\"sampleTime\": [Ts, 0]"));
  nlohmann::json no_filter = pd;
  no_filter["parameters"]["derivative_filter"] = 0.0;
  EXPECT_THAT(LoopError(PdLoop(no_filter)), ::testing::HasSubstr("has derivative pole a = 0"));

  nlohmann::json two_plants = PdLoop(pd);
  two_plants["elements"].push_back({{"name", "other"}, {"type", "rigid_body"}});
  two_plants["connections"].push_back(
      {{"startElement", "c"}, {"startConnector", "u"}, {"endElement", "other"}, {"endConnector", "f"}});
  EXPECT_THAT(LoopError(two_plants),
              ::testing::HasSubstr("the diagram has 2 elements that could be the plant (body, other): name the one "
                                   "in the loop with \"roles\": {\"plant\": \"body\"}"));
  two_plants["roles"] = {{"plant", "other"}};
  EXPECT_EQ(LoopError(two_plants), "no error");
  two_plants["roles"] = {{"plant", "e"}};
  EXPECT_THAT(LoopError(two_plants),
              ::testing::HasSubstr("roles/plant names 'e', a sum; the plant must be a linear_motor or rigid_body"));

  nlohmann::json gains = PdLoop({{"name", "c"}, {"type", "gain"}, {"parameters", {{"gain", 100.0}}}});
  gains["connections"][2]["endConnector"] = "u";
  gains["connections"][3]["startConnector"] = "y";
  EXPECT_THAT(LoopError(gains), ::testing::HasSubstr("the diagram has no pd_controller; for a PD built of blocks name "
                                                     "its parts in \"roles\""));
}

}  // namespace
}  // namespace mb

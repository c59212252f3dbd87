// Static and linear blocks: product, sign, abs, lookup_table_1d and _2d, bump, discrete_derivative, saturation, quantizer, zero_order_hold, logger, transfer_function,
// discrete_transfer_function, state_space — against closed forms, difference equations, sample-time
// boundaries, feedthrough (algebraic loops) and their error messages.

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

json Constant(const std::string& name, const json& value) { return Element(name, "constant", {{"value", value}}); }

// Runs a one-step diagram and returns the named signal's first logged sample.
double Evaluate(const json& elements, const json& connections, const std::string& signal) {
  const auto r = Simulator(Build(MakeDiagram(elements, connections, {signal}, 1.0, 1.0))).Run();
  return r.log.Column(signal).front();
}

TEST(ProductTest, MultipliesAndDividesElementWise) {
  const json elements = {Constant("a", json::array({2.0, 3.0})), Constant("b", json::array({4.0, -5.0})),
                         Constant("c", json::array({8.0, 2.0})),
                         Element("p", "product", {{"ops", "*/*"}, {"width", 2}})};
  const json connections = {Connect("a.y", "p.u1"), Connect("b.y", "p.u2"), Connect("c.y", "p.u3")};
  const auto r = Simulator(Build(MakeDiagram(elements, connections, {"p.y"}, 1.0, 1.0))).Run();
  EXPECT_DOUBLE_EQ(r.log.Column("p.y[0]").front(), 2.0 / 4.0 * 8.0);
  EXPECT_DOUBLE_EQ(r.log.Column("p.y[1]").front(), 3.0 / -5.0 * 2.0);
  EXPECT_DOUBLE_EQ(Evaluate({Constant("a", 4.0), Element("p", "product", {{"ops", "/"}})}, {Connect("a.y", "p.u1")},
                            "p.y"),
                   0.25);
}

TEST(ProductTest, RejectsUnknownOperators) {
  EXPECT_THAT(BuildError(MakeDiagram({Element("p", "product", {{"ops", "*+"}})}, json::array(), json::array(), 1, 1)),
              HasSubstr("element 'p' (product): ops may contain only '*' (multiply) and '/' (divide), got \"*+\""));
  EXPECT_THAT(BuildError(MakeDiagram({Element("p", "product", {{"ops", ""}})}, json::array(), json::array(), 1, 1)),
              HasSubstr("ops must list at least one"));
}

TEST(SignTest, IsSimulinksSignWithAnOptionalDeadBand) {
  for (const auto& [u, y] : std::vector<std::pair<double, double>>{{-3.0, -1.0}, {0.0, 0.0}, {1e-9, 1.0}, {2.0, 1.0}}) {
    EXPECT_EQ(Evaluate({Constant("u", u), Element("s", "sign", json::object())}, {Connect("u.y", "s.u")}, "s.y"), y)
        << "u = " << u;
  }
  for (const auto& [u, y] : std::vector<std::pair<double, double>>{{-0.3, -1.0}, {-0.1, 0.0}, {0.2, 0.0}, {0.21, 1.0}}) {
    EXPECT_EQ(Evaluate({Constant("u", u), Element("s", "sign", {{"dead_band", 0.2}})}, {Connect("u.y", "s.u")}, "s.y"),
              y)
        << "u = " << u;
  }
  EXPECT_THAT(BuildError(MakeDiagram({Element("s", "sign", {{"dead_band", -1.0}})}, json::array(), json::array(), 1, 1)),
              HasSubstr("dead_band"));
  // Regularised: tanh(u/u_r), smooth through 0 (a friction's direction of slip as the regularised Coulomb law has it).
  for (const double u : {-0.003, 0.0, 0.0005, 0.01}) {
    EXPECT_DOUBLE_EQ(Evaluate({Constant("u", u), Element("s", "sign", {{"regularization_velocity", 0.001}})},
                              {Connect("u.y", "s.u")}, "s.y"),
                     std::tanh(u / 0.001))
        << "u = " << u;
  }
  EXPECT_THAT(BuildError(MakeDiagram({Element("s", "sign", {{"dead_band", 0.1}, {"regularization_velocity", 0.1}})},
                                     json::array(), json::array(), 1, 1)),
              HasSubstr("give a dead_band or a regularization_velocity, not both"));
}

TEST(SwitchTest, PassesTheFirstInputWhereTheControlPassesSimulinksCriteria) {
  const auto at = [](double control, const json& parameters) {
    return Evaluate({Constant("a", 7.0), Constant("c", control), Constant("b", -2.0),
                     Element("s", "switch", parameters)},
                    {Connect("a.y", "s.u1"), Connect("c.y", "s.u2"), Connect("b.y", "s.u3")}, "s.y");
  };
  EXPECT_EQ(at(0.5, {{"threshold", 0.5}}), 7.0);  // the default: u2 >= threshold
  EXPECT_EQ(at(0.4999, {{"threshold", 0.5}}), -2.0);
  EXPECT_EQ(at(0.5, {{"criteria", "u2 > threshold"}, {"threshold", 0.5}}), -2.0);
  EXPECT_EQ(at(0.5001, {{"criteria", "u2 > threshold"}, {"threshold", 0.5}}), 7.0);
  EXPECT_EQ(at(0.0, {{"criteria", "u2 ~= 0"}, {"threshold", 3.0}}), -2.0);  // the threshold plays no part
  EXPECT_EQ(at(-1e-12, {{"criteria", "u2 ~= 0"}}), 7.0);
  EXPECT_THAT(BuildError(MakeDiagram({Element("s", "switch", {{"criteria", "u2 < threshold"}})}, json::array(),
                                     json::array(), 1, 1)),
              HasSubstr("criteria must be \"u2 >= threshold\", \"u2 > threshold\" or \"u2 ~= 0\""));
}

TEST(LookupTable1dTest, InterpolatesLinearlyAndClipsOrExtrapolatesAtTheEnds) {
  const json table = {{"breakpoints", {0.0, 1.0, 3.0}}, {"table", {10.0, 20.0, 0.0}}};
  const auto at = [&](double u, const json& extra) {
    json p = table;
    p.update(extra);
    return Evaluate({Constant("u", u), Element("t", "lookup_table_1d", p)}, {Connect("u.y", "t.u")}, "t.y");
  };
  EXPECT_DOUBLE_EQ(at(0.25, json::object()), 12.5);  // inside: 10 + 0.25·(20 − 10)
  EXPECT_DOUBLE_EQ(at(1.0, json::object()), 20.0);   // on a breakpoint
  EXPECT_DOUBLE_EQ(at(2.5, json::object()), 5.0);    // 20 + 0.75·(0 − 20)
  EXPECT_DOUBLE_EQ(at(-1.0, json::object()), 10.0);  // clipped (Simulink's default)
  EXPECT_DOUBLE_EQ(at(7.0, json::object()), 0.0);
  EXPECT_DOUBLE_EQ(at(-1.0, {{"extrapolation", "linear"}}), 0.0);    // 10 − 1·10
  EXPECT_DOUBLE_EQ(at(4.0, {{"extrapolation", "linear"}}), -10.0);   // 0 − 1·10
}

// The Tukey window over one stretch: the gain on the flat top |z| ≤ f, cos² flanks to 0 at |z| = 1, nothing beyond;
// f = 0 is the diagnosis' cos²(π(x − c)/(2w)). A half-width of 0 or a flat top of the whole stretch is refused on load.
TEST(BumpTest, IsAFlatTopWithCosineSquaredFlanks) {
  const auto at = [](double u, double flat) {
    const json p = {{"center", 0.1}, {"half_width", 0.02}, {"flat", flat}, {"gain", 40.0}};
    return Evaluate({Constant("u", u), Element("b", "bump", p)}, {Connect("u.y", "b.u")}, "b.y");
  };
  EXPECT_DOUBLE_EQ(at(0.1, 0.0), 40.0);
  EXPECT_NEAR(at(0.11, 0.0), 20.0, 1e-9);                          // cos²(π/4) at half the half-width
  EXPECT_NEAR(at(0.09, 0.0), 20.0, 1e-9);                          // symmetric
  EXPECT_DOUBLE_EQ(at(0.125, 0.0), 0.0);                           // beyond c + w
  EXPECT_DOUBLE_EQ(at(0.109, 0.5), 40.0);                          // on the flat top, |z| = 0.45 ≤ 0.5
  EXPECT_NEAR(at(0.115, 0.5), 20.0, 1e-9);                         // the flank's middle, |z| = 0.75
  EXPECT_NEAR(at(0.085, 0.5), 20.0, 1e-9);
  const auto error = [](const json& p) {
    return BuildError(MakeDiagram({Element("b", "bump", p)}, json::array(), json::array(), 1, 1));
  };
  EXPECT_THAT(error({{"center", 0.1}, {"half_width", 0.0}}), HasSubstr("half_width"));
  EXPECT_THAT(error({{"center", 0.1}, {"half_width", 0.02}, {"flat", 1.0}}), HasSubstr("flat"));
  EXPECT_THAT(error({{"half_width", 0.02}}), HasSubstr("center"));
}

TEST(AbsTest, IsSimulinksAbs) {
  for (const double u : {-2.5, 0.0, 3.0}) {
    EXPECT_EQ(Evaluate({Constant("u", u), Element("a", "abs", json::object())}, {Connect("u.y", "a.u")}, "a.y"),
              std::abs(u));
  }
}

TEST(SqrtTest, IsSimulinksSqrtHeldAtZeroBelowZero) {
  const auto at = [](double u) {
    return Evaluate({Constant("u", u), Element("r", "sqrt", json::object())}, {Connect("u.y", "r.u")}, "r.y");
  };
  EXPECT_DOUBLE_EQ(at(6.25), 2.5);
  EXPECT_EQ(at(0.0), 0.0);
  EXPECT_EQ(at(-1e-17), 0.0);  // a hair below 0 by rounding: 0, not NaN
  EXPECT_EQ(at(-4.0), 0.0);
}

// Simulink's 2-D Lookup Table: bilinear inside, the edge values beyond (clip) or the edge cells extended (linear).
TEST(LookupTable2dTest, InterpolatesBilinearlyAndClipsOrExtrapolatesAtTheEdges) {
  // y = 1 + 2 u1 + 3 u2 + u1·u2 at the grid points: bilinear interpolation reproduces it exactly inside.
  const std::vector<double> rows = {0.0, 1.0, 3.0}, columns = {-1.0, 2.0};
  json table = json::array();
  for (double r : rows) {
    for (double c : columns) table.push_back(1.0 + 2.0 * r + 3.0 * c + r * c);
  }
  const auto at = [&](double u1, double u2, const char* extrapolation) {
    return Evaluate({Constant("a", u1), Constant("b", u2),
                     Element("t", "lookup_table_2d",
                             {{"row_breakpoints", rows}, {"column_breakpoints", columns}, {"table", table},
                              {"extrapolation", extrapolation}})},
                    {Connect("a.y", "t.u1"), Connect("b.y", "t.u2")}, "t.y");
  };
  const auto f = [](double u1, double u2) { return 1.0 + 2.0 * u1 + 3.0 * u2 + u1 * u2; };
  for (const auto& [u1, u2] : std::vector<std::pair<double, double>>{{0.5, 0.0}, {2.0, 1.5}, {3.0, -1.0}, {1.0, 2.0}}) {
    EXPECT_NEAR(at(u1, u2, "clip"), f(u1, u2), 1e-12) << u1 << ", " << u2;
  }
  EXPECT_NEAR(at(5.0, 4.0, "clip"), f(3.0, 2.0), 1e-12);      // beyond both ends: the corner holds
  EXPECT_NEAR(at(-1.0, 0.5, "clip"), f(0.0, 0.5), 1e-12);     // beyond the first row: the edge holds
  EXPECT_NEAR(at(-1.0, 0.5, "linear"), f(-1.0, 0.5), 1e-12);  // the first cell extended: bilinear stays exact
  const auto error = [](const json& parameters) {
    return BuildError(MakeDiagram({Element("t", "lookup_table_2d", parameters)}, json::array(), json::array(), 1, 1));
  };
  EXPECT_THAT(error({{"row_breakpoints", {0.0, 1.0}}, {"column_breakpoints", {0.0, 1.0}}, {"table", {1.0, 2.0, 3.0}}}),
              HasSubstr("table has 3 entries for 2 row × 2 column breakpoints; give 4 values, row by row"));
  EXPECT_THAT(error({{"row_breakpoints", {0.0, 0.0}}, {"column_breakpoints", {0.0, 1.0}}, {"table", {1, 2, 3, 4}}}),
              HasSubstr("row_breakpoints[1] = 0 must be finite and above row_breakpoints[0] = 0"));
  EXPECT_THAT(error({{"row_breakpoints", {0.0, 1.0}}, {"column_breakpoints", {0.0}}, {"table", {1.0, 2.0}}}),
              HasSubstr("column_breakpoints has 1 entries; give at least 2"));
}

TEST(LookupTable1dTest, RefusesTablesItCannotInterpolate) {
  const auto error = [](const json& p) {
    return BuildError(MakeDiagram({Element("t", "lookup_table_1d", p)}, json::array(), json::array(), 1, 1));
  };
  EXPECT_THAT(error({{"breakpoints", {0.0, 1.0, 1.0}}, {"table", {1.0, 2.0, 3.0}}}),
              HasSubstr("breakpoints must increase strictly"));
  EXPECT_THAT(error({{"breakpoints", {0.0, 1.0}}, {"table", {1.0, 2.0, 3.0}}}),
              HasSubstr("table has 3 entries for 2 breakpoints"));
  EXPECT_THAT(error({{"breakpoints", {0.0}}, {"table", {1.0}}}), HasSubstr("give at least 2"));
  EXPECT_THAT(error({{"breakpoints", {0.0, 1.0}}, {"table", {1.0, 2.0}}, {"extrapolation", "nearest"}}),
              HasSubstr("write \"clip\""));
}

TEST(SaturationTest, ClampsToTheLimits) {
  for (const auto& [u, y] : std::vector<std::pair<double, double>>{{-3.0, -0.5}, {0.2, 0.2}, {2.0, 1.5}, {1.5, 1.5}}) {
    EXPECT_EQ(Evaluate({Constant("u", u), Element("s", "saturation", {{"lower", -0.5}, {"upper", 1.5}})},
                       {Connect("u.y", "s.u")}, "s.y"),
              y)
        << "u = " << u;
  }
  EXPECT_THAT(
      BuildError(MakeDiagram({Element("s", "saturation", {{"lower", 2.0}, {"upper", 1.0}})}, json::array(),
                             json::array(), 1, 1)),
      HasSubstr("lower limit 2.000000 is above upper limit 1.000000; swap them"));
}

TEST(QuantizerTest, RoundsToTheIntervalHalfAwayFromZero) {
  const double q = 0.25;
  for (const auto& [u, y] : std::vector<std::pair<double, double>>{
           {0.1, 0.0}, {0.13, 0.25}, {0.125, 0.25}, {-0.125, -0.25}, {1.01, 1.0}, {-0.9, -1.0}}) {
    EXPECT_DOUBLE_EQ(
        Evaluate({Constant("u", u), Element("q", "quantizer", {{"interval", q}})}, {Connect("u.y", "q.u")}, "q.y"), y)
        << "u = " << u;
  }
  EXPECT_THAT(BuildError(MakeDiagram({Element("q", "quantizer", {{"interval", 0.0}})}, json::array(), json::array(),
                                     1, 1)),
              HasSubstr("interval must be > 0"));
}

TEST(ZeroOrderHoldTest, SamplesAtHitsAndHoldsWithOffset) {
  // u = t (integrator of 1), held every 0.1 s from offset 0.05; logged every 0.025 s.
  const json j = MakeDiagram({Constant("one", 1.0), Element("t", "integrator"),
                              Element("h", "zero_order_hold", json::object(), {0.1, 0.05})},
                             {Connect("one.y", "t.u"), Connect("t.y", "h.u")}, {"h.y"}, 0.4, 0.025);
  const auto r = Simulator(Build(j)).Run();
  const auto& y = r.log.Column("h.y");
  for (std::size_t i = 0; i < y.size(); ++i) {
    const double t = r.log.time[i];
    const double expected = t < 0.05 - 1e-12 ? 0.0 : 0.05 + 0.1 * std::floor((t - 0.05) / 0.1 + 1e-9);
    EXPECT_NEAR(y[i], expected, 1e-12) << "t = " << t;
  }
}

TEST(ZeroOrderHoldTest, RequiresASampleTime) {
  EXPECT_THAT(BuildError(MakeDiagram({Element("h", "zero_order_hold")}, json::array(), json::array(), 1, 1)),
              HasSubstr("element 'h' (zero_order_hold) is discrete: add \"sampleTime\""));
}

TEST(LoggerTest, PassesItsInputToALoggableOutput) {
  const auto r = Simulator(Build(MakeDiagram({Element("s", "sine"), Element("scope", "logger")},
                                             {Connect("s.y", "scope.u")}, {"scope.y"}, 0.5, 0.1)))
                     .Run();
  for (std::size_t i = 0; i < r.log.time.size(); ++i) {
    EXPECT_NEAR(r.log.Column("scope.y")[i], std::sin(2.0 * std::numbers::pi * r.log.time[i]), 1e-12);
  }
}

// Step response of a continuous transfer function driven by a unit constant (a step at t = 0).
SignalLog TfStep(const json& numerator, const json& denominator, double stop = 3.0) {
  const json j = MakeDiagram({Constant("one", 1.0), Element("H", "transfer_function",
                                                            {{"numerator", numerator}, {"denominator", denominator}})},
                             {Connect("one.y", "H.u")}, {"H.y"}, stop, 0.05,
                             {{"type", "cvode"}, {"rtol", 1e-10}, {"atol", 1e-12}});
  return Simulator(Build(j)).Run().log;
}

TEST(TransferFunctionTest, FirstOrderLagStepResponse) {
  const auto log = TfStep(json::array({2.0}), json::array({0.5, 1.0}));  // 2/(0.5 s + 1), τ = 0.5 s
  for (std::size_t i = 0; i < log.time.size(); ++i) {
    EXPECT_NEAR(log.Column("H.y")[i], 2.0 * (1.0 - std::exp(-log.time[i] / 0.5)), 1e-8);
  }
}

TEST(TransferFunctionTest, SecondOrderStepResponse) {
  const double wn = 4.0, zeta = 0.3, wd = wn * std::sqrt(1.0 - zeta * zeta);
  const auto log = TfStep(json::array({0.0, 0.0, 2.0 * wn * wn}), json::array({2.0, 4.0 * zeta * wn, 2.0 * wn * wn}));
  for (std::size_t i = 0; i < log.time.size(); ++i) {
    const double t = log.time[i];
    const double y = 1.0 - std::exp(-zeta * wn * t) * (std::cos(wd * t) + zeta * wn / wd * std::sin(wd * t));
    EXPECT_NEAR(log.Column("H.y")[i], y, 1e-7) << "t = " << t;
  }
}

TEST(TransferFunctionTest, BiproperFeedsThrough) {
  const auto log = TfStep(json::array({1.0, 2.0}), json::array({1.0, 1.0}));  // (s + 2)/(s + 1) → 2 − e^{−t}
  EXPECT_NEAR(log.Column("H.y").front(), 1.0, 1e-12);                         // jumps to b0 at t = 0
  for (std::size_t i = 0; i < log.time.size(); ++i) {
    EXPECT_NEAR(log.Column("H.y")[i], 2.0 - std::exp(-log.time[i]), 1e-8);
  }
}

TEST(TransferFunctionTest, FeedthroughOnlyWhenBiproper) {
  auto loop = [](const json& numerator) {
    return MakeDiagram({Element("H", "transfer_function", {{"numerator", numerator}, {"denominator", {1.0, 1.0}}}),
                        Element("k", "gain", {{"gain", -1.0}})},
                       {Connect("H.y", "k.u"), Connect("k.y", "H.u")}, json::array(), 1.0, 0.1);
  };
  EXPECT_THAT(BuildError(loop({1.0, 0.0})), HasSubstr("algebraic loop"));
  EXPECT_EQ(BuildError(loop({1.0})), "");
  EXPECT_EQ(BuildError(loop({0.0, 1.0})), "");  // leading zeros dropped: strictly proper
}

TEST(TransferFunctionTest, RejectsImproperAndZeroLeadingDenominator) {
  auto tf = [](const json& numerator, const json& denominator) {
    return BuildError(MakeDiagram(
        {Element("H", "transfer_function", {{"numerator", numerator}, {"denominator", denominator}})}, json::array(),
        json::array(), 1.0, 0.1));
  };
  EXPECT_THAT(tf({1.0, 0.0, 0.0}, {1.0, 1.0}),
              HasSubstr("improper transfer function: numerator order 2 > denominator order 1"));
  EXPECT_THAT(tf({1.0}, {0.0, 1.0}), HasSubstr("denominator must start with a non-zero coefficient"));
}

// Reference: the difference equation Σ a_i y[k−i] = Σ b_i u[k−i] with coefficients in descending powers of z,
// numerator padded to the denominator's length.
std::vector<double> DifferenceEquation(std::vector<double> b, const std::vector<double>& a,
                                       const std::vector<double>& u) {
  b.insert(b.begin(), a.size() - b.size(), 0.0);
  std::vector<double> y(u.size(), 0.0);
  for (std::size_t k = 0; k < u.size(); ++k) {
    double acc = 0.0;
    for (std::size_t i = 0; i < a.size() && i <= k; ++i) acc += b[i] * u[k - i];
    for (std::size_t i = 1; i < a.size() && i <= k; ++i) acc -= a[i] * y[k - i];
    y[k] = acc / a[0];
  }
  return y;
}

TEST(DiscreteTransferFunctionTest, MatchesDifferenceEquation) {
  const double Ts = 0.01;
  const std::vector<std::pair<std::vector<double>, std::vector<double>>> cases = {
      {{1.0}, {1.0, -0.5}},                  // 1/(z − 0.5): one-sample delay
      {{1.0, 0.2}, {1.0, -0.5}},             // biproper
      {{0.5, 0.3, 0.1}, {2.0, -1.8, 0.4}},   // second order, a0 ≠ 1
      {{0.0, 1.0, 0.0}, {1.0, 0.1, -0.2}}};  // leading zero in the numerator
  for (const auto& [num, den] : cases) {
    const json j = MakeDiagram({Element("u", "sine", {{"frequency_hz", 3.0}}, {Ts, 0.0}),
                                Element("H", "discrete_transfer_function", {{"numerator", num}, {"denominator", den}},
                                        {Ts, 0.0})},
                               {Connect("u.y", "H.u")}, {"u.y", "H.y"}, 0.3, Ts);
    const auto r = Simulator(Build(j)).Run();
    const auto expected = DifferenceEquation(num, den, r.log.Column("u.y"));
    ASSERT_EQ(r.log.Column("H.y").size(), expected.size());
    for (std::size_t k = 0; k < expected.size(); ++k) {
      EXPECT_NEAR(r.log.Column("H.y")[k], expected[k], 1e-12) << "k = " << k << ", den[1] = " << den[1];
    }
  }
}

TEST(DiscreteTransferFunctionTest, ErrorsForImproperAndMissingSampleTime) {
  EXPECT_THAT(BuildError(MakeDiagram({Element("H", "discrete_transfer_function",
                                              {{"numerator", {1.0, 0.0}}, {"denominator", {1.0}}}, 0.1)},
                                     json::array(), json::array(), 1.0, 0.1)),
              HasSubstr("improper (non-causal) transfer function: numerator order 1 > denominator order 0"));
  EXPECT_THAT(BuildError(MakeDiagram({Element("H", "discrete_transfer_function")}, json::array(), json::array(), 1.0,
                                     0.1)),
              HasSubstr("is discrete: add \"sampleTime\""));
}

// Simulink's Discrete Derivative, K·(u[k] − u[k−1])/Ts, except that the first output is 0 (u[−1] = u[0]): a signal
// that starts at 22 (a temperature) gives no kick.
TEST(DiscreteDerivativeTest, IsTheBackwardDifferenceWithoutAFirstSampleKick) {
  const double Ts = 0.01;
  const json j = MakeDiagram({Element("u", "sine", {{"frequency_hz", 3.0}, {"amplitude", 2.0}, {"bias", 22.0}}, {Ts, 0.0}),
                              Element("d", "discrete_derivative", {{"gain", 0.5}}, {Ts, 0.0})},
                             {Connect("u.y", "d.u")}, {"u.y", "d.y"}, 0.3, Ts);
  const auto r = Simulator(Build(j)).Run();
  const auto& u = r.log.Column("u.y");
  const auto& y = r.log.Column("d.y");
  ASSERT_GT(y.size(), 20U);
  EXPECT_EQ(y[0], 0.0);
  for (std::size_t k = 1; k < y.size(); ++k) EXPECT_NEAR(y[k], 0.5 * (u[k] - u[k - 1]) / Ts, 1e-9) << "k = " << k;
  // The rate of 22 + 2 sin(2π·3t) is 12π cos(2π·3t): the difference follows it within its O(Ts) error.
  EXPECT_NEAR(y[10], 0.5 * 12.0 * std::numbers::pi * std::cos(2.0 * std::numbers::pi * 3.0 * (r.log.time[10] - 0.5 * Ts)),
              0.05);
  EXPECT_THAT(BuildError(MakeDiagram({Element("d", "discrete_derivative")}, json::array(), json::array(), 1.0, 0.1)),
              HasSubstr("is discrete: add \"sampleTime\""));
}

TEST(StateSpaceTest, OscillatorFromInitialState) {
  const double w = 3.0;
  const json j = MakeDiagram({Constant("zero", 0.0),
                              Element("G", "state_space",
                                      {{"A", {0.0, 1.0, -w * w, 0.0}},
                                       {"B", {0.0, 1.0}},
                                       {"C", {1.0, 0.0, 0.0, 1.0}},
                                       {"x0", {1.0, 0.0}}})},
                             {Connect("zero.y", "G.u")}, {"G.y"}, 2.0, 0.05,
                             {{"type", "cvode"}, {"rtol", 1e-10}, {"atol", 1e-12}});
  const auto r = Simulator(Build(j)).Run();
  for (std::size_t i = 0; i < r.log.time.size(); ++i) {
    const double t = r.log.time[i];
    EXPECT_NEAR(r.log.Column("G.y[0]")[i], std::cos(w * t), 1e-7);
    EXPECT_NEAR(r.log.Column("G.y[1]")[i], -w * std::sin(w * t), 1e-6);
  }
}

TEST(StateSpaceTest, TwoInputsWithFeedthrough) {
  // ẋ = −x + u1, y = x + 2 u1 − u2 with u = (1, 3): y(t) = 1 − e^{−t} + 2 − 3.
  const json j = MakeDiagram({Constant("u", json::array({1.0, 3.0})),
                              Element("G", "state_space",
                                      {{"A", -1.0}, {"B", {1.0, 0.0}}, {"C", 1.0}, {"D", {2.0, -1.0}}})},
                             {Connect("u.y", "G.u")}, {"G.y"}, 1.0, 0.1,
                             {{"type", "cvode"}, {"rtol", 1e-10}, {"atol", 1e-12}});
  const auto r = Simulator(Build(j)).Run();
  for (std::size_t i = 0; i < r.log.time.size(); ++i) {
    EXPECT_NEAR(r.log.Column("G.y")[i], -std::exp(-r.log.time[i]), 1e-8);
  }
}

TEST(StateSpaceTest, ErrorsNameTheMatrix) {
  auto ss = [](const json& parameters) {
    return BuildError(MakeDiagram({Element("G", "state_space", parameters)}, json::array(), json::array(), 1, 0.1));
  };
  EXPECT_THAT(ss({{"A", {1.0, 2.0, 3.0}}, {"B", 1.0}, {"C", 1.0}}), HasSubstr("A has 3 entries; it must be a square"));
  EXPECT_THAT(ss({{"A", {1.0, 0.0, 0.0, 1.0}}, {"B", {1.0, 2.0, 3.0}}, {"C", {1.0, 0.0}}}),
              HasSubstr("B has 3 entries; it must be n×m = 2×m"));
  EXPECT_THAT(ss({{"A", {1.0, 0.0, 0.0, 1.0}}, {"B", {1.0, 2.0}}, {"C", {1.0}}}),
              HasSubstr("C has 1 entries; it must be p×n = p×2"));
  EXPECT_THAT(ss({{"A", 1.0}, {"B", 1.0}, {"C", 1.0}, {"D", {1.0, 2.0}}}), HasSubstr("D has 2 entries; it must be p×m = 1×1"));
  EXPECT_THAT(ss({{"A", 1.0}, {"B", 1.0}}), HasSubstr("missing required parameter 'C'"));
}

}  // namespace
}  // namespace mb

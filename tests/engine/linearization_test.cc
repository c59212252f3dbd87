// engine/linearization.h: the linearisation of diagrams whose linear model is known in closed form (a mass–spring–
// damper assembled from a rigid body, a gain and a sum; a second-order transfer function), the treatment of discrete
// blocks (held, as linmod), the operating point, and Bode's unwrapped phase.

#include "engine/linearization.h"

#include <cmath>
#include <complex>
#include <numbers>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "tests/engine/test_util.h"

namespace mb {
namespace {

using ::testing::HasSubstr;
using testing::Build;

nlohmann::json Link(const std::string& from_element, const std::string& from, const std::string& to_element,
                    const std::string& to) {
  nlohmann::json j = {{"startConnector", from}, {"endConnector", to}};
  if (!from_element.empty()) j["startElement"] = from_element;
  if (!to_element.empty()) j["endElement"] = to_element;
  return j;
}

// M ẍ = u − k x − b ẋ: a rigid body (mass M, damping b) whose force is u plus a spring gain −k on its position.
nlohmann::json MassSpringDamper(double mass, double damping, double stiffness) {
  return {{"schemaVersion", "1.0"},
          {"name", "msd"},
          {"defaultExperiment", {{"startTime", 0.0}, {"stopTime", 1.0}, {"stepSize", 0.001}}},
          {"connectors",
           {{{"name", "force"}, {"kind", "input"}, {"unit", "N"}},
            {{"name", "position"}, {"kind", "output"}, {"unit", "m"}},
            {{"name", "velocity"}, {"kind", "output"}, {"unit", "m/s"}}}},
          {"elements",
           {{{"name", "body"}, {"type", "rigid_body"}, {"parameters", {{"mass", mass}, {"damping", damping}}}},
            {{"name", "spring"}, {"type", "gain"}, {"parameters", {{"gain", -stiffness}}}},
            {{"name", "total"}, {"type", "sum"}, {"parameters", {{"signs", "++"}}}}}},
          {"connections",
           {Link("", "force", "total", "u1"), Link("spring", "y", "total", "u2"), Link("total", "y", "body", "f"),
            Link("body", "x", "spring", "u"), Link("body", "x", "", "position"), Link("body", "v", "", "velocity")}}};
}

TEST(Linearize, AMassSpringDamperGivesItsStateSpaceModel) {
  const double m = 2.0, b = 3.0, k = 5.0;
  const Diagram d = Build(MassSpringDamper(m, b, k));
  const LinearModel model = Linearize(d);
  ASSERT_EQ(model.a.rows(), 2);
  Eigen::Matrix2d a;
  a << 0.0, 1.0, -k / m, -b / m;
  EXPECT_LT((model.a - a).cwiseAbs().maxCoeff(), 1e-8) << model.a;
  EXPECT_LT((model.b - Eigen::Vector2d(0.0, 1.0 / m)).cwiseAbs().maxCoeff(), 1e-8) << model.b;
  EXPECT_LT((model.c - Eigen::Matrix2d::Identity()).cwiseAbs().maxCoeff(), 1e-8) << model.c;
  EXPECT_LT(model.d.cwiseAbs().maxCoeff(), 1e-8);
  EXPECT_EQ(model.input_names, std::vector<std::string>{"force"});
  EXPECT_EQ(model.output_units, (std::vector<std::string>{"m", "m/s"}));
  EXPECT_THAT(model.state_names.front(), HasSubstr("'body'"));

  // The position's response 1/(M s² + b s + k), against its closed form.
  const Eigen::VectorXd f = LogSpacedFrequencies(0.01, 100.0, 9);
  const Eigen::VectorXcd h = model.FrequencyResponse(0, 0, f);
  for (Eigen::Index i = 0; i < f.size(); ++i) {
    const std::complex<double> s(0.0, 2.0 * std::numbers::pi * f(i));
    const std::complex<double> expected = 1.0 / (m * s * s + b * s + k);
    EXPECT_LT(std::abs(h(i) - expected), 1e-7 * std::abs(expected)) << f(i) << " Hz";
  }
}

TEST(Linearize, ATransferFunctionsResponseIsItsOwn) {
  const double wn = 2.0 * std::numbers::pi * 5.0, zeta = 0.05;
  const nlohmann::json j = {
      {"schemaVersion", "1.0"},
      {"connectors", {{{"name", "u"}, {"kind", "input"}}, {{"name", "y"}, {"kind", "output"}}}},
      {"elements",
       {{{"name", "mode"},
         {"type", "transfer_function"},
         {"parameters", {{"numerator", {wn * wn}}, {"denominator", {1.0, 2.0 * zeta * wn, wn * wn}}}}}}},
      {"connections", {Link("", "u", "mode", "u"), Link("mode", "y", "", "y")}}};
  const LinearModel model = Linearize(Build(j));
  const Eigen::VectorXd f = LogSpacedFrequencies(0.1, 50.0, 25);
  const Eigen::VectorXcd h = model.FrequencyResponse(0, 0, f);
  for (Eigen::Index i = 0; i < f.size(); ++i) {
    const std::complex<double> s(0.0, 2.0 * std::numbers::pi * f(i));
    const std::complex<double> expected = wn * wn / (s * s + 2.0 * zeta * wn * s + wn * wn);
    EXPECT_LT(std::abs(h(i) - expected), 1e-6 * std::abs(expected)) << f(i) << " Hz";
  }
  // The resonance: gain 1/(2ζ) = +20 dB at 5 Hz, phase −90°; the phase runs on to −180°, unwrapped.
  const BodeData bode = ToBode(model.FrequencyResponse(0, 0, Eigen::Vector3d(0.01, 5.0, 500.0)));
  EXPECT_NEAR(bode.gain_db(1), 20.0, 1e-6);
  EXPECT_NEAR(bode.phase_deg(1), -90.0, 1e-6);
  EXPECT_NEAR(bode.phase_deg(2), -180.0, 1.0);
}

TEST(Linearize, ADiscreteBlockHoldsItsOutputAndTheInputsAreHeldWhereAsked) {
  // u → gain 3 → y1 (direct); u → zero-order hold → y2 (a discrete path: held, so no dependence on u).
  const nlohmann::json j = {
      {"schemaVersion", "1.0"},
      {"connectors",
       {{{"name", "u"}, {"kind", "input"}},
        {{"name", "y1"}, {"kind", "output"}},
        {{"name", "y2"}, {"kind", "output"}}}},
      {"elements",
       {{{"name", "g"}, {"type", "gain"}, {"parameters", {{"gain", 3.0}}}},
        {{"name", "hold"}, {"type", "zero_order_hold"}, {"sampleTime", {0.01, 0.0}}}}},
      {"connections",
       {Link("", "u", "g", "u"), Link("g", "y", "", "y1"), Link("", "u", "hold", "u"), Link("hold", "y", "", "y2")}}};
  const LinearModel model = Linearize(Build(j), OperatingPoint{{{"u", 0.5}}, std::nullopt});
  EXPECT_EQ(model.a.rows(), 0);
  EXPECT_NEAR(model.d(0, 0), 3.0, 1e-9);
  EXPECT_EQ(model.d(1, 0), 0.0);
  EXPECT_NEAR(model.y0(0), 1.5, 1e-12);
  EXPECT_NEAR(model.y0(1), 0.5, 1e-12);  // the hold's output at the operating point
}

TEST(Linearize, AnUnknownInputIsRefusedWithTheKnownOnes) {
  const Diagram d = Build(MassSpringDamper(1.0, 0.0, 1.0));
  try {
    Linearize(d, OperatingPoint{{{"forse", 1.0}}, std::nullopt});
    FAIL() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("no input connector 'forse'"));
    EXPECT_THAT(e.what(), HasSubstr("force"));
  }
  EXPECT_THROW(LogSpacedFrequencies(0.0, 10.0, 5), std::invalid_argument);
  EXPECT_THROW(LinearModel{}.FrequencyResponse(0, 0, Eigen::VectorXd::Ones(1)), std::out_of_range);
}

TEST(ToBode, UnwrapsAPureDelaysPhase) {
  // e^{−j2πfτ} with τ = 0.01 s from 1 to 200 Hz: the phase falls linearly to −720°, gain 0 dB.
  const Eigen::VectorXd f = Eigen::VectorXd::LinSpaced(200, 1.0, 200.0);
  Eigen::VectorXcd h(f.size());
  for (Eigen::Index i = 0; i < f.size(); ++i) h(i) = std::polar(1.0, -2.0 * std::numbers::pi * f(i) * 0.01);
  const BodeData bode = ToBode(h);
  for (Eigen::Index i = 0; i < f.size(); ++i) {
    EXPECT_NEAR(bode.phase_deg(i), -360.0 * f(i) * 0.01, 1e-9);
    EXPECT_NEAR(bode.gain_db(i), 0.0, 1e-12);
  }
}

}  // namespace
}  // namespace mb

// The diagnosis in simulation mode (issue 46): a closed-loop diagram driven by the logged reference, its simulated
// position compared with the measured one, on records of the independent generator (tests/diagnosis/independent_plant.h:
// its own plant, friction law, PID with filtered velocity and feedforward, encoder quantisation and timing jitter) that
// hide one force each. The user's diagram (data/independent_closed_loop.json) models that loop as its user would: the
// same PID structure at 1 kHz, a rigid body with friction; its mass, friction and offset are refit.
//
// What is checked: the hidden force is named with its key parameter and, because every candidate force is fitted
// through the closed loop (models/diagnosis/loop_response.h), with its amplitude in newtons; on a record with nothing
// hidden nothing is named; the logged motor force, which the loop computes from the very error being explained, never
// becomes a candidate.

#include <cmath>
#include <limits>
#include <numbers>
#include <filesystem>
#include <optional>
#include <string>
#include <tuple>
#include <utility>

#include <unistd.h>

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "engine/diagram_document.h"
#include "engine/diagram_loader.h"
#include "models/diagnosis/effect_block.h"
#include "models/diagnosis/loop_response.h"
#include "tests/diagnosis/independent_plant.h"
#include "tools/workflow/comparison.h"
#include "tools/workflow/equation_error_view.h"
#include "tools/workflow/improve.h"
#include "tools/workflow/loop_probe.h"
#include "tools/workflow/measurement.h"
#include "tools/workflow/suggest.h"

namespace mb {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

const fs::path kData = fs::path(MB_SOURCE_DIR) / "tests" / "diagnosis" / "data";
constexpr const char* kDiagram = "independent_closed_loop.json";

struct SimulationCase {
  MeasurementLog log;
  DiagnosedComparison compared;
  std::string notes;  // every note, one per line
};

// The independent generator's closed-loop record hiding `hidden` (its reference logged), read as the user's diagram
// reads it.
MeasurementLog IndependentRecord(const nlohmann::json& diagram, independent::Hidden hidden, const std::string& name,
                                 const MeasurementSettings& measurement, unsigned seed = 11, double duration = 12.0) {
  independent::GeneratorSettings settings;
  settings.duration = duration;
  settings.log_reference = true;
  settings.seed = seed;
  const fs::path directory = fs::temp_directory_path() / fmt::format("mb_simulation_mode_{}_{}", name, ::getpid());
  fs::create_directories(directory);
  const fs::path csv = directory / "record.csv";
  independent::WriteCsv(independent::Generate(hidden, settings), csv.string());
  MeasurementLog log = ReadMeasurementFor(diagram, csv.string(), measurement);
  fs::remove_all(directory);
  return log;
}

SimulationCase CompareInSimulation(independent::Hidden hidden, const std::string& name, unsigned seed = 11,
                                   double duration = 12.0) {
  const nlohmann::json diagram = ReadDiagramJson(kData / kDiagram);
  MeasurementSettings measurement;
  SimulationCase out{IndependentRecord(diagram, hidden, name, measurement, seed, duration), {}, {}};
  out.compared = CompareAndDiagnose(diagram, kData, kDiagram, out.log, measurement, diagram["free"]);
  for (const std::string& note : out.compared.notes) out.notes += note + "\n";
  return out;
}

// The simulated position's RMSE against the measured one, with the fitted diagram and with `amended`, recorded as the
// test's properties position_rmse_before_m and position_rmse_after_m [m].
std::pair<double, double> PositionRmse(const SimulationCase& c, const nlohmann::json& amended) {
  const ModelComparison before(c.compared.fitted_diagram, kData, kDiagram, c.log, {});
  const ModelComparison after(amended, kData, kDiagram, c.log, {});
  const double rmse_before = before.Simulate().front().rmse, rmse_after = after.Simulate().front().rmse;
  ::testing::Test::RecordProperty("position_rmse_before_m", fmt::format("{:.4g}", rmse_before));
  ::testing::Test::RecordProperty("position_rmse_after_m", fmt::format("{:.4g}", rmse_after));
  return {rmse_before, rmse_after};
}

const DiagnosedEffect* FirstNamed(const DiagnosisResult& d) {
  for (const DiagnosedEffect& e : d.effects) {
    if (std::find(d.friction_law.begin(), d.friction_law.end(), e.effect) == d.friction_law.end()) return &e;
  }
  return nullptr;
}

TEST(SimulationMode, ThePositionRippleIsNamedWithItsPeriodAndItsForce) {
  const SimulationCase c = CompareInSimulation(independent::Hidden::kPositionRipple, "ripple");
  ASSERT_TRUE(c.compared.diagnosis);
  EXPECT_EQ(c.compared.mode, ExperimentMode::kSimulation);
  EXPECT_THAT(c.notes, HasSubstr("through the closed loop"));
  // The logged motor force is the controller's output: a reaction, never a candidate.
  EXPECT_THAT(c.notes, HasSubstr("log column 'force_N' is the diagram's own signal"));
  const DiagnosedEffect* first = FirstNamed(*c.compared.diagnosis);
  ASSERT_NE(first, nullptr) << c.compared.diagnosis->summary;
  EXPECT_EQ(first->effect, "position_periodic") << c.compared.diagnosis->summary;
  EXPECT_NEAR(first->parameters.at("period"), 0.006, 0.03 * 0.006);
  // 1.5 N at the period (and 0.4 N at its half): the first harmonic's amplitude, a force.
  const double cos1 = BlockCoefficient(*first, "cos1"), sin1 = BlockCoefficient(*first, "sin1");
  EXPECT_NEAR(std::hypot(cos1, sin1), 1.5, 0.3) << c.compared.diagnosis->summary;
}

TEST(SimulationMode, TheSuggestedBlockActsOnThePlantAndBringsThePositionCloser) {
  const SimulationCase c = CompareInSimulation(independent::Hidden::kPositionRipple, "ripple_block");
  ASSERT_TRUE(c.compared.diagnosis);
  const DiagnosedEffect* first = FirstNamed(*c.compared.diagnosis);
  ASSERT_NE(first, nullptr);
  ASSERT_EQ(first->effect, "position_periodic");
  // The ripple block reads the plant's simulated position and loads the plant's force input; its coefficients are
  // the diagnosis' forces, not refit: the amended loop's position comes closer to the measured one by itself.
  const nlohmann::json amended = SuggestAmendedDiagram(c.compared.fitted_diagram, *first, "position");
  const DiagramDocument document(amended);
  bool reads_plant = false, loads_plant = false;
  for (const Connection& k : document.Connections()) {
    if (k.start.element == "plant" && k.start.port == "x" && !k.end.is_connector() &&
        document.TypeOf(k.end.element) == "position_periodic") {
      reads_plant = true;
    }
    if (k.end.element == "plant" && k.end.port == "f" && k.start.element.rfind("with_", 0) == 0) loads_plant = true;
  }
  EXPECT_TRUE(reads_plant) << amended.dump(1);
  EXPECT_TRUE(loads_plant) << amended.dump(1);
  const auto [rmse_before, rmse_after] = PositionRmse(c, amended);
  EXPECT_LT(rmse_after, 0.95 * rmse_before) << "position RMSE " << rmse_before << " m -> " << rmse_after << " m";
}

// A drive that saturates (at 120 N and −135 N, below the controller's ±400 N clip) slows the axis, and the controller
// commands more than the model's loop, which lacks the limit, ever does: the logged command follows no signal of the
// closed loop. Opened at the compared position (the diagram's controller fed the measured position), the diagram
// computes what the controller that ran computed, so the logged command is recognised as a reaction — the
// controller's output, which must not explain the error — and the model's drive force is known. Before, it was kept
// as a force "from outside the loop", and the viscous friction following it was tried as a candidate. The first 4 s.
TEST(SimulationMode, TheCommandOfASaturatingDriveIsAReactionOfTheLoopOpenedAtThePosition) {
  const SimulationCase c = CompareInSimulation(independent::Hidden::kSaturation, "saturation", 11, 4.0);
  ASSERT_TRUE(c.compared.diagnosis);
  EXPECT_THAT(c.notes, HasSubstr("log column 'force_N' is the diagram's own signal 'clip.y' computed from the "
                                 "measured 'position_m' (the loop opened there"));
  EXPECT_THAT(c.notes, HasSubstr("the model's drive force ŷ, which a force constant multiplies, is 'clip.y'"));
  EXPECT_THAT(c.compared.signals.extra_names, ::testing::IsEmpty());
  ASSERT_TRUE(c.compared.drive_force_source);
  EXPECT_EQ(c.compared.drive_force_source->ToString(), "clip.y");
  // The equation-error view: the logged command against the plant's inverse on the measured motion names the
  // saturation the position view cannot tell from the loop's own clip.
  const EquationErrorView view = DiagnoseEquationErrorView(c.compared, kData, kDiagram, c.log, MeasurementSettings{});
  ASSERT_TRUE(view.diagnosis) << view.skipped;
  EXPECT_EQ(view.command_column, "force_N");
  EXPECT_EQ(view.force_signal, "net_force.y");
  // The plant's inverse, identified from the plant's own run: the mass the position fit left in it.
  const double fitted_mass =
      GetParameterValues(c.compared.compared_diagram, ResolveFreeParameters(c.compared.compared_diagram, {"plant.mass"}))(0);
  EXPECT_NEAR(view.mass, fitted_mass, 1e-3 * fitted_mass) << view.note;
  EXPECT_NEAR(view.damping, 0.0, 0.01) << view.note;  // the diagram's rigid body has none
  EXPECT_EQ(view.first_named, "drive_saturation") << view.diagnosis->summary;
  ASSERT_FALSE(view.verdict.empty()) << view.note;
  EXPECT_EQ(view.verdict.front().effect, "drive_saturation") << view.note;
}

TEST(SimulationMode, NothingIsNamedWhenNothingIsMissing) {
  const SimulationCase c = CompareInSimulation(independent::Hidden::kNone, "none");
  ASSERT_TRUE(c.compared.diagnosis);
  for (const DiagnosedEffect& e : c.compared.diagnosis->effects) {
    EXPECT_LT(e.score, 0.02) << e.effect << " named on a record with nothing missing: "
                             << c.compared.diagnosis->summary;
  }
  const EquationErrorView view = DiagnoseEquationErrorView(c.compared, kData, kDiagram, c.log, MeasurementSettings{});
  ASSERT_TRUE(view.diagnosis) << view.skipped;
  for (const DiagnosedEffect& e : view.diagnosis->effects) {
    EXPECT_LT(e.score, 0.02) << e.effect << " named in the equation-error view of a record with nothing missing: "
                             << view.diagnosis->summary;
  }
  // Without the controller's output in the log there is no commanded force to set against the plant: said, not run.
  DiagnosedComparison without = c.compared;
  without.reactions.clear();
  EXPECT_THAT(DiagnoseEquationErrorView(without, kData, kDiagram, c.log, MeasurementSettings{}).skipped,
              HasSubstr("no log column is the controller's output"));
  without.mode = ExperimentMode::kEquationError;
  EXPECT_THAT(DiagnoseEquationErrorView(without, kData, kDiagram, c.log, MeasurementSettings{}).skipped,
              HasSubstr("equation-error mode"));
}

// A ranked effect for CombineViews: its name, score and one parameter.
DiagnosedEffect Named(const std::string& effect, double score, double parameter) {
  DiagnosedEffect e;
  e.effect = effect;
  e.score = score;
  e.parameters["p"] = parameter;
  return e;
}

// Two instruments on one machine: what both name is the verdict, with the force's parameters — but a delay of the
// measured output, an effect of the measurement chain, keeps the position's; what one view names alone is left out.
TEST(CombineViews, WhatBothViewsNameIsTheVerdictWithTheParametersOfTheViewThatMeasuresIt) {
  DiagnosisResult position, force;
  position.effects = {Named("backlash_load", 0.7, 1.0), Named("time_delay", 0.4, 2.0), Named("backlash", 0.3, 3.0)};
  force.effects = {Named("backlash", 0.4, 30.0), Named("hysteresis", 0.08, 40.0), Named("time_delay", 0.05, 20.0),
                   Named("backlash", 0.01, 31.0)};
  const auto [verdict, from] = CombineViews(position, force);
  EXPECT_EQ(from, "both");
  ASSERT_EQ(verdict.size(), 2U);
  EXPECT_EQ(verdict[0].effect, "backlash");
  EXPECT_EQ(verdict[0].parameters.at("p"), 30.0);  // the force view's, its first entry
  EXPECT_EQ(verdict[1].effect, "time_delay");
  EXPECT_EQ(verdict[1].parameters.at("p"), 2.0);  // the position view's: it acts on the measured output
}

TEST(CombineViews, WithNothingInCommonTheViewWhoseFirstEffectExplainsMoreOfItsResidualStands) {
  DiagnosisResult position, force;
  position.effects = {Named("viscous_friction", 0.93, 1.0), Named("hysteresis", 0.85, 2.0)};
  force.effects = {Named("drive_saturation", 0.999, 400.0)};
  auto [verdict, from] = CombineViews(position, force);
  EXPECT_EQ(from, "equation-error view");
  ASSERT_EQ(verdict.size(), 1U);
  EXPECT_EQ(verdict[0].effect, "drive_saturation");
  force.effects = {Named("local_force_constant", 0.18, 0.5)};
  position.effects = {Named("force_constant_along_travel", 0.997, 0.1)};
  std::tie(verdict, from) = CombineViews(position, force);
  EXPECT_EQ(from, "position view");
  ASSERT_EQ(verdict.size(), 1U);
  EXPECT_EQ(verdict[0].effect, "force_constant_along_travel");
  force.effects.clear();  // one view names nothing: the other's stands
  std::tie(verdict, from) = CombineViews(position, force);
  EXPECT_EQ(from, "position view");
  position.effects.clear();
  std::tie(verdict, from) = CombineViews(position, force);
  EXPECT_EQ(from, "");
  EXPECT_TRUE(verdict.empty());
}

// The share of `column`'s energy that the base's columns reproduce by least squares.
double ShareSpanned(const Eigen::VectorXd& column, const Eigen::MatrixXd& base) {
  const Eigen::VectorXd fitted = base * base.colPivHouseholderQr().solve(column);
  return fitted.squaredNorm() / column.squaredNorm();
}

// A force of the base's own (the plant's mass: a load M·a) simulated through the full diagram is the base's
// sensitivity to the mass itself; through the loop linearised at one stretch it is not, because the axis sticks at
// every reversal, where the loop is another. So the chosen effects are refit on simulated columns, and a mass mismatch
// beside the free plant mass (−21 kg on the Stribeck record, fitting the linearisation's error) is no longer named.
TEST(SimulationMode, TheChosenEffectsAreRefitThroughTheFullDiagram) {
  const SimulationCase c = CompareInSimulation(independent::Hidden::kStribeck, "stribeck");
  ASSERT_TRUE(c.compared.diagnosis);
  ASSERT_TRUE(c.compared.diagnosis->loop);
  const LoopResponse& loop = *c.compared.diagnosis->loop;
  ASSERT_TRUE(loop.can_simulate());
  const Eigen::VectorXd& a = c.compared.signals.acceleration;
  const double simulated = ShareSpanned(loop.Simulate(a), c.compared.base.columns);
  const double linearised = ShareSpanned(loop.Apply(a), c.compared.base.columns);
  RecordProperty("mass_share_simulated", fmt::format("{:.4f}", simulated));
  RecordProperty("mass_share_linearised", fmt::format("{:.4f}", linearised));
  EXPECT_GT(simulated, 0.98);
  EXPECT_LT(linearised, simulated);
  EXPECT_THAT(c.notes, HasSubstr("simulated through the full diagram"));
  for (const DiagnosedEffect& e : c.compared.diagnosis->effects) {
    EXPECT_NE(e.effect, "mass_mismatch") << c.compared.diagnosis->summary;
  }
}

TEST(SimulationMode, APayloadStepIsNamedAtItsTime) {
  const SimulationCase c = CompareInSimulation(independent::Hidden::kPayloadStep, "payload");
  ASSERT_TRUE(c.compared.diagnosis);
  const DiagnosedEffect* first = FirstNamed(*c.compared.diagnosis);
  ASSERT_NE(first, nullptr) << c.compared.diagnosis->summary;
  EXPECT_EQ(first->effect, "mass_change") << c.compared.diagnosis->summary;
  EXPECT_NEAR(first->parameters.at("change_time"), 8.0, 0.5) << c.compared.diagnosis->summary;
  // 31 kg picked up: a load the drive must carry, with the sign equation-error mode gives it.
  EXPECT_NEAR(BlockCoefficient(*first, ""), 31.0, 6.0) << c.compared.diagnosis->summary;
  // Its block schedules the plant's mass (a block of the plant's acceleration would close an algebraic loop), and the
  // simulated position comes closer to the measured one.
  const nlohmann::json amended = SuggestAmendedDiagram(c.compared.fitted_diagram, *first, "position");
  const DiagramDocument document(amended);
  EXPECT_EQ(document.Parameter("plant", "mass_input"), true);
  const std::optional<Endpoint> mass = document.DriverOf({"plant", "added_mass"});
  ASSERT_TRUE(mass) << amended.dump(1);
  EXPECT_EQ(document.TypeOf(mass->element), "switched_gain") << amended.dump(1);
  const auto [rmse_before, rmse_after] = PositionRmse(c, amended);
  EXPECT_LT(rmse_after, 0.75 * rmse_before) << "position RMSE " << rmse_before << " m -> " << rmse_after << " m";
}

TEST(SimulationMode, AForceConstantRippleIsNamedWithItsPeriod) {
  // The drive's force constant ripples with a 12 mm period. It multiplies the drive's force, which in simulation mode
  // is the simulated controller's: the diagram's signal that the logged command force_N is.
  const SimulationCase c = CompareInSimulation(independent::Hidden::kForceRipple, "force_ripple");
  ASSERT_TRUE(c.compared.diagnosis);
  EXPECT_THAT(c.notes, HasSubstr("the diagram's signal that the logged command 'force_N' is"));
  const DiagnosedEffect* first = FirstNamed(*c.compared.diagnosis);
  ASSERT_NE(first, nullptr) << c.compared.diagnosis->summary;
  EXPECT_EQ(first->effect, "force_constant_ripple") << c.compared.diagnosis->summary;
  EXPECT_NEAR(first->parameters.at("period"), 0.012, 0.03 * 0.012) << c.compared.diagnosis->summary;
  // Its block multiplies the drive's force (the controller's output, before or after its hold) and loads the plant:
  // the position comes closer.
  ASSERT_TRUE(c.compared.drive_force_source);
  const std::string drive_force = c.compared.drive_force_source->ToString();
  EXPECT_THAT(drive_force, ::testing::AnyOf("command.y", "controller_output.y"));
  const nlohmann::json amended =
      SuggestAmendedDiagram(c.compared.fitted_diagram, *first, "position", c.compared.drive_force_source);
  const DiagramDocument document(amended);
  bool reads_drive_force = false;
  for (const Connection& k : document.Connections()) {
    if (k.start.ToString() == drive_force && document.TypeOf(k.end.element) == "product") {
      reads_drive_force = true;
    }
  }
  EXPECT_TRUE(reads_drive_force) << amended.dump(1);
  const auto [rmse_before, rmse_after] = PositionRmse(c, amended);
  EXPECT_LT(rmse_after, 0.95 * rmse_before) << "position RMSE " << rmse_before << " m -> " << rmse_after << " m";
  // Without the drive's force the block is refused, with what to do.
  try {
    SuggestAmendedDiagram(c.compared.fitted_diagram, *first, "position");
    FAIL() << "a force constant's block was added without the drive's force";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("compare the drive's force as an output"));
  }
}

TEST(SimulationMode, AnActuatorLagIsNamedAlongTheCommandTheLoopGivesWithItAndRefitInTheDiagram) {
  // The drive applies the command 4 ms late. The force the plant lacks is u(t) − u(t − d) along the command the loop
  // gives with the lag (the controller reacts to it), fitted through the loop; along the model's own command alone the
  // lag came out 6.1 ms on the bench's record. Through the loop linearised along the record the lag comes out short
  // (3.35 ms on the bench's record); simulated in the diagram (DiagnosisSignals::simulate_effect) it is refined, and
  // improve's refit of the amended closed-loop diagram keeps it (the block's delay is refinable).
  const nlohmann::json diagram = ReadDiagramJson(kData / kDiagram);
  ImproveSettings settings;
  settings.max_effects = 1;
  settings.max_trials_per_round = 1;
  settings.fallback = false;
  const MeasurementLog log =
      IndependentRecord(diagram, independent::Hidden::kActuatorLag, "actuator_lag", settings.measurement);
  const ImproveResult improved = ImproveModel(DiagramDocument(diagram, kData, kDiagram), log, nullptr, settings);
  const DiagnosedComparison& compared = improved.first().training;
  ASSERT_TRUE(compared.diagnosis);
  const DiagnosedEffect* first = FirstNamed(*compared.diagnosis);
  ASSERT_NE(first, nullptr) << compared.diagnosis->summary;
  EXPECT_EQ(first->effect, "actuator_lag") << compared.diagnosis->summary;
  EXPECT_NEAR(first->parameters.at("lag"), 0.004, 0.05 * 0.004) << compared.diagnosis->summary;
  EXPECT_NEAR(BlockCoefficient(*first, ""), 1.0, 0.2) << compared.diagnosis->summary;
  // Its block, a transport delay, goes after the drive's force: every block that read it reads the delayed force; the
  // refit sets its delay, and the held-out position error falls.
  ASSERT_EQ(improved.steps.size(), 2U) << improved.stop_reason;
  const ImproveStep& step = improved.steps[1];
  ASSERT_TRUE(step.accepted) << step.verdict;
  ASSERT_TRUE(compared.drive_force_source);
  const DiagramDocument document(step.training.fitted_diagram);
  const std::string drive_force = compared.drive_force_source->ToString();
  int reads_drive_force = 0;
  for (const Connection& k : document.Connections()) {
    if (k.start.ToString() == drive_force && !k.end.is_connector()) {
      ++reads_drive_force;
      EXPECT_EQ(document.TypeOf(k.end.element), "transport_delay") << document.json().dump(1);
    }
  }
  EXPECT_EQ(reads_drive_force, 1) << document.json().dump(1);
  const double delay = document.Parameter(step.element, "delay").get<double>();
  ::testing::Test::RecordProperty("lag_diagnosed_s", fmt::format("{:.5g}", first->parameters.at("lag")));
  ::testing::Test::RecordProperty("lag_refit_s", fmt::format("{:.5g}", delay));
  EXPECT_NEAR(delay, 0.004, 0.05 * 0.004) << step.verdict;
  EXPECT_LT(step.rmse_heldout, 0.5 * step.rmse_heldout_before) << step.verdict;
}

TEST(SimulationMode, AMassAlongTheTravelIsThePlantsAndItsKineticForceALoad) {
  // M(x)·a + ½M′(x)·v²: M(x) goes to the plant's mass input (a block of the plant's acceleration would feed the force
  // that sets it), ½M′(x)·v² is a load on the plant's force.
  DiagnosedEffect linkage;
  linkage.effect = "inertia_ripple";
  linkage.parameters = {{"period", 0.04}, {"harmonics", 1.0}};
  linkage.column_names = {"inertia_ripple.cos1", "inertia_ripple.sin1"};
  linkage.coefficients = Eigen::Vector2d(6.0, -2.0);
  const DiagramDocument amended(SuggestAmendedDiagram(ReadDiagramJson(kData / kDiagram), linkage, "position"));
  EXPECT_EQ(amended.Parameter("plant", "mass_input"), true);
  EXPECT_EQ(amended.Parameter("inertia_ripple", "acceleration_input"), false);
  EXPECT_EQ(amended.DriverOf({"plant", "added_mass"}), (Endpoint{"inertia_ripple", "mass"}));
  EXPECT_EQ(amended.DriverOf({"inertia_ripple", "x"}), (Endpoint{"plant", "x"}));
  EXPECT_EQ(amended.DriverOf({"inertia_ripple", "v"}), (Endpoint{"plant", "v"}));
  const std::optional<Endpoint> force = amended.DriverOf({"plant", "f"});
  ASSERT_TRUE(force);
  EXPECT_EQ(amended.DriverOf({force->element, "u2"}), (Endpoint{"inertia_ripple", "y"})) << amended.json().dump(1);
}

TEST(SimulationMode, AMassOnAPlantWithoutAMassInputIsRefusedWithWhatToDo) {
  DiagnosedEffect payload;
  payload.effect = "mass_change";
  payload.parameters = {{"change_time", 8.0}};
  payload.column_names = {"mass_change"};
  payload.coefficients = Eigen::VectorXd::Constant(1, 31.0);
  nlohmann::json diagram = ReadDiagramJson(kData / kDiagram);
  for (auto& element : diagram["elements"]) {
    if (element["name"] == "plant") element = {{"name", "plant"}, {"type", "linear_motor"}};
  }
  try {
    SuggestAmendedDiagram(diagram, payload, "position");
    FAIL() << "a mass was added to a plant that cannot take it";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("has no mass input"));
  }
}

TEST(SimulationMode, ADiagramWithoutAPlantSaysWhyItIsNotProbed) {
  // The EMPS inverse model has no element of a type with the loop role "plant": nothing to probe.
  const DiagramDocument inverse(ReadDiagramJson(fs::path(MB_SOURCE_DIR) / "diagrams" / "emps" / "rigid_body.json"));
  std::string why;
  EXPECT_FALSE(PlantForcePort(inverse, &why));
  EXPECT_THAT(why, HasSubstr("no plant"));
  const DiagramDocument loop(ReadDiagramJson(kData / kDiagram));
  const std::optional<Endpoint> port = PlantForcePort(loop, &why);
  ASSERT_TRUE(port);
  EXPECT_EQ(port->ToString(), "plant.f");
}

TEST(LoopResponse, FiltersCausallyAsTheDirectSumDoes) {
  Eigen::VectorXd h(4);
  h << 0.5, 0.25, -0.125, 0.0625;
  const LoopResponse loop(h, 9);
  Eigen::MatrixXd in(9, 2);
  in.col(0) << 1, 0, 0, 0, 0, 0, 0, 0, 0;
  in.col(1) << 0.3, -1.2, 2.0, 0.7, -0.4, 1.1, 0.0, -2.5, 0.9;
  const Eigen::MatrixXd out = loop.Apply(in);
  for (Eigen::Index j = 0; j < 2; ++j) {
    for (Eigen::Index n = 0; n < 9; ++n) {
      double direct = 0.0;
      for (Eigen::Index k = 0; k < h.size() && k <= n; ++k) direct += h(k) * in(n - k, j);
      EXPECT_NEAR(out(n, j), direct, 1e-12) << "column " << j << ", sample " << n;
    }
  }
  EXPECT_DOUBLE_EQ(loop.static_gain(), 0.6875);
  EXPECT_THROW(loop.Apply(Eigen::MatrixXd::Zero(8, 1)), std::invalid_argument);
  EXPECT_THROW(LoopResponse(Eigen::VectorXd::Zero(3), 9), std::invalid_argument);
}

// Simulate gives what the attached simulator gives; a column it has no tangent for (NaN) the linearised loop's, and the
// count says how many; without a simulator every column is Apply's.
TEST(LoopResponse, ASimulatedColumnWithoutATangentKeepsTheLinearisedResponse) {
  Eigen::VectorXd h(3);
  h << 0.5, 0.25, 0.125;
  LoopResponse loop(h, 6);
  Eigen::MatrixXd in(6, 2);
  in.col(0) << 1, 2, 3, 4, 5, 6;
  in.col(1) << 0, 1, 0, -1, 0, 1;
  EXPECT_TRUE(loop.Simulate(in).isApprox(loop.Apply(in)));  // no simulator yet
  EXPECT_FALSE(loop.can_simulate());
  loop.set_simulator([](const Eigen::MatrixXd& loads) {
    Eigen::MatrixXd out = 2.0 * loads;
    out.col(1).setConstant(std::numeric_limits<double>::quiet_NaN());
    return out;
  });
  ASSERT_TRUE(loop.can_simulate());
  const LoopResponse copy = loop;  // copies share the count
  const Eigen::MatrixXd out = copy.Simulate(in);
  EXPECT_TRUE(out.col(0).isApprox(2.0 * in.col(0)));
  EXPECT_TRUE(out.col(1).isApprox(loop.Apply(in.col(1))));
  EXPECT_EQ(loop.simulated_count().columns, 2);
  EXPECT_EQ(loop.simulated_count().linearised, 1);
  EXPECT_THROW(loop.Simulate(Eigen::MatrixXd::Zero(5, 1)), std::invalid_argument);
}

TEST(LoopResponse, ItsGainIsTheMagnitudeOfItsFourierTransform) {
  // h = [½, ½]: a two-sample average, |H(f)| = |cos(π f Ts)|; 0 at the Nyquist frequency.
  const LoopResponse average(Eigen::Vector2d(0.5, 0.5), 16);
  const double ts = 1e-3;
  for (const double f : {0.0, 100.0, 250.0, 400.0, 500.0}) {
    EXPECT_NEAR(average.GainAt(f, ts), std::abs(std::cos(std::numbers::pi * f * ts)), 1e-12) << f << " Hz";
  }
}

TEST(LoopResponse, TheForceOfAnOutputIsRecoveredWhereTheLoopPassesIt) {
  // h = [1, ½]: |H| between ½ and 3/2, well conditioned; the Wiener deconvolution with a small λ returns the force.
  const Eigen::Index n = 256;
  const LoopResponse loop(Eigen::Vector2d(1.0, 0.5), n);
  Eigen::VectorXd force(n);
  for (Eigen::Index i = 0; i < n; ++i) force(i) = std::sin(0.07 * static_cast<double>(i)) + (i % 17 == 0 ? 1.0 : 0.0);
  const Eigen::VectorXd output = loop.Apply(force).col(0);
  EXPECT_LT((loop.ForceOf(output, 1e-9) - force).cwiseAbs().maxCoeff(), 1e-6);
  // A large λ damps the force it returns rather than blowing up anything.
  EXPECT_LT(loop.ForceOf(output, 10.0).norm(), 0.5 * force.norm());
  EXPECT_THROW(loop.ForceOf(Eigen::VectorXd::Zero(n - 1), 1e-3), std::invalid_argument);
}

TEST(SimulationMode, ItSaysHowLargeAForceThePositionCanShow) {
  const SimulationCase c = CompareInSimulation(independent::Hidden::kNone, "shows");
  EXPECT_THAT(c.notes, HasSubstr("what the position can show (simulation mode)"));
  EXPECT_THAT(c.notes, ::testing::ContainsRegex("is [0-9.e+-]+ N at 2 Hz, [0-9.e+-]+ N at 5 Hz"));
}

}  // namespace
}  // namespace mb

// Reading a log for a diagram (tools/workflow/measurement.h): column units from the names' suffixes (issue 30) and a
// derivative cut-off that follows the sample rate (issue 25 item 1). Every log is made here, not by the code tested.
#include "tools/workflow/measurement.h"

#include <cmath>
#include <filesystem>
#include <fstream>
#include <numbers>
#include <string>

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "engine/diagram_loader.h"
#include "models/diagnosis/signal_processing.h"
#include "tests/error_message.h"
#include "tools/workflow/comparison.h"
#include "tools/workflow/measurement_in_memory.h"

namespace mb {
namespace {

namespace fs = std::filesystem;
using ::testing::AllOf;
using ::testing::HasSubstr;
using ::testing::Not;

constexpr double kPi = std::numbers::pi;
const fs::path kDiagram = fs::path(MB_SOURCE_DIR) / "diagrams" / "emps" / "rigid_body.json";  // equation error

// A back-and-forth of 10 mm amplitude at 0.5 Hz sampled every `step` [s], `rows` rows: time, position, force.
struct Motion {
  Eigen::VectorXd t, x, force;
};
Motion Sampled(double step, Eigen::Index rows) {
  Motion m{Eigen::VectorXd(rows), Eigen::VectorXd(rows), Eigen::VectorXd(rows)};
  for (Eigen::Index i = 0; i < rows; ++i) {
    m.t(i) = static_cast<double>(i) * step;
    m.x(i) = 0.01 * std::sin(kPi * m.t(i));
    m.force(i) = 50.0 * std::cos(kPi * m.t(i));
  }
  return m;
}

std::string WriteCsv(const std::string& name, const std::string& header, const Eigen::VectorXd& a,
                     const Eigen::VectorXd& b, const Eigen::VectorXd& c) {
  const fs::path dir = fs::temp_directory_path() /
                       ("mb_measurement_test_" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()));
  fs::create_directories(dir);
  const fs::path path = dir / name;
  std::ofstream out(path);
  out << header << "\n";
  for (Eigen::Index i = 0; i < a.size(); ++i) out << fmt::format("{},{},{}\n", a(i), b(i), c(i));
  return path.string();
}

bool AnyNoteHas(const MeasurementLog& log, const std::string& text) {
  for (const auto& n : log.notes()) {
    if (n.find(text) != std::string::npos) return true;
  }
  return false;
}

// Issue 30: position_mm was read as metres ("period 8001 mm", a fit of −15979 %).
TEST(MeasurementUnits, APositionInMillimetresIsReadInMetres) {
  const Motion m = Sampled(1e-3, 2000);
  const MeasurementLog in_m = AddMeasurementDerivatives(
      IntakeMeasurementLog(MeasurementLog({"time_s", "position_m", "force_N"}, {m.t, m.x, m.force})), "position_m",
      kAutomaticCutoffHz);
  const MeasurementLog in_mm = AddMeasurementDerivatives(
      IntakeMeasurementLog(MeasurementLog({"time_s", "position_mm", "force_N"}, {m.t, 1e3 * m.x, m.force})),
      "position_mm", kAutomaticCutoffHz);
  EXPECT_DOUBLE_EQ(PositionToMetres("position_mm"), 1e-3);
  EXPECT_DOUBLE_EQ(PositionToMetres("position_um"), 1e-6);
  EXPECT_DOUBLE_EQ(PositionToMetres("position_cm"), 1e-2);
  EXPECT_EQ(DerivedVelocityColumn("position_mm"), "velocity_m_s");
  EXPECT_EQ(DerivedAccelerationColumn("position_mm"), "acceleration_m_s2");
  // The column keeps its name and holds metres; the derived motion is in m/s and m/s², as from a log in metres.
  EXPECT_LT((in_mm.column("position_mm") - m.x).cwiseAbs().maxCoeff(), 1e-17);
  EXPECT_LT((in_mm.column("velocity_m_s") - in_m.column("velocity_m_s")).cwiseAbs().maxCoeff(), 1e-13);
  EXPECT_NEAR(in_mm.column("velocity_m_s")(1000), 0.01 * kPi * std::cos(kPi * 1.0), 1e-5);
  ASSERT_EQ(in_mm.notes().size(), 1u);
  EXPECT_THAT(in_mm.notes()[0],
              HasSubstr("the position column 'position_mm' is in mm (its name's suffix): converted to metres (× 0.001) "
                        "and keeps its name, also as 'position_m' for a diagram that reads metres; the derived "
                        "velocity_m_s and acceleration_m_s2 are in m/s and m/s²"));
  // Issue 40, item 8: one flag does it — a diagram whose position connector reads position_m finds the metres.
  ASSERT_TRUE(in_mm.has_column("position_m"));
  EXPECT_EQ((in_mm.column("position_m") - in_mm.column("position_mm")).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_TRUE(in_m.notes().empty());
}

// The code base's convention for rotary axes (engine/units.h): rad, rev and deg stay in their own unit.
TEST(MeasurementUnits, ARotaryPositionKeepsItsUnit) {
  const Motion m = Sampled(1e-3, 500);
  const MeasurementLog log = AddMeasurementDerivatives(
      IntakeMeasurementLog(MeasurementLog({"time_s", "angle_deg", "torque_Nm"}, {m.t, 360.0 * m.x, m.force})),
      "angle_deg", kAutomaticCutoffHz);
  EXPECT_DOUBLE_EQ(PositionToMetres("angle_deg"), 1.0);
  EXPECT_EQ((log.column("angle_deg") - 360.0 * m.x).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_TRUE(log.has_column("velocity_deg_s"));
  EXPECT_TRUE(log.notes().empty());
}

// Issue 30: a time column time_ms ended in "cut-off 100 Hz must lie in (0, 0.5 Hz)"; now read in seconds.
TEST(MeasurementUnits, ATimeInMillisecondsIsReadInSeconds) {
  const Motion m = Sampled(1e-3, 2000);
  const std::string path = WriteCsv("time_ms.csv", "time_ms,position_mm,force_N", 1e3 * m.t, 1e3 * m.x, m.force);
  MeasurementSettings settings;
  settings.position_column = "position_mm";
  const MeasurementLog log = ReadMeasurementFor(ReadDiagramJson(kDiagram), path, settings);
  EXPECT_EQ(log.names().front(), "time_s");
  EXPECT_NEAR(log.time()(1000), 1.0, 1e-12);
  EXPECT_NEAR(log.column("velocity_m_s")(1000), 0.01 * kPi * std::cos(kPi * 1.0), 1e-5);
  EXPECT_TRUE(AnyNoteHas(log, "the time column 'time_ms' is in ms (its name's suffix): converted to seconds"));
  EXPECT_TRUE(AnyNoteHas(log, "the position column 'position_mm' is in mm"));
}

// Issue 25 item 1: on a log sampled at 100 Hz, compare stopped with "ZeroPhaseLowPass: cut-off 100 Hz must lie in
// (0, 50 Hz)". The default now follows the sample rate, with a note; a cut-off the user chose stays an error.
TEST(AutomaticCutoff, A100HzLogIsReadWithACutoffBelowItsNyquistFrequency) {
  const Motion m = Sampled(1e-2, 1000);
  const std::string path = WriteCsv("rate_100hz.csv", "time_s,position_m,force_N", m.t, m.x, m.force);
  const MeasurementSettings settings;  // the default cut-off
  const MeasurementLog log = ReadMeasurementFor(ReadDiagramJson(kDiagram), path, settings);
  EXPECT_NEAR(DerivativeCutoffHz(settings, log), 20.0, 1e-9);
  EXPECT_TRUE(AnyNoteHas(log, "rate_100hz.csv: sampled at 100 Hz (Nyquist 50 Hz): the default derivative cut-off "
                              "100 Hz became 0.2 × the sample rate, 20 Hz"));
  EXPECT_NEAR(log.column("velocity_m_s")(500), 0.01 * kPi * std::cos(kPi * 5.0), 1e-4);
  // The same in memory.
  const MeasurementLog memory = AddMeasurementDerivatives(
      IntakeMeasurementLog(MeasurementLog({"time_s", "position_m", "force_N"}, {m.t, m.x, m.force})), "position_m",
      kAutomaticCutoffHz, {"force_N"});
  EXPECT_EQ((memory.column("velocity_m_s") - log.column("velocity_m_s")).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_TRUE(AnyNoteHas(memory, "became 0.2 × the sample rate, 20 Hz"));

  MeasurementSettings chosen;
  chosen.derivative_cutoff_hz = 60.0;
  EXPECT_THAT(::mb::testing::ErrorOf([&] { ReadMeasurementFor(ReadDiagramJson(kDiagram), path, chosen); }),
              AllOf(HasSubstr("rate_100hz.csv: the derivative cut-off 60 Hz must lie above 0 and below the Nyquist "
                              "frequency 50 Hz of this log (sampled at 100 Hz)"),
                    HasSubstr("e.g. --derivative-cutoff-hz 20"), Not(HasSubstr("ZeroPhaseLowPass"))));
  // compare goes through: the model output and the diagnosis' regressors are filtered like the log.
  const nlohmann::json diagram = ReadDiagramJson(kDiagram);
  const DiagnosedComparison c = CompareAndDiagnose(diagram, kDiagram.parent_path(), kDiagram.string(), log, settings,
                                                   {"inertia.gain", "friction.viscous"});
  EXPECT_TRUE(c.diagnosis.has_value()) << c.diagnosis_skipped;
  EXPECT_LT(c.after.front().rmse, c.before.front().rmse);

  chosen.derivative_cutoff_hz = 10.0;  // a chosen cut-off below Nyquist: as given, no note
  const MeasurementLog at_10 = ReadMeasurementFor(ReadDiagramJson(kDiagram), path, chosen);
  EXPECT_DOUBLE_EQ(DerivativeCutoffHz(chosen, at_10), 10.0);
  EXPECT_FALSE(AnyNoteHas(at_10, "derivative cut-off"));
}

// Issue 45, item 4: a coarse encoder. Its count differentiated twice with a 100 Hz low-pass is most of the derived
// acceleration of a slow motion; the automatic cut-off comes down (with a note) to where it is at most a tenth, and the
// diagnosis' parallel filter follows. A fine encoder keeps 100 Hz; a chosen cut-off is kept.
TEST(AutomaticCutoff, ACoarseEncoderBringsItDownToWhereTheMotionDominates) {
  const auto counted = [](double step) {
    Motion m = Sampled(1e-3, 4000);
    for (Eigen::Index i = 0; i < m.x.size(); ++i) m.x(i) = std::floor(0.01 * std::sin(kPi * m.t(i)) / step) * step;
    return m;
  };
  const auto log_with_step = [&](double step, const std::string& name) {
    const Motion m = counted(step);
    return WriteCsv(name, "time_s,position_m,force_N", m.t, m.x, m.force);
  };
  const MeasurementSettings settings;
  const MeasurementLog coarse =
      ReadMeasurementFor(ReadDiagramJson(kDiagram), log_with_step(1e-5, "coarse.csv"), settings);
  const double cutoff = DerivativeCutoffHz(settings, coarse);
  EXPECT_LT(cutoff, 100.0);
  EXPECT_GE(cutoff, 100.0 / 8.0 - 1e-9);
  EXPECT_TRUE(AnyNoteHas(coarse, "coarse.csv: the position 'position_m' is logged in steps of 1e-05"));
  EXPECT_TRUE(AnyNoteHas(coarse, fmt::format("the automatic cut-off came down to {:.4g} Hz", cutoff)));
  // The derived acceleration is the motion's, not the encoder's: −0.01·π²·sin(πt), its error's RMS within a fifth of
  // the motion's (the turning points, where the count stands still for 14 ms, are the worst).
  const double amplitude = 0.01 * kPi * kPi;
  double error = 0.0;
  for (Eigen::Index i = 500; i < 3500; ++i) {
    error += std::pow(coarse.column("acceleration_m_s2")(i) + amplitude * std::sin(kPi * coarse.time()(i)), 2);
  }
  EXPECT_LT(std::sqrt(error / 3000.0), 0.2 * amplitude / std::sqrt(2.0));
  const Motion m = counted(1e-5);
  const MeasurementLog unlimited = AddMeasurementDerivatives(  // a cut-off chosen: kept
      IntakeMeasurementLog(MeasurementLog({"time_s", "position_m", "force_N"}, {m.t, m.x, m.force})), "position_m", 99.0);
  double error_at_99 = 0.0;
  for (Eigen::Index i = 500; i < 3500; ++i) {
    error_at_99 += std::pow(unlimited.column("acceleration_m_s2")(i) + amplitude * std::sin(kPi * coarse.time()(i)), 2);
  }
  EXPECT_GT(error_at_99, 4.0 * error) << "at 99 Hz the encoder's count dominates the derived acceleration";

  const MeasurementLog fine = ReadMeasurementFor(ReadDiagramJson(kDiagram), log_with_step(1e-9, "fine.csv"), settings);
  EXPECT_EQ(DerivativeCutoffHz(settings, fine), 100.0);
  EXPECT_FALSE(AnyNoteHas(fine, "came down"));

  MeasurementSettings chosen;
  chosen.derivative_cutoff_hz = 80.0;
  const MeasurementLog kept = ReadMeasurementFor(ReadDiagramJson(kDiagram), log_with_step(1e-5, "kept.csv"), chosen);
  EXPECT_EQ(DerivativeCutoffHz(chosen, kept), 80.0);
  EXPECT_FALSE(AnyNoteHas(kept, "came down"));
}

// At 500 Hz and above the default stays 100 Hz: the 1 kHz results (EMPS) are bit-identical to a 100 Hz low-pass.
TEST(AutomaticCutoff, At1kHzTheDefaultIs100HzBitForBit) {
  EXPECT_EQ(DerivativeCutoffHz(kAutomaticCutoffHz, 1e-3, "log"), 100.0);
  EXPECT_EQ(DerivativeCutoffHz(kAutomaticCutoffHz, 2e-3, "log"), 100.0);
  EXPECT_DOUBLE_EQ(DerivativeCutoffHz(kAutomaticCutoffHz, 1.0 / 250.0, "log"), 50.0);
  const Motion m = Sampled(1e-3, 3000);
  const MeasurementLog log = AddMeasurementDerivatives(
      IntakeMeasurementLog(MeasurementLog({"time_s", "position_m", "force_N"}, {m.t, m.x, m.force})), "position_m",
      kAutomaticCutoffHz, {"force_N"});
  const MotionDerivatives direct = DeriveMotion(m.t, m.x, 100.0);
  EXPECT_EQ((log.column("velocity_m_s") - direct.velocity).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((log.column("acceleration_m_s2") - direct.acceleration).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((log.column("force_N") - ZeroPhaseLowPass(m.force, MedianTimeStep(m.t), 100.0)).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_TRUE(log.notes().empty());
}

// Columns in memory (the Python module's arrays): time_s first whatever its place, and refused as a log file's reader
// refuses them, naming the column and the row.
TEST(MeasurementOfColumns, PutsTheTimeFirstAndRefusesWhatAFileReaderRefuses) {
  const Motion m = Sampled(1e-3, 10);
  const MeasurementLog log = MeasurementOfColumns({{"force_N", m.force}, {"time_s", m.t}}, "<arrays>");
  EXPECT_EQ(log.time(), m.t);
  EXPECT_EQ(log.column("force_N"), m.force);
  EXPECT_THROW(MeasurementOfColumns({}, "<arrays>"), std::invalid_argument);
  Eigen::VectorXd bad = m.force;
  bad(7) = std::nan("");
  try {
    MeasurementOfColumns({{"time_s", m.t}, {"force_N", bad}}, "<arrays>");
    ADD_FAILURE() << "a NaN was taken";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("column 'force_N' row 7 is nan"));
  }
  Eigen::VectorXd back = m.t;
  back(9) = 0.0;
  try {
    MeasurementOfColumns({{"time_s", back}, {"force_N", m.force}}, "<arrays>");
    ADD_FAILURE() << "a decreasing time was taken";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("time 'time_s' decreases at row 9"));
  }
  EXPECT_THROW(MeasurementOfColumns({{"time_s", m.t}, {"force_N", m.force.head(5)}}, "<arrays>"),
               std::invalid_argument);
}

}  // namespace
}  // namespace mb

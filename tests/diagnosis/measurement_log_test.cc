#include "models/diagnosis/measurement_log.h"

#include <chrono>
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <iostream>
#include <numbers>
#include <fstream>
#include <random>
#include <string>

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "tests/error_message.h"
#include "tests/process_temp_dir.h"

namespace mb {
namespace {

using ::testing::AllOf;
using ::testing::HasSubstr;

class MeasurementLogTest : public ::testing::Test {
 protected:
  std::string Write(const std::string& name, const std::string& text) {
    const auto dir = mb::testing::ProcessTempDir("mb_log_test");
    const std::string path = (dir / name).string();
    std::ofstream(path) << text;
    return path;
  }
  // A valid log of n rows at 1 ms.
  static std::string Rows(int n, int first = 0) {
    std::string s;
    for (int i = first; i < first + n; ++i) s += std::to_string(i * 1e-3) + "," + std::to_string(0.5 * i) + ",1\n";
    return s;
  }
  template <typename F>
  static std::string ErrorOf(F&& f) {
    return ::mb::testing::ErrorOf(std::forward<F>(f));
  }
};

TEST_F(MeasurementLogTest, ReadsColumnsByName) {
  const auto path = Write("ok.csv", "time_s,position_m,force_N\n" + Rows(20));
  const MeasurementLog log = ReadMeasurementLog(path, {.required_columns = {"position_m", "force_N"}});
  ASSERT_EQ(log.rows(), 20);
  EXPECT_EQ(log.names()[0], "time_s");
  EXPECT_DOUBLE_EQ(log.time()(3), 0.003);
  EXPECT_DOUBLE_EQ(log.column("position_m")(4), 2.0);
  EXPECT_TRUE(log.has_column("force_N"));
  EXPECT_THAT(ErrorOf([&] { (void)log.column("speed"); }),
              AllOf(HasSubstr("no column 'speed'"), HasSubstr("time_s, position_m, force_N")));
}

TEST_F(MeasurementLogTest, MissingFile) {
  EXPECT_THAT(ErrorOf([&] { ReadMeasurementLog("/nonexistent/log.csv"); }),
              AllOf(HasSubstr("/nonexistent/log.csv"), HasSubstr("cannot open"), HasSubstr("check the path")));
}

TEST_F(MeasurementLogTest, MissingColumnListsThePresentOnes) {
  const auto path = Write("cols.csv", "time_s,position_m,force_N\n" + Rows(20));
  EXPECT_THAT(ErrorOf([&] { ReadMeasurementLog(path, {.required_columns = {"input_V"}}); }),
              AllOf(HasSubstr("cols.csv"), HasSubstr("missing required column(s) input_V"),
                    HasSubstr("the columns present are: time_s, position_m, force_N")));
}

TEST_F(MeasurementLogTest, NonNumericCellNamesLineAndColumn) {
  const auto path = Write("text.csv", "time_s,position_m,force_N\n" + Rows(5) + "0.005,abc,1\n" + Rows(10, 6));
  EXPECT_THAT(ErrorOf([&] { ReadMeasurementLog(path); }),
              AllOf(HasSubstr("text.csv: line 7, column 'position_m': 'abc' is not a number")));
}

TEST_F(MeasurementLogTest, NanIsRejected) {
  const auto path = Write("nan.csv", "time_s,position_m,force_N\n" + Rows(3) + "0.003,1.5,NaN\n" + Rows(10, 4));
  EXPECT_THAT(ErrorOf([&] { ReadMeasurementLog(path); }),
              AllOf(HasSubstr("line 5, column 'force_N'"), HasSubstr("NaN or Inf"), HasSubstr("interpolate")));
  const auto inf = Write("inf.csv", "time_s,position_m,force_N\n" + Rows(3) + "0.003,inf,1\n" + Rows(10, 4));
  EXPECT_THAT(ErrorOf([&] { ReadMeasurementLog(inf); }), HasSubstr("line 5, column 'position_m'"));
}

TEST_F(MeasurementLogTest, GapIsReportedWithWhere) {
  const auto path = Write("gap.csv", "time_s,position_m,force_N\n" + Rows(10) + Rows(10, 15));
  EXPECT_THAT(ErrorOf([&] { ReadMeasurementLog(path); }),
              AllOf(HasSubstr("1 gap(s)"), HasSubstr("after t = 0.009 s (line 11, step 0.00"),
                    HasSubstr("the median step 0.00"), HasSubstr("resample")));
  // The check can be disabled.
  EXPECT_EQ(ReadMeasurementLog(path, {.required_columns = {}, .max_gap_ratio = 0.0}).rows(), 20);
}

TEST_F(MeasurementLogTest, NonMonotonicTime) {
  const auto path = Write("mono.csv", "time_s,position_m,force_N\n" + Rows(5) + "0.002,1,1\n" + Rows(10, 6));
  EXPECT_THAT(ErrorOf([&] { ReadMeasurementLog(path); }),
              AllOf(HasSubstr("line 7, column 'time_s': time 0.002 does not increase"), HasSubstr("sort the rows")));
}

TEST_F(MeasurementLogTest, TooFewRowsAndRaggedRows) {
  const auto few = Write("few.csv", "time_s,position_m,force_N\n" + Rows(3));
  EXPECT_THAT(ErrorOf([&] { ReadMeasurementLog(few); }), HasSubstr("only 3 data row(s), at least 10"));
  const auto ragged = Write("ragged.csv", "time_s,position_m,force_N\n" + Rows(5) + "0.005,1\n");
  EXPECT_THAT(ErrorOf([&] { ReadMeasurementLog(ragged); }), HasSubstr("line 7 has 2 cells but the header has 3"));
  const auto noheader = Write("noheader.csv", Rows(20));
  EXPECT_THAT(ErrorOf([&] { ReadMeasurementLog(noheader); }), HasSubstr("line 1 is numbers, not a header"));
}

TEST_F(MeasurementLogTest, WriteReadRoundTripIsExact) {
  Eigen::VectorXd t = Eigen::VectorXd::LinSpaced(50, 0.0, 0.049);
  Eigen::VectorXd y = t.array().sin() * 1e-3 + 1.0 / 3.0;
  const MeasurementLog log({"time_s", "y_m"}, {t, y});
  const auto path = Write("round.csv", "");
  WriteMeasurementLog(log, path);
  const MeasurementLog back = ReadMeasurementLog(path);
  ASSERT_EQ(back.rows(), 50);
  EXPECT_EQ((back.column("y_m") - y).cwiseAbs().maxCoeff(), 0.0);
  EXPECT_EQ((back.time() - t).cwiseAbs().maxCoeff(), 0.0);
}

// Its speed (about 10 ms in Release) is BM_ReadEmpsRecord's (tests/benchmarks/diagnosis_benchmark.cc).
TEST_F(MeasurementLogTest, ReadsTheEmpsRecord) {
  const std::string path = std::string(MB_SOURCE_DIR) + "/diagrams/emps/data/DATA_EMPS.csv";
  ASSERT_TRUE(std::filesystem::exists(path)) << "the repository's EMPS record is missing: " << path;
  const MeasurementLog log = ReadMeasurementLog(path, {.required_columns = {"position_m", "force_N"}});
  EXPECT_EQ(log.rows(), 24841);
  EXPECT_EQ(log.names().size(), 5u);
  EXPECT_NEAR(log.column("position_m")(0), 7.45e-06, 1e-18);
}

// 200k columns (issue 11): reading and looking up every column by name is linear (a name search per lookup made
// it quadratic: minutes), and an error lists only the first 30 names, not megabytes of them.
TEST_F(MeasurementLogTest, WideLogReadsInLinearTimeAndErrorsStayShort) {
  constexpr int kColumns = 200000;
  std::string text = "time_s";
  for (int j = 0; j < kColumns; ++j) text += ",c" + std::to_string(j);
  text += "\n";
  for (int i = 0; i < 3; ++i) {
    text += std::to_string(i * 1e-3);
    for (int j = 0; j < kColumns; ++j) text += ",1";
    text += "\n";
  }
  const std::string path = Write("wide.csv", text);
  const auto start = std::chrono::steady_clock::now();
  const MeasurementLog log = ReadMeasurementLog(path, {.required_columns = {}, .min_rows = 3});
  double sum = 0.0;
  for (const auto& name : log.names()) sum += log.column(name)(0);
  const double seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  EXPECT_EQ(sum, kColumns + 0.0);
  EXPECT_LT(seconds, 10.0);  // about 1.8 s under ASan on the loaded 2-core machine; the quadratic lookup: minutes
  try {
    log.column("missing");
    FAIL() << "no exception";
  } catch (const std::invalid_argument& e) {
    const std::string m = e.what();
    EXPECT_THAT(m, HasSubstr(": no column 'missing'; the columns present are: time_s, c0, c1,"));
    EXPECT_THAT(m, HasSubstr(", c28, … (199971 more)"));
    EXPECT_LT(m.size(), 400u);
  }
}

// Users' logs (issue 13): jitter, gaps, repeated rows are taken in with a note each, not refused.
TEST_F(MeasurementLogTest, IntakeResamplesAJitteredLogOntoItsMedianStep) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> jitter(0.6e-3, 1.4e-3);  // USB-like: ±40 % around 1 ms
  std::string text = "time_s,angle_rev,iq_A\n";
  double t = 0.0;
  for (int i = 0; i < 400; ++i) {
    text += fmt::format("{},{},{}\n", t, 0.5 * t, std::sin(2.0 * t));
    t += jitter(rng);
  }
  const MeasurementLog log = IntakeMeasurementLog(Write("jitter.csv", text));
  ASSERT_EQ(log.notes().size(), 1u);
  // Accurate stamps of uneven steps (each step's error stays in the stamps after it): irregular sampling, not noise.
  EXPECT_THAT(log.notes()[0], AllOf(HasSubstr("jitter.csv: the time steps are not uniform (jitter: steps from 0.0006"),
                                    HasSubstr("irregular sampling: stamp − a line fitted against the sample index "
                                              "reaches "),
                                    HasSubstr("resampled onto a uniform grid of step "), HasSubstr("400 rows → ")));
  const Eigen::VectorXd& tt = log.time();
  const double step = tt(1) - tt(0);
  EXPECT_NEAR(step, 1e-3, 0.05e-3);
  for (Eigen::Index i = 1; i < log.rows(); ++i) ASSERT_NEAR(tt(i) - tt(i - 1), step, 1e-12);
  for (Eigen::Index i = 0; i < log.rows(); ++i) {
    ASSERT_NEAR(log.column("angle_rev")(i), 0.5 * tt(i), 1e-12);           // linear: exact
    ASSERT_NEAR(log.column("iq_A")(i), std::sin(2.0 * tt(i)), 2e-6);        // interpolated
  }
  EXPECT_EQ(log.segment_starts(), std::vector<Eigen::Index>{0});
}

// Issue 25 item 7: a regular clock whose stamps are noisy (a logger stamping on arrival, ±20 % of the step) is not
// irregular sampling. Two segments split at a gap, each fitted on its own: the fitted clock is kept and the samples
// as logged, far closer to the truth than interpolating them at the noisy stamps.
TEST_F(MeasurementLogTest, IntakeKeepsTheFittedClockOfNoisyStampsOnARegularClock) {
  constexpr double kStep = 1e-3, kHz = 5.0;
  constexpr Eigen::Index kRows = 1000;  // per segment
  const double starts[2] = {0.5, 2.0};  // the gap between them: 0.5 s
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> stamp_noise(-0.2 * kStep, 0.2 * kStep);
  Eigen::VectorXd stamps(2 * kRows), truth_time(2 * kRows), y(2 * kRows);
  for (Eigen::Index i = 0; i < 2 * kRows; ++i) {
    truth_time(i) = starts[i / kRows] + static_cast<double>(i % kRows) * kStep;  // when the sample was taken
    stamps(i) = truth_time(i) + stamp_noise(rng);                                // when it was stamped
    y(i) = std::sin(2.0 * std::numbers::pi * kHz * truth_time(i));
  }
  const MeasurementLog raw({"time_s", "y_V"}, {stamps, y}, "noisy_stamps.csv");
  const MeasurementLog log = IntakeMeasurementLog(raw);

  ASSERT_EQ(log.rows(), 2 * kRows);
  EXPECT_EQ(log.segment_starts(), (std::vector<Eigen::Index>{0, kRows}));
  ASSERT_EQ(log.notes().size(), 2u);  // the gap, then the clock
  EXPECT_THAT(log.notes()[1],
              AllOf(HasSubstr("noisy_stamps.csv: the time stamps are noisy on a regular clock"),
                    HasSubstr("in 2 segments, each fitted on its own"), HasSubstr("% of the step; RMS "),
                    HasSubstr("the fitted clock t_k = t0 + k·T (T from "), HasSubstr("Lab Streaming Layer")));
  EXPECT_EQ((log.column("y_V") - y).cwiseAbs().maxCoeff(), 0.0);  // the samples untouched
  for (Eigen::Index i = 1; i < log.rows(); ++i) {
    if (i == kRows) continue;
    ASSERT_NEAR(log.time()(i) - log.time()(i - 1), kStep, 1e-3 * kStep);  // one clock per segment
  }
  EXPECT_LT((log.time() - truth_time).cwiseAbs().maxCoeff(), 0.05 * kStep);

  // The values against the truth at the times the log now gives them, and what interpolating the samples at their
  // noisy stamps onto the true grid gives (the intake's resampling before).
  const auto rms_error = [&](const Eigen::VectorXd& t, const Eigen::VectorXd& v) {
    return std::sqrt((v.array() - (2.0 * std::numbers::pi * kHz * t.array()).sin()).square().mean());
  };
  Eigen::VectorXd interpolated(2 * kRows);
  for (Eigen::Index i = 0; i < 2 * kRows; ++i) {
    const Eigen::Index first = (i / kRows) * kRows, last = first + kRows - 1;
    Eigen::Index j = std::clamp<Eigen::Index>(i, first + 1, last);
    while (j > first + 1 && stamps(j - 1) > truth_time(i)) --j;
    while (j < last && stamps(j) < truth_time(i)) ++j;
    const double w = (truth_time(i) - stamps(j - 1)) / (stamps(j) - stamps(j - 1));
    interpolated(i) = y(j - 1) + w * (y(j) - y(j - 1));
  }
  const double fitted_error = rms_error(log.time(), log.column("y_V"));
  const double interpolation_error = rms_error(truth_time, interpolated);
  std::cout << fmt::format("noisy stamps ±20 %: RMS error of the values, fitted clock {:.3g}, interpolated at the "
                           "stamps {:.3g} (amplitude 1)\n",
                           fitted_error, interpolation_error);
  EXPECT_LT(fitted_error, 0.05 * interpolation_error);
  std::cout << log.notes()[1] << "\n";
}

// The same bounded scatter about a regular clock, but the stamps accurate: a sampling loop with scheduling jitter (±5 %
// of the step) that stamps each sample when it takes it. The stamps alone cannot tell it from the case above; the
// signal can: the sine is smooth against the stamps and rough against the fitted clock. Its samples are interpolated
// onto the fitted clock, far closer to the truth there than the samples as logged (the fitted clock's reading).
TEST_F(MeasurementLogTest, IntakeInterpolatesOntoTheFittedClockWhenTheSamplesWereTakenAtTheirStamps) {
  constexpr double kStep = 1e-3, kHz = 5.0;
  constexpr Eigen::Index kRows = 2000;
  std::mt19937 rng(11);
  std::uniform_real_distribution<double> jitter(-0.05 * kStep, 0.05 * kStep);
  std::normal_distribution<double> noise(0.0, 0.1);
  Eigen::VectorXd stamps(kRows), y(kRows), force(kRows);
  for (Eigen::Index i = 0; i < kRows; ++i) {
    stamps(i) = 0.5 + static_cast<double>(i) * kStep + jitter(rng);  // when the sample was taken and stamped
    y(i) = std::sin(2.0 * std::numbers::pi * kHz * stamps(i));
    force(i) = noise(rng);  // a column of noise alone: as rough on either time base
  }
  const MeasurementLog log = IntakeMeasurementLog(MeasurementLog({"time_s", "y_V", "force_N"}, {stamps, y, force},
                                                                 "sampled_when_stamped.csv"));
  ASSERT_EQ(log.rows(), kRows);
  ASSERT_EQ(log.notes().size(), 1u);
  EXPECT_THAT(log.notes()[0], AllOf(HasSubstr("sampled_when_stamped.csv: the samples were taken at their time stamps"),
                                    HasSubstr("'y_V' is"), HasSubstr("smoother against the stamps"),
                                    HasSubstr("interpolated (linearly) onto the fitted clock")));
  for (Eigen::Index i = 1; i < log.rows(); ++i) ASSERT_NEAR(log.time()(i) - log.time()(i - 1), kStep, 1e-3 * kStep);
  const auto rms_error = [&](const Eigen::VectorXd& v) {
    return std::sqrt((v.array() - (2.0 * std::numbers::pi * kHz * log.time().array()).sin()).square().mean());
  };
  const double interpolated = rms_error(log.column("y_V")), as_logged = rms_error(y);
  std::cout << fmt::format("sampled when stamped, ±5 %: RMS error of the values on the fitted clock, interpolated "
                           "{:.3g}, as logged {:.3g} (amplitude 1)\n", interpolated, as_logged);
  EXPECT_LT(interpolated, 0.1 * as_logged);
  std::cout << log.notes()[0] << "\n";
}

// A regular clock with exact stamps that drops a sample now and then is irregular sampling: the residual against the
// fitted line steps at each drop (it drifts), so the rows are resampled, not put on a fitted clock.
TEST_F(MeasurementLogTest, IntakeResamplesARegularClockThatDropsSamples) {
  Eigen::VectorXd t(300), y(300);
  for (Eigen::Index i = 0, k = 0; i < 300; ++i, ++k) {
    if (i % 50 == 25) ++k;  // a sample missed (6 in all)
    t(i) = 1e-3 * static_cast<double>(k);
    y(i) = 2.0 * t(i);
  }
  const MeasurementLog log = IntakeMeasurementLog(MeasurementLog({"time_s", "position_m"}, {t, y}));
  ASSERT_EQ(log.notes().size(), 1u);
  EXPECT_THAT(log.notes()[0], AllOf(HasSubstr("irregular sampling"), HasSubstr("300 rows → 306")));
  for (Eigen::Index i = 0; i < log.rows(); ++i) ASSERT_NEAR(log.column("position_m")(i), 2.0 * log.time()(i), 1e-12);
}

TEST_F(MeasurementLogTest, IntakeSplitsAtAGapAndWarnsInsteadOfRefusing) {
  const auto path = Write("gap_intake.csv", "time_s,position_m,force_N\n" + Rows(20) + Rows(30, 40) + Rows(3, 100));
  const MeasurementLog log = IntakeMeasurementLog(path);
  ASSERT_EQ(log.rows(), 50);  // the 3 rows after the second gap are too few to filter: left out
  EXPECT_EQ(log.segment_starts(), (std::vector<Eigen::Index>{0, 20}));
  ASSERT_EQ(log.notes().size(), 2u);
  EXPECT_THAT(log.notes()[0], AllOf(HasSubstr("2 gap(s) in time longer than 5 × the median step 0.001 s"),
                                    HasSubstr("0.019 s → 0.04 s"), HasSubstr("split into 3 segments"),
                                    HasSubstr("nothing is interpolated across a gap")));
  EXPECT_THAT(log.notes()[1], HasSubstr("1 segment(s) shorter than 16 rows between gaps were left out"));
  EXPECT_DOUBLE_EQ(log.time()(20), 0.04);  // uniform within each segment: nothing resampled
}

TEST_F(MeasurementLogTest, IntakeMergesRepeatedTimeStamps) {
  const auto path = Write("dup.csv", "time_s,position_m,force_N\n" + Rows(5) + "0.004,3,5\n0.004,4,7\n" + Rows(20, 5));
  const MeasurementLog log = IntakeMeasurementLog(path);
  ASSERT_EQ(log.rows(), 25);
  ASSERT_EQ(log.notes().size(), 1u);
  EXPECT_THAT(log.notes()[0], AllOf(HasSubstr("1 time stamp(s) appear on more than one row (first at t = 0.004 s)"),
                                    HasSubstr("the mean of its rows, 27 rows → 25")));
  EXPECT_DOUBLE_EQ(log.column("position_m")(4), 3.0);  // mean of 2, 3, 4
  EXPECT_DOUBLE_EQ(log.column("force_N")(4), (1.0 + 5.0 + 7.0) / 3.0);
  // The strict reader still refuses them; a time going back stays an error for both.
  EXPECT_THAT(ErrorOf([&] { ReadMeasurementLog(path); }), HasSubstr("does not increase"));
  const auto back = Write("back.csv", "time_s,position_m,force_N\n" + Rows(5) + "0.002,1,1\n" + Rows(10, 6));
  EXPECT_THAT(ErrorOf([&] { IntakeMeasurementLog(back); }),
              AllOf(HasSubstr("line 7, column 'time_s': time 0.002 does not increase"), HasSubstr("sort the rows")));
}

TEST_F(MeasurementLogTest, IntakeLeavesAUniformLogAsItIs) {
  const auto path = Write("uniform.csv", "time_s,position_m,force_N\n" + Rows(40));
  const MeasurementLog log = IntakeMeasurementLog(path);
  EXPECT_EQ(log.rows(), 40);
  EXPECT_TRUE(log.notes().empty());
  EXPECT_DOUBLE_EQ(log.time()(7), 0.007);
  const auto gaps_only = Write("gaps_only.csv", "time_s,position_m,force_N\n" + Rows(5) + Rows(5, 20) + Rows(5, 40));
  EXPECT_THAT(ErrorOf([&] { IntakeMeasurementLog(gaps_only); }),
              HasSubstr("no stretch of the log between its gaps has 16 rows"));
}

TEST(ColumnUnit, ReadsLinearRotaryAndDriveUnitsFromTheSuffix) {
  EXPECT_EQ(ColumnUnit("position_m"), "m");
  EXPECT_EQ(ColumnUnit("angle_rev"), "rev");
  EXPECT_EQ(ColumnUnit("theta_rad"), "rad");
  EXPECT_EQ(ColumnUnit("angle_deg"), "deg");
  EXPECT_EQ(ColumnUnit("iq_A"), "A");
  EXPECT_EQ(ColumnUnit("torque_Nm"), "N·m");
  EXPECT_EQ(ColumnUnit("force_N"), "N");
  EXPECT_EQ(ColumnUnit("velocity_rev_s"), "rev/s");
  EXPECT_EQ(ColumnUnit("acceleration_m_s2"), "m/s^2");
  EXPECT_EQ(ColumnUnit("encoder_counts"), "");
  EXPECT_EQ(ColumnUnit("speed"), "");
  // Issue 30: the other units of a position and of the time.
  EXPECT_EQ(ColumnUnit("position_mm"), "mm");
  EXPECT_EQ(ColumnUnit("position_um"), "um");
  EXPECT_EQ(ColumnUnit("position_cm"), "cm");
  EXPECT_EQ(ColumnUnit("time_ms"), "ms");
  EXPECT_EQ(ColumnUnit("time_us"), "us");
  EXPECT_EQ(ColumnUnit("velocity_m_s"), "m/s");
}

// Issue 30: a time column named time_ms was read as seconds (a 1000 times too slow record: "cut-off 100 Hz must lie
// in (0, 0.5 Hz)"). It is converted to seconds and named time_s, with a note, by the strict reader and the intake.
TEST_F(MeasurementLogTest, TimeInMillisecondsIsReadInSeconds) {
  std::string text = "time_ms,position_m,force_N\n";
  for (int i = 0; i < 20; ++i) text += fmt::format("{},{},1\n", 2 * i, 0.5 * i);  // 2 ms steps
  const auto path = Write("time_ms.csv", text);
  for (const MeasurementLog& log : {ReadMeasurementLog(path), IntakeMeasurementLog(path)}) {
    EXPECT_EQ(log.names().front(), "time_s");
    EXPECT_DOUBLE_EQ(log.time()(3), 0.006);
    EXPECT_DOUBLE_EQ(log.column("position_m")(3), 1.5);
    ASSERT_EQ(log.notes().size(), 1u);
    EXPECT_THAT(log.notes()[0], AllOf(HasSubstr("time_ms.csv: the time column 'time_ms' is in ms (its name's suffix): "
                                                "converted to seconds (× 0.001) and named time_s")));
  }
  Eigen::VectorXd t_us = Eigen::VectorXd::LinSpaced(20, 0.0, 19e3);  // 1 ms steps in µs, in memory
  const MeasurementLog in_memory =
      IntakeMeasurementLog(MeasurementLog({"time_us", "y_V"}, {t_us, Eigen::VectorXd::Ones(20)}));
  EXPECT_DOUBLE_EQ(in_memory.time()(19), 0.019);
  // A column named time_s beside it: refused, naming both.
  const auto both = Write("both.csv", "time_ms,time_s,force_N\n" + Rows(20));
  EXPECT_THAT(ErrorOf([&] { ReadMeasurementLog(both); }),
              AllOf(HasSubstr("both.csv: the time column 'time_ms' is in ms"), HasSubstr("named time_s; rename one")));
  // A time column that declares a unit this reader does not know is refused, not read as seconds (tests/hostile);
  // a first column without that form stays seconds (below).
  const auto fortnight = Write("fortnight.csv", "time_fortnight,position_m,force_N\n" + Rows(20));
  EXPECT_THAT(ErrorOf([&] { ReadMeasurementLog(fortnight); }),
              HasSubstr("fortnight.csv: the time column 'time_fortnight' declares the unit 'fortnight', which is no "
                        "time unit known here"));
  // Seconds, or no unit: as before, without a note.
  EXPECT_TRUE(ReadMeasurementLog(Write("plain.csv", "t,position_m,force_N\n" + Rows(20))).notes().empty());
}

}  // namespace
}  // namespace mb

// fit-gpr / predict-gpr through the library functions the commands call: a synthetic DOB log as CSV
// → training-sample selection (window, downsampling) → fit → model file → prediction along a log →
// CSV, and the errors a wrong column, an empty window or a clashing column give.
#include "models/gpr/gpr_log.h"

#include <cmath>
#include <filesystem>
#include <functional>
#include <limits>
#include <stdexcept>
#include <string>
#include <vector>

#include <fmt/format.h>
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "models/gpr/gpr_io.h"
#include "tests/error_message.h"
#include "tests/gpr/synthetic_data.h"

namespace mb {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;

// A DOB log of constant-velocity scans: time_s, position_m, velocity_m_s, dob_N (noise 0.02 N).
MeasurementLog SyntheticLog() {
  const auto s = testing::ConstantVelocityScans(0.05, 0.4, 40, 0.02, 61);
  const Eigen::Index n = s.x.size();
  const Eigen::VectorXd t = Eigen::VectorXd::LinSpaced(n, 0.0, 1e-3 * static_cast<double>(n - 1));
  return MeasurementLog({"time_s", "position_m", "velocity_m_s", "dob_N"}, {t, s.x, s.xdot, s.d});
}

using ::mb::testing::ErrorOf;

class GprLog : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("mb_gpr_log_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()));
    fs::create_directories(dir_);
  }
  void TearDown() override { fs::remove_all(dir_); }
  fs::path dir_;
};

TEST_F(GprLog, SelectionAppliesWindowThenDownsampling) {
  const MeasurementLog log = SyntheticLog();
  GprTrainingSelection selection;
  selection.disturbance_column = "dob_N";
  selection.window = GprRange{0.1, 0.325};
  selection.downsample = 3;
  const GprTrainingData data = SelectGprTrainingData(log, selection);

  std::vector<Eigen::Index> in_window;
  const Eigen::VectorXd& x = log.column("position_m");
  for (Eigen::Index i = 0; i < log.rows(); ++i) {
    if (x(i) >= 0.1 && x(i) <= 0.325) in_window.push_back(i);
  }
  const auto expected_n = static_cast<Eigen::Index>((in_window.size() + 2) / 3);
  ASSERT_EQ(data.x.size(), expected_n);
  for (Eigen::Index k = 0; k < expected_n; ++k) {
    const Eigen::Index i = in_window[static_cast<std::size_t>(3 * k)];
    ASSERT_EQ(data.x(k), x(i));
    ASSERT_EQ(data.xdot(k), log.column("velocity_m_s")(i));
    ASSERT_EQ(data.d(k), log.column("dob_N")(i));
  }
  EXPECT_EQ(data.description,
            "<memory> (position: position_m, velocity: velocity_m_s, disturbance: dob_N, window [0.1, 0.325] m, "
            "downsampled by 3; N = " + std::to_string(expected_n) + " of 400 rows)");
}

TEST_F(GprLog, FitAndPredictRoundTripThroughFiles) {
  const fs::path csv = dir_ / "dob_log.csv";
  WriteMeasurementLog(SyntheticLog(), csv.string());

  // fit-gpr dob_log.csv --disturbance-column dob_N --window 0.1,0.325 --downsample 2 -o model.json
  MeasurementLogOptions read;
  read.min_rows = 2;
  read.max_gap_ratio = 0.0;
  const MeasurementLog log = ReadMeasurementLog(csv.string(), read);
  GprTrainingSelection selection;
  selection.disturbance_column = "dob_N";
  selection.window = GprRange{0.1, 0.325};
  selection.downsample = 2;
  GprFitOptions options;
  options.restarts = 0;
  const GprModel fitted = FitGprToLog(log, selection, options);
  SaveGprModel(fitted, dir_ / "model.json");
  const GprModel model = LoadGprModel(dir_ / "model.json");

  const GprProvenance& p = model.data().provenance;
  const Eigen::Index n = SelectGprTrainingData(log, selection).x.size();
  EXPECT_EQ(p.sample_count, n);
  EXPECT_THAT(p.source, HasSubstr(csv.string() + " (position: position_m, velocity: velocity_m_s, disturbance: "
                                  "dob_N, window [0.1, 0.325] m, downsampled by 2; N = " + std::to_string(n) +
                                  " of 400 rows)"));
  EXPECT_EQ(p.created_utc.size(), 20u) << p.created_utc;  // "YYYY-MM-DDTHH:MM:SSZ"
  EXPECT_EQ(p.solver, "weight_space");
  EXPECT_GE(model.x_range().min, 0.1);
  EXPECT_LE(model.x_range().max, 0.325);

  // predict-gpr model.json scan.csv -o prediction.csv, on a fresh scan at 0.3 m/s.
  const Eigen::Index rows = 200;
  const Eigen::VectorXd t = Eigen::VectorXd::LinSpaced(rows, 0.0, 0.199);
  const Eigen::VectorXd x = Eigen::VectorXd::LinSpaced(rows, 0.12, 0.3);
  const Eigen::VectorXd v = Eigen::VectorXd::Constant(rows, 0.3);
  const fs::path scan = dir_ / "scan.csv";
  WriteMeasurementLog(MeasurementLog({"time_s", "pos", "vel"}, {t, x, v}), scan.string());
  read.min_rows = 1;
  const MeasurementLog in = ReadMeasurementLog(scan.string(), read);
  WriteMeasurementLog(PredictGprOnLog(model, in, "pos", "vel"), (dir_ / "prediction.csv").string());
  const MeasurementLog out = ReadMeasurementLog((dir_ / "prediction.csv").string(), read);

  EXPECT_EQ(out.names(), (std::vector<std::string>{"time_s", "pos", "vel", "mean", "std", "extrapolated"}));
  ASSERT_EQ(out.rows(), rows);
  double squared_error = 0.0;
  for (Eigen::Index i = 0; i < rows; ++i) {
    ASSERT_EQ(out.column("pos")(i), x(i));
    // Written in the shortest form that reads back exactly: the prediction itself, bit for bit.
    ASSERT_EQ(out.column("mean")(i), fitted.PredictPosteriorMean(x(i), 0.3));
    double sd = -1.0;
    fitted.Predict(x(i), 0.3, nullptr, &sd);
    ASSERT_EQ(out.column("std")(i), sd);
    ASSERT_EQ(out.column("extrapolated")(i), GprExtrapolates(fitted, x(i), 0.3) ? 1.0 : 0.0);
    const double e = out.column("mean")(i) - testing::TrueDisturbance(x(i), 0.3);
    squared_error += e * e;
  }
  // Noise 0.02 N, cogging amplitude ≈ 0.6 N: the learned model follows the truth closely.
  EXPECT_LT(std::sqrt(squared_error / static_cast<double>(rows)), 0.03);
}

// Issue 30: a model trained on x in [0.1, 0.325] m was "fully confident" at x = 1e299 m. The prediction keeps its
// value there (as GprModel documents) but says, row by row, that it extrapolates.
TEST_F(GprLog, PredictionsOutsideTheTrainedRangeAreMarkedExtrapolated) {
  GprTrainingSelection selection;
  selection.disturbance_column = "dob_N";
  selection.window = GprRange{0.1, 0.325};
  GprFitOptions options;
  options.restarts = 0;
  const GprModel model = FitGprToLog(SyntheticLog(), selection, options);
  const GprRange x = model.x_range(), v = model.xdot_range();
  const double x_mid = 0.5 * (x.min + x.max), v_mid = 0.5 * (v.min + v.max);
  const double nan = std::numeric_limits<double>::quiet_NaN();
  // Inside, both bounds (inside), x far out, x just below, ẋ above, ẋ below, NaN position, infinite velocity.
  const std::vector<double> xs = {x_mid, x.min, 1e299, x.min - 1e-9, x_mid, x_mid, nan, x_mid};
  const std::vector<double> vs = {v_mid, v.max, v_mid, v_mid, v.max + 1e-9, v.min - 0.1, v_mid,
                                  std::numeric_limits<double>::infinity()};
  const std::vector<double> expected = {0, 0, 1, 1, 1, 1, 1, 1};
  const MeasurementLog query({"position_m", "velocity_m_s"},
                             {Eigen::Map<const Eigen::VectorXd>(xs.data(), 8),
                              Eigen::Map<const Eigen::VectorXd>(vs.data(), 8)});
  const MeasurementLog out = PredictGprOnLog(model, query);
  ASSERT_TRUE(out.has_column("extrapolated"));
  for (Eigen::Index i = 0; i < 8; ++i) {
    EXPECT_EQ(out.column("extrapolated")(i), expected[static_cast<std::size_t>(i)]) << "row " << i;
  }
  MeasurementLog clash = query;
  clash.AddColumn("extrapolated", Eigen::VectorXd::Zero(8));
  EXPECT_THAT(ErrorOf([&] { PredictGprOnLog(model, clash); }),
              HasSubstr("already has a column \"extrapolated\", which the prediction would write"));
}

TEST_F(GprLog, ErrorsNameTheProblemAndTheFix) {
  const MeasurementLog log = SyntheticLog();
  GprTrainingSelection selection;
  EXPECT_THAT(ErrorOf([&] { SelectGprTrainingData(log, selection); }), HasSubstr("no disturbance column given"));
  selection.disturbance_column = "force_N";
  EXPECT_THAT(ErrorOf([&] { SelectGprTrainingData(log, selection); }),
              HasSubstr("<memory>: no column 'force_N'; the columns present are: "));
  selection.disturbance_column = "dob_N";
  selection.window = GprRange{0.5, 0.6};
  EXPECT_THAT(ErrorOf([&] { SelectGprTrainingData(log, selection); }),
              HasSubstr("<memory>: 0 training sample(s) in the position window [0.5, 0.6] m (column position_m "
                        "spans ["));
  // Two rows are no fit (issue 41: a 56-feature model came of them without a word): the minimum is said.
  const Eigen::VectorXd& x = log.column("position_m");
  const auto two = [&](const Eigen::VectorXd& column) { return Eigen::VectorXd(column.head(2)); };
  const MeasurementLog two_rows({"time_s", "position_m", "velocity_m_s", "dob_N"},
                                {two(log.column("time_s")), two(x), two(log.column("velocity_m_s")),
                                 two(log.column("dob_N"))});
  selection.window.reset();
  EXPECT_THAT(ErrorOf([&] { SelectGprTrainingData(two_rows, selection); }),
              HasSubstr(fmt::format("<memory>: 2 training sample(s) (column position_m spans [{:g}, {:g}] m over 2 "
                                    "rows); a GP fit needs at least 10 (it estimates its hyperparameters from the "
                                    "data)",
                                    std::min(x(0), x(1)), std::max(x(0), x(1)))));
  selection.window = GprRange{0.3, 0.2};
  EXPECT_THAT(ErrorOf([&] { SelectGprTrainingData(log, selection); }),
              HasSubstr("position window [0.3, 0.2] m is empty or not finite: give xmin < xmax"));
  selection.window.reset();
  selection.downsample = 0;
  EXPECT_THAT(ErrorOf([&] { SelectGprTrainingData(log, selection); }), HasSubstr("downsample must be >= 1"));

  // Prediction: missing columns name the source; an existing "mean" column is not overwritten.
  selection.downsample = 1;
  GprFitOptions options;
  options.restarts = 0;
  const GprModel model = FitGprToLog(log, selection, options);
  EXPECT_THAT(ErrorOf([&] { PredictGprOnLog(model, log, "x", "velocity_m_s"); }),
              HasSubstr("<memory>: no column 'x'; the columns present are: "));
  MeasurementLog clash = log;
  clash.AddColumn("mean", Eigen::VectorXd::Zero(log.rows()));
  EXPECT_THAT(ErrorOf([&] { PredictGprOnLog(model, clash); }),
              HasSubstr("<memory>: already has a column \"mean\", which the prediction would write"));
}

// Issue 30: a column a GP cannot be scaled to is named with the fix, not as "DefaultGprPriors: the trained position
// range (max x − min x) must be finite and > 0, got 0.000000".
TEST_F(GprLog, AColumnThatDoesNotVaryOrOverflowsIsNamedWithTheFix) {
  const MeasurementLog log = SyntheticLog();
  const Eigen::Index n = log.rows();
  GprTrainingSelection selection;
  selection.disturbance_column = "dob_N";
  GprFitOptions options;
  options.restarts = 0;
  const auto with = [&](const std::string& name, Eigen::VectorXd values) {
    std::vector<std::string> names = log.names();
    std::vector<Eigen::VectorXd> columns;
    for (const auto& c : names) columns.push_back(c == name ? values : log.column(c));
    return MeasurementLog(names, columns);
  };
  EXPECT_EQ(ErrorOf([&] { FitGprToLog(with("position_m", Eigen::VectorXd::Constant(n, 0.1)), selection, options); }),
            fmt::format("<memory>: column 'position_m' is constant (0.1 m) over the {} training rows: a GP learns "
                        "nothing from it; give a record in which it varies (a scan over the travel), or name another "
                        "column with --position-column",
                        n));
  EXPECT_THAT(ErrorOf([&] { FitGprToLog(with("dob_N", Eigen::VectorXd::Constant(n, 2.0)), selection, options); }),
              HasSubstr("<memory>: column 'dob_N' is constant (2) over the"));
  Eigen::VectorXd huge = log.column("velocity_m_s");
  huge(0) = -1e308;
  huge(1) = 1e308;
  EXPECT_THAT(ErrorOf([&] { FitGprToLog(with("velocity_m_s", huge), selection, options); }),
              HasSubstr("column 'velocity_m_s' spans [-1e+308, 1e+308] m/s over the"));
  // Positions of 1e300 m were fitted without a word (tests/hostile): beyond any stage's travel, refused.
  EXPECT_THAT(ErrorOf([&] { FitGprToLog(with("position_m", log.column("position_m") * 1e300), selection, options); }),
              HasSubstr("m over the " + std::to_string(n) + " training rows, beyond the 1e+06 m any stage moves"));
  // One scan velocity stays allowed (TrainedVelocityRange widens it).
  EXPECT_NO_THROW(SelectGprTrainingData(with("velocity_m_s", Eigen::VectorXd::Constant(n, 0.2)), selection));
}

}  // namespace
}  // namespace mb

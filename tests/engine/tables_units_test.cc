// The one CSV reader/writer (engine/csv.h), the table type (engine/table.h), the unit normaliser (engine/units.h)
// as parameters use it, and the one Fourier-series helper (models/physics/fourier_series.h).
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <numbers>
#include <string>
#include <vector>

#include <unistd.h>

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "engine/csv.h"
#include "engine/parameters.h"
#include "engine/table.h"
#include "engine/units.h"
#include "models/physics/cogging.h"
#include "models/physics/fourier_series.h"
#include "tests/error_message.h"

namespace mb {
namespace {

namespace fs = std::filesystem;
using ::testing::ElementsAre;

using ::mb::testing::ErrorOf;

fs::path WriteText(const std::string& name, const std::string& text) {
  const fs::path dir = fs::temp_directory_path() / ("mb_tables_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  const fs::path path = dir / name;
  std::ofstream(path, std::ios::binary) << text;
  return path;
}

// --- CSV ---------------------------------------------------------------------------------------------------------

TEST(CsvReader, QuotesCommasLineBreaksAndLineNumbers) {
  const std::string text = "\xEF\xBB\xBFid,\"na,me\"\r\n1,\"two\nlines\"\n\n 3 , \"say \"\"hi\"\"\"\n";
  CsvReader reader(text);
  CsvRecord r;
  ASSERT_TRUE(reader.Next(&r));
  EXPECT_THAT(r.cells, ElementsAre("id", "na,me"));
  EXPECT_EQ(r.line, 1u);
  ASSERT_TRUE(reader.Next(&r));
  EXPECT_THAT(r.cells, ElementsAre("1", "two\nlines"));
  EXPECT_EQ(r.line, 2u);
  ASSERT_TRUE(reader.Next(&r));
  EXPECT_TRUE(r.blank);
  EXPECT_EQ(r.line, 4u);
  ASSERT_TRUE(reader.Next(&r));
  EXPECT_THAT(r.cells, ElementsAre("3", "say \"hi\""));
  EXPECT_EQ(r.line, 5u);
  EXPECT_FALSE(reader.Next(&r));
}

TEST(CsvWriter, QuotesOnlyWhatMustBeQuotedAndReadsBack) {
  const std::vector<std::string> cells = {"plain", "a,b", "say \"hi\"", " padded", "two\nlines", ""};
  const std::string line = CsvLine(cells);
  EXPECT_EQ(line, "plain,\"a,b\",\"say \"\"hi\"\"\",\" padded\",\"two\nlines\",");
  EXPECT_EQ(SplitCsvLine(line), cells);
  std::string number;
  AppendCsvNumber(0.1, &number);
  EXPECT_EQ(number, "0.1");
}

TEST(Table, ReadsWritesAndRoundTripsWithQuotedNames) {
  Table t({"time_s", "force, N"}, {Eigen::Vector2d(0.0, 1e-3), Eigen::Vector2d(0.1, -2.5)}, "<memory>");
  const fs::path path = WriteText("round_trip.csv", "");
  WriteTable(t, path.string());
  EXPECT_EQ(TableCsv(t), "time_s,\"force, N\"\n0,0.1\n0.001,-2.5\n");
  const Table back = ReadTable(path.string());
  EXPECT_EQ(back.names(), t.names());
  EXPECT_EQ(back.column("force, N"), t.column("force, N"));
  EXPECT_THAT(back.row_lines(), ElementsAre(2u, 3u));
}

TEST(Table, DropsPandasIndexOnlyWhenAsked) {
  const fs::path path = WriteText("pandas.csv", ",x,y\n0,1.5,2\n1,2.5,3\n");
  TableReadOptions options;
  EXPECT_EQ(ErrorOf([&] { ReadTable(path.string(), options); }),
            path.string() + ": line 1 (header): column 1 has no name; give every column a name");
  options.drop_unnamed_index = true;
  const Table t = ReadTable(path.string(), options);
  EXPECT_THAT(t.names(), ElementsAre("x", "y"));
  EXPECT_EQ(t.column("x")(1), 2.5);
}

TEST(Table, BadCellsNameFileLineAndColumn) {
  const fs::path path = WriteText("bad.csv", "a,b\n1,2\n3,x\n");
  EXPECT_EQ(ErrorOf([&] { ReadTable(path.string()); }),
            path.string() + ": line 3, column 'b': 'x' is not a number; write a decimal number such as 1.5e-3 "
                            "(dot as decimal separator, comma between cells)");
}

// --- units -------------------------------------------------------------------------------------------------------

TEST(Units, SpellingsOfOneUnitAreTheSame) {
  EXPECT_TRUE(SameUnit("N*s/m", "N·s/m"));
  EXPECT_TRUE(SameUnit("N s/m", "N*s/m"));
  EXPECT_TRUE(SameUnit("kg/s", "N*s/m"));
  EXPECT_TRUE(SameUnit("m/s2", "m/s^2"));
  EXPECT_TRUE(SameUnit("m/s²", "m/s^2"));
  EXPECT_FALSE(SameUnit("mm", "m"));
  EXPECT_FALSE(SameUnit("N", "kg"));
  EXPECT_TRUE(PortAcceptsUnit("N·s/m", "N*s/m"));
  EXPECT_DOUBLE_EQ(*UnitFactor("µm", "m"), 1e-6);
  EXPECT_DOUBLE_EQ(*UnitFactor("um", "m"), 1e-6);
  EXPECT_DOUBLE_EQ(*UnitFactor("deg", "rad"), std::numbers::pi / 180.0);
  EXPECT_DOUBLE_EQ(*UnitFactor("rev", "rad"), 2.0 * std::numbers::pi);
  EXPECT_DOUBLE_EQ(*UnitFactor("ms", "s"), 1e-3);
  EXPECT_DOUBLE_EQ(*UnitFactor("g", "kg"), 1e-3);
  EXPECT_FALSE(UnitFactor("rad", "m"));
  EXPECT_FALSE(UnitFactor("furlong", "m"));
}

const std::vector<ParamSpec>& Specs() {
  static const std::vector<ParamSpec> specs = {
      Required("pitch", "m", "pole pitch"), Optional("damping", 3.0, "N*s/m", "viscous damping"),
      Optional("mass", 1.0, "kg", "moving mass"), Optional("angles", nlohmann::json::array(), "rad", "phases",
                                                          ParamType::kVector),
      Optional("gain", 1.0, "", "a plain number")};
  return specs;
}

TEST(ParameterUnits, ConvertToTheDeclaredSiUnit) {
  std::vector<std::string> errors;
  const auto p = ValidateParameters(Specs(),
                                    {{"pitch", {{"value", 22.5}, {"unit", "mm"}}},
                                     {"damping", {{"value", 4.0}, {"unit", "N·s/m"}}},
                                     {"mass", {{"value", 94.0}, {"unit", "g"}}},
                                     {"angles", {{"value", {90.0, 180.0}}, {"unit", "deg"}}}},
                                    "/elements/0/parameters", &errors);
  ASSERT_TRUE(errors.empty()) << errors.front();
  EXPECT_DOUBLE_EQ(p.at("pitch").get<double>(), 0.0225);
  EXPECT_EQ(p.at("damping").get<double>(), 4.0);
  EXPECT_DOUBLE_EQ(p.at("mass").get<double>(), 0.094);
  EXPECT_DOUBLE_EQ(p.at("angles")[1].get<double>(), std::numbers::pi);
  const auto q = ValidateParameters(Specs(),
                                    {{"pitch", {{"value", 5.0}, {"unit", "um"}}},
                                     {"damping", {{"value", 4.0}, {"unit", "N s/m"}}},
                                     {"angles", {{"value", {1.0}}, {"unit", "rev"}}}},
                                    "/elements/0/parameters", &errors);
  ASSERT_TRUE(errors.empty()) << errors.front();
  EXPECT_DOUBLE_EQ(q.at("pitch").get<double>(), 5e-6);
  EXPECT_EQ(q.at("damping").get<double>(), 4.0);
  EXPECT_DOUBLE_EQ(q.at("angles")[0].get<double>(), 2.0 * std::numbers::pi);
}

TEST(ParameterUnits, IncompatibleOrUnitOnAPlainNumberIsRefused) {
  std::vector<std::string> errors;
  ValidateParameters(Specs(),
                     {{"pitch", {{"value", 1.0}, {"unit", "s"}}},
                      {"mass", {{"value", 1.0}, {"unit", "N"}}},
                      {"gain", {{"value", 2.0}, {"unit", "m"}}}},
                     "/elements/0/parameters", &errors);
  ASSERT_EQ(errors.size(), 3u);
  EXPECT_EQ(errors[0], "/elements/0/parameters/pitch: unit mismatch: given 's', this parameter is in 'm' (SI)");
  EXPECT_EQ(errors[1], "/elements/0/parameters/mass: unit mismatch: given 'N', this parameter is in 'kg' (SI)");
  EXPECT_EQ(errors[2],
            "/elements/0/parameters/gain: this parameter has no unit (a plain number), but \"unit\": \"m\" is given; "
            "remove the unit");
}

// --- Fourier series ----------------------------------------------------------------------------------------------

TEST(FourierSeries, OneHelperForBlocksCoggingAndTheGp) {
  const Eigen::Vector3d a(0.5, -0.2, 0.1), b(0.3, 0.05, -0.4);
  const double theta = 0.7;
  double direct = 0.0;
  for (int h = 1; h <= 3; ++h) direct += a(h - 1) * std::cos(h * theta) + b(h - 1) * std::sin(h * theta);
  EXPECT_NEAR(FourierSeries(a, b, theta), direct, 1e-15);

  // The cogging shape Σ r_h sin(hθ + φ_h) is the series with a_h = r_h sin φ_h, b_h = r_h cos φ_h, exactly.
  CoggingParameters c;
  c.pole_pitch = 0.0225;
  c.harmonics = Eigen::Vector3d(1.0, 0.25, 0.1);
  c.phases = Eigen::Vector3d(0.3, -1.0, 2.0);
  const CoggingForce cogging(c);
  const Eigen::VectorXd sa = c.harmonics.array() * c.phases.array().sin();
  const Eigen::VectorXd sb = c.harmonics.array() * c.phases.array().cos();
  const double x = 0.0131;
  EXPECT_EQ(cogging.Shape(x), FourierSeries(sa, sb, 2.0 * std::numbers::pi / c.pole_pitch * x));

  // Four lanes (the GP's features) agree with one lane to rounding.
  const int n = 23;
  Eigen::VectorXd one(2 * n), four(2 * n);
  ForEachHarmonic<1>(std::cos(theta), std::sin(theta), n, [&](int h, double cs, double sn, int) {
    one(2 * (h - 1)) = cs;
    one(2 * (h - 1) + 1) = sn;
  });
  ForEachHarmonic<4>(std::cos(theta), std::sin(theta), n, [&](int h, double cs, double sn, int) {
    four(2 * (h - 1)) = cs;
    four(2 * (h - 1) + 1) = sn;
  });
  for (int h = 1; h <= n; ++h) {
    EXPECT_NEAR(one(2 * (h - 1)), std::cos(h * theta), 1e-13);
    EXPECT_NEAR(four(2 * (h - 1) + 1), std::sin(h * theta), 1e-13);
  }

  // The design matrix is the series' regressor: its columns times (a, b) interleaved give the series.
  const Eigen::Vector2d z(0.004, 0.0131);
  const Eigen::MatrixXd m = FourierDesignMatrix(z, 0.0225, 3);
  Eigen::VectorXd ab(6);
  ab << a(0), b(0), a(1), b(1), a(2), b(2);
  EXPECT_NEAR((m * ab)(1), FourierSeries(a, b, 2.0 * std::numbers::pi * z(1) / 0.0225), 1e-13);
  // Its recurrence over the harmonics stays on the directly evaluated angle far from z = 0 (a time-periodic regressor
  // over 2,000 cycles) and at the tenth harmonic, scaled or not.
  const Eigen::VectorXd t = Eigen::VectorXd::LinSpaced(501, 0.0, 100.0);
  const Eigen::VectorXd g = Eigen::VectorXd::LinSpaced(501, -2.0, 3.0);
  const Eigen::MatrixXd plain = FourierDesignMatrix(t, 0.0497, 10), scaled = FourierDesignMatrix(t, 0.0497, 10, &g);
  for (Eigen::Index i = 0; i < t.size(); ++i) {
    for (int h = 1; h <= 10; ++h) {
      const double th = 2.0 * std::numbers::pi * h * t(i) / 0.0497;
      ASSERT_NEAR(plain(i, 2 * (h - 1)), std::cos(th), 1e-10) << "t = " << t(i) << ", h = " << h;
      ASSERT_NEAR(plain(i, 2 * (h - 1) + 1), std::sin(th), 1e-10) << "t = " << t(i) << ", h = " << h;
      ASSERT_NEAR(scaled(i, 2 * (h - 1) + 1), g(i) * std::sin(th), 3e-10) << "t = " << t(i) << ", h = " << h;
    }
  }
  // A period of 0 has no finite phase: NaN columns, as std::sin gives, never a NaN cast to an integer.
  EXPECT_TRUE(FourierDesignMatrix(z, 0.0, 2).array().isNaN().all());
  EXPECT_EQ(ErrorOf([] { FourierCoefficients(Eigen::VectorXd::Ones(2), "cos_coefficients", 3); }),
            "cos_coefficients has 2 entries; give one per harmonic (3) or []");
}

}  // namespace
}  // namespace mb

// A sweep's report.html (tools/report/sweep_report.h) holds what runs.csv holds: its table of runs is runs.csv cell
// for cell, every chart's embedded points are the "ok" runs' (parameter, metric) pairs, a failed run is listed with
// its error (escaped), a grid of two parameters gets one heat map per metric with each cell's value and a sweep of
// one parameter none; shards merged by sweep-merge get the whole sweep's report; the files it writes are those it
// declares (so `sweep` can refuse them over its inputs).
// HtmlReport::HeatMap's colour scale and shape check (tools/report/report.h).

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include <unistd.h>

#include <fmt/format.h>
#include <nlohmann/json.hpp>

#include "engine/csv.h"
#include "tests/tools/batch/sweep_test_files.h"
#include "tests/tools/report/report_test_files.h"
#include "tools/batch/shard.h"
#include "tools/batch/sweep.h"
#include "tools/report/output_files.h"
#include "tools/report/report.h"
#include "tools/report/sweep_report.h"

namespace mb {
namespace {

namespace fs = std::filesystem;
using json = nlohmann::json;
using ::testing::HasSubstr;
using ::testing::Not;
using report_test::Count;
using report_test::EmbeddedCharts;
using report_test::Read;

class SweepReportTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = fs::temp_directory_path() /
           ("mb_sweep_report_" + std::string(::testing::UnitTest::GetInstance()->current_test_info()->name()) + "_" +
            std::to_string(::getpid()));
    fs::remove_all(dir_);
    fs::create_directories(dir_);
    diagram_ = dir_ / "gain.json";
    std::ofstream(diagram_) << mb::testing::GainDiagram().dump(2);
  }
  void TearDown() override { fs::remove_all(dir_); }

  // Runs `sweep` (its JSON) over the gain diagram (y = K·c; metrics y_final, c_final) into dir_/name; the report.
  std::string Sweep(const std::string& sweep, const std::string& name) {
    SweepOptions options;
    options.progress = false;
    out_ = dir_ / name;
    RunSweep(diagram_, ParseSweep(json::parse(sweep), "s.json"), out_, options);
    return Read(out_ / "report.html");
  }

  fs::path dir_, diagram_, out_;
};

std::string Unescape(std::string text) {
  for (const auto& [from, to] : std::vector<std::pair<std::string, std::string>>{
           {"&lt;", "<"}, {"&gt;", ">"}, {"&quot;", "\""}, {"&amp;", "&"}}) {
    for (auto at = text.find(from); at != std::string::npos; at = text.find(from, at + to.size())) {
      text.replace(at, from.size(), to);
    }
  }
  return text;
}

// The cells of the HTML table starting at `at` (<th> and <td> alike), row by row, unescaped.
std::vector<std::vector<std::string>> TableAt(const std::string& html, std::size_t at) {
  const std::size_t end = html.find("</table>", at);
  std::vector<std::vector<std::string>> rows;
  for (std::size_t tr = html.find("<tr>", at); tr < end; tr = html.find("<tr>", tr + 1)) {
    const std::size_t tr_end = html.find("</tr>", tr);
    std::vector<std::string> cells;
    for (std::size_t c = html.find("<t", tr + 4); c < tr_end; c = html.find("<t", c + 1)) {
      const std::size_t open = html.find('>', c) + 1, close = html.find("</t", open);
      cells.push_back(Unescape(html.substr(open, close - open)));
      c = close;
    }
    rows.push_back(cells);
  }
  return rows;
}

// The section under the heading `title` (up to the next heading).
std::string Section(const std::string& html, const std::string& title) {
  const std::size_t at = html.find("<h2>" + title + "</h2>");
  if (at == std::string::npos) return {};
  return html.substr(at, html.find("<h2>", at + 4) - at);
}

TEST_F(SweepReportTest, TablesAndChartsHoldRunsCsvAndTheFailedRunIsListed) {
  // Run 0002 fails (a negative stop time is refused by the loader); the others give y_final = 2·K.
  const std::string html = Sweep(R"({"list": [{"k.gain": 1}, {"k.gain": 3},
      {"k.gain": 2, "defaultExperiment.stopTime": -1}, {"k.gain": 0.5}]})", "list");
  const CsvTextTable csv = ReadCsvTextTable((out_ / "runs.csv").string());
  ASSERT_EQ(csv.rows.size(), 4u);
  ASSERT_EQ(csv.rows[2][1], "failed");

  // The table of runs is runs.csv, header and cells.
  const std::string runs = Section(html, "Runs (runs.csv)");
  ASSERT_FALSE(runs.empty());
  std::vector<std::vector<std::string>> expected = {csv.header};
  expected.insert(expected.end(), csv.rows.begin(), csv.rows.end());
  EXPECT_EQ(TableAt(runs, runs.find("<table>")), expected);

  // The failed run with its values and error, and only it.
  const std::string failures = Section(html, "Failed runs");
  const auto failed = TableAt(failures, failures.find("<table>"));
  ASSERT_EQ(failed.size(), 2u);
  EXPECT_EQ(failed[1].front(), "0002");
  EXPECT_EQ(failed[1].back(), csv.rows[2].back());
  EXPECT_FALSE(failed[1].back().empty());
  EXPECT_THAT(html, Not(HasSubstr("mb-heatmap"))) << "a list is no grid";

  // Each chart of y_final against k.gain: the ok runs' (K, y_final) from runs.csv, sorted by K (to 7 digits).
  const json charts = EmbeddedCharts(html);
  if (charts.is_null()) GTEST_SKIP() << "no charting library at " << kDygraphsPath << ": no chart data embedded";
  const auto gain = std::find(csv.header.begin(), csv.header.end(), "k.gain") - csv.header.begin();
  const auto y_final = std::find(csv.header.begin(), csv.header.end(), "y_final") - csv.header.begin();
  std::vector<std::pair<double, double>> points;
  for (const auto& row : csv.rows) {
    if (row[1] == "ok") points.emplace_back(std::stod(row[static_cast<std::size_t>(gain)]),
                                            std::stod(row[static_cast<std::size_t>(y_final)]));
  }
  std::sort(points.begin(), points.end());
  ASSERT_EQ(points.size(), 3u);
  const auto chart = std::find_if(charts.begin(), charts.end(),
                                  [](const json& c) { return c.value("title", std::string()) == "y_final against k.gain"; });
  ASSERT_NE(chart, charts.end()) << charts.dump();
  ASSERT_EQ((*chart)["data"].size(), points.size());
  for (std::size_t i = 0; i < points.size(); ++i) {
    EXPECT_NEAR((*chart)["data"][i][0].get<double>(), points[i].first, 1e-6 * std::abs(points[i].first));
    EXPECT_NEAR((*chart)["data"][i][1].get<double>(), points[i].second, 1e-6 * std::abs(points[i].second));
  }
  EXPECT_EQ(points[2].second, 6.0) << "y_final = K·c with c = 2";
  // defaultExperiment.stopTime is assigned only by the failed run: nothing to draw against it, said in words.
  EXPECT_THAT(html, HasSubstr("y_final against defaultExperiment.stopTime: no run"));
}

TEST_F(SweepReportTest, TwoParameterGridGetsAHeatMapPerMetricAndOneParameterNone) {
  const std::string grid = Sweep(R"({"grid": {"c.value": [1, 2], "k.gain": [1, 2, 3]}})", "grid");
  EXPECT_EQ(Count(grid, "<table class=\"mb-heatmap\">"), 2u) << "one per metric (y_final, c_final)";
  // y_final's map: rows c.value, columns k.gain, each cell c·K as runs.csv has it.
  const std::size_t at = grid.find("<table class=\"mb-heatmap\"><caption>y_final");
  ASSERT_NE(at, std::string::npos);
  const auto cells = TableAt(grid, at);
  ASSERT_EQ(cells.size(), 3u);
  EXPECT_EQ(cells[0], (std::vector<std::string>{"c.value ↓ · k.gain →", "1", "2", "3"}));
  EXPECT_EQ(cells[1], (std::vector<std::string>{"1", "1", "2", "3"}));
  EXPECT_EQ(cells[2], (std::vector<std::string>{"2", "2", "4", "6"}));
  EXPECT_THAT(Section(grid, "Failed runs"), HasSubstr("No run failed."));

  const std::string one = Sweep(R"({"grid": {"k.gain": [1, 2, 3]}})", "one");
  EXPECT_THAT(one, HasSubstr("<h2>Metrics against the swept parameters</h2>"));
  EXPECT_THAT(one, Not(HasSubstr("mb-heatmap")));
  const std::string random = Sweep(R"({"random": {"seed": 1, "samples": 4, "parameters":
      {"c.value": {"uniform": [1, 2]}, "k.gain": {"uniform": [1, 2]}}}})", "random");
  EXPECT_THAT(random, Not(HasSubstr("mb-heatmap"))) << "two parameters, but no grid";
}

TEST_F(SweepReportTest, MergedShardsGetTheReportOfTheWholeSweep) {
  const std::string sweep = R"({"grid": {"c.value": [1, 2], "k.gain": [1, 2, 3]}})";
  const std::string whole = Sweep(sweep, "whole");
  SweepOptions options;
  options.progress = false;
  const SweepSpec spec = ParseSweep(json::parse(sweep), "s.json");
  RunSweepShard(diagram_, spec, {0, 2}, dir_ / "s0", options);
  RunSweepShard(diagram_, spec, {1, 2}, dir_ / "s1", options);
  MergeSweepShards({dir_ / "s1", dir_ / "s0"}, dir_ / "merged");
  const std::string merged = Read(dir_ / "merged" / "report.html");
  const std::string heat = "Heat maps over c.value × k.gain";
  ASSERT_THAT(Section(whole, heat), HasSubstr("mb-heatmap"));
  EXPECT_EQ(Section(merged, heat), Section(whole, heat)) << "the same values, the same colours";
  const CsvTextTable csv = ReadCsvTextTable((dir_ / "merged" / "runs.csv").string());
  std::vector<std::vector<std::string>> expected = {csv.header};
  expected.insert(expected.end(), csv.rows.begin(), csv.rows.end());
  const std::string runs = Section(merged, "Runs (runs.csv)");
  EXPECT_EQ(TableAt(runs, runs.find("<table>")), expected);
}

TEST_F(SweepReportTest, WritesOnlyTheFilesItDeclares) {
  Sweep(R"({"grid": {"c.value": [1, 2], "k.gain": [1, 2]}})", "grid");
  const std::vector<std::string> names = SweepReportFileNames();
  std::size_t figures = 0;
  for (const auto& entry : fs::recursive_directory_iterator(out_)) {
    if (!entry.is_regular_file()) continue;
    const std::string name = fs::relative(entry.path(), out_).generic_string();
    if (name == "runs.csv" || name == "runs.json") continue;
    if (FileNameMatches(name, "sweep_*.png")) ++figures;
    EXPECT_TRUE(std::any_of(names.begin(), names.end(), [&](const auto& n) { return FileNameMatches(name, n); }))
        << name << " is not among SweepReportFileNames()";
  }
  EXPECT_EQ(figures, 4u) << "2 metrics × 2 parameters (gnuplot missing?)";
}

TEST_F(SweepReportTest, EscapesWhatRunsCsvHoldsAndRefusesAnotherTable) {
  const fs::path out = dir_ / "written";
  fs::create_directories(out);
  std::ofstream(out / "runs.csv") << "id,status,a.x,m,wall_time_s,error\n"
                                  << "0000,ok,1,0.5,0.1,\n"
                                  << "0001,failed,2,,0.1,\"</script><script>alert(1)</script>\"\n";
  const json head = {{"kind", "list"}, {"parameters", {"a.x"}}, {"metric_units", {{"m", "m"}}}};
  WriteSweepReport(out, head);
  const std::string html = Read(out / "report.html");
  EXPECT_THAT(html, HasSubstr("<td>&lt;/script&gt;&lt;script&gt;alert(1)&lt;/script&gt;</td>"));
  EXPECT_THAT(html, Not(HasSubstr("<script>alert")));

  const json other = {{"kind", "list"}, {"parameters", {"b.y"}}};
  EXPECT_THROW(WriteSweepReport(out, other), std::runtime_error);
  EXPECT_THROW(WriteSweepReport(dir_ / "missing", head), std::runtime_error);
}

TEST(HtmlReportHeatMap, ColoursByValueAndRefusesAWrongShape) {
  const fs::path dir = fs::temp_directory_path() / ("mb_heatmap_" + std::to_string(::getpid()));
  fs::create_directories(dir);
  HtmlReport report("heat");
  report.HeatMap("m [s]", "a", {"1"}, "b", {"x", "y", "z"}, {{0.0, 2.0, std::nan("")}}, {{"0", "2", "failed"}});
  EXPECT_THROW(report.HeatMap("m", "a", {"1", "2"}, "b", {"x"}, {{0.0}}, {{"0"}}), std::invalid_argument);
  report.Write(dir / "report.html");
  std::ifstream in(dir / "report.html");
  const std::string html((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  EXPECT_THAT(html, HasSubstr("<td style=\"background:#440154;color:#fff\">0</td>")) << "smallest: viridis' start";
  EXPECT_THAT(html, HasSubstr("<td style=\"background:#fde725;color:#000\">2</td>")) << "largest: viridis' end";
  EXPECT_THAT(html, HasSubstr("<td style=\"background:#ddd;color:#555\">failed</td>"));
  fs::remove_all(dir);
}

}  // namespace
}  // namespace mb

// Interactive reports (tools/report/report.h, chart_data.h): the decimation keeps every peak (a plain stride would
// not), the page embeds the charting library and the data in one file with every user text escaped (a hostile name
// closes no <script>), the full data is in a CSV beside it, and without the library the page falls back to the PNGs
// and says why.

#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include <unistd.h>

#include "tests/tools/report/report_test_files.h"
#include "tools/report/chart_data.h"
#include "tools/report/report.h"
#include "tools/report/run_program.h"

namespace mb {
namespace {

namespace fs = std::filesystem;
using ::testing::HasSubstr;
using ::testing::Not;

constexpr const char* kHostile = "</script><script>alert(1)</script>";

using report_test::Count;
using report_test::Folder;
using report_test::Read;

// A noisy record of n samples with isolated spikes (up and down, one per chosen pixel column at most) at random
// places: the spikes' indices are returned through `spikes`.
std::vector<double> SpikyRecord(std::size_t n, std::size_t columns, std::size_t count, std::vector<std::size_t>* spikes) {
  std::mt19937 rng(27);
  std::normal_distribution<double> noise(0.0, 0.1);
  std::vector<double> y(n);
  for (std::size_t i = 0; i < n; ++i) y[i] = std::sin(1e-4 * static_cast<double>(i)) + noise(rng);
  std::uniform_int_distribution<std::size_t> where(0, n - 1);
  std::vector<char> column_used(columns, 0);
  while (spikes->size() < count) {
    const std::size_t i = where(rng), c = i * columns / n;
    // One spike per column and none in the columns beside it: a column's min/max is what a pixel shows.
    if (column_used[c] || (c > 0 && column_used[c - 1]) || (c + 1 < columns && column_used[c + 1])) continue;
    column_used[c] = 1;
    y[i] += (spikes->size() % 2 ? -1.0 : 1.0) * (3.0 + 0.01 * static_cast<double>(spikes->size()));
    spikes->push_back(i);
  }
  return y;
}

TEST(DecimateMinMax, KeepsEverySpikeOfAMillionSamplesWhereAStrideLosesThem) {
  const std::size_t n = 1'000'003, columns = 2000;
  std::vector<std::size_t> spikes;
  const std::vector<double> y = SpikyRecord(n, columns, 300, &spikes);
  const std::vector<std::size_t> kept = DecimateMinMax(y, columns);
  EXPECT_LE(kept.size(), 2 * columns + 2);
  EXPECT_TRUE(std::is_sorted(kept.begin(), kept.end()));
  EXPECT_EQ(std::adjacent_find(kept.begin(), kept.end()), kept.end()) << "an index kept twice";
  EXPECT_EQ(kept.front(), 0u);
  EXPECT_EQ(kept.back(), n - 1);
  for (std::size_t i : spikes) EXPECT_TRUE(std::binary_search(kept.begin(), kept.end(), i)) << "spike at " << i;
  // The same budget taken as a stride loses most of them: the test above can fail.
  std::size_t seen_by_stride = 0;
  const std::size_t stride = n / kept.size();
  for (std::size_t i : spikes) seen_by_stride += (i % stride == 0);
  EXPECT_LT(seen_by_stride, spikes.size() / 10);
  // Every column's extremes are among the kept samples (what a pixel column shows is unchanged).
  for (std::size_t c = 0; c < columns; ++c) {
    const auto lo = y.begin() + static_cast<std::ptrdiff_t>(c * n / columns);
    const auto hi = y.begin() + static_cast<std::ptrdiff_t>((c + 1) * n / columns);
    const auto imax = static_cast<std::size_t>(std::max_element(lo, hi) - y.begin());
    const auto imin = static_cast<std::size_t>(std::min_element(lo, hi) - y.begin());
    ASSERT_TRUE(std::binary_search(kept.begin(), kept.end(), imax)) << "column " << c;
    ASSERT_TRUE(std::binary_search(kept.begin(), kept.end(), imin)) << "column " << c;
  }
}

TEST(DecimateMinMax, ANonFiniteSampleHidesNoPeakAndShortRecordsAreKeptWhole) {
  std::vector<double> y(1000, 0.0);
  y[0] = std::nan("");
  y[3] = 7.0;  // column 0 holds samples 0..9
  const std::vector<std::size_t> kept = DecimateMinMax(y, 100);
  EXPECT_TRUE(std::binary_search(kept.begin(), kept.end(), std::size_t{3}));
  EXPECT_EQ(DecimateMinMax(std::vector<double>(150, 1.0), 100).size(), 150u);
  EXPECT_TRUE(DecimateMinMax({}, 100).empty());
}

TEST(DecimateScatter, KeepsTheEnvelopeAndBoundsTheCount) {
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const std::size_t n = 200'000;
  std::vector<double> x(n), y(n);
  for (std::size_t i = 0; i < n; ++i) {
    x[i] = u(rng);
    y[i] = std::sin(20.0 * x[i]) + 0.1 * u(rng);
  }
  y[12345] = 5.0;   // an outlier above
  y[54321] = -5.0;  // and below
  x[777] = std::nan("");
  const std::vector<std::size_t> kept = DecimateScatter(x, y, 600, 150);
  EXPECT_LE(kept.size(), 600u * 150u + 2u * 600u);
  EXPECT_LT(kept.size(), n / 2);
  EXPECT_TRUE(std::binary_search(kept.begin(), kept.end(), std::size_t{12345}));
  EXPECT_TRUE(std::binary_search(kept.begin(), kept.end(), std::size_t{54321}));
  EXPECT_FALSE(std::binary_search(kept.begin(), kept.end(), std::size_t{777}));
}

TEST(ChartJson, AMillionSampleRecordBecomesAFewThousandRowsWithItsSpikes) {
  const std::size_t n = 1'000'000;
  std::vector<std::size_t> spikes;
  Series s;
  s.y = SpikyRecord(n, 2000, 50, &spikes);
  s.x.resize(n);
  for (std::size_t i = 0; i < n; ++i) s.x[i] = 1e-3 * static_cast<double>(i);
  s.label = "measured";
  Figure f{"r.png", "r", "time [s]", "force [N]", {s}};
  const nlohmann::json chart = ChartJson(f, "r.csv", 2000);
  EXPECT_LE(chart["data"].size(), 4002u);
  EXPECT_TRUE(chart["decimated"].get<bool>());
  EXPECT_EQ(chart["samples"].get<std::size_t>(), n);
  double top = -1e9;
  for (const auto& row : chart["data"]) top = std::max(top, row[1].get<double>());
  EXPECT_NEAR(top, *std::max_element(s.y.begin(), s.y.end()), 1e-6);
}

// Each series says how it is drawn: dots, steps, or a line with a marker at each point (gnuplot's linespoints, e.g.
// resid's correlations: a marker per lag), which the chart drew as a bare line.
TEST(ChartJson, SaysPerSeriesWhetherItIsDotsStepsOrMarkedLine) {
  const std::vector<double> x{0.0, 1.0, 2.0};
  Figure f{"styles.png", "styles", "lag", "ρ",
           {{x, {1.0, 0.5, 0.2}, "correlation", "linespoints"}, {x, {0.1, 0.1, 0.1}, "band", "lines"},
            {x, {0.3, 0.2, 0.1}, "samples", "dots"}, {x, {2.0, 1.0, 0.0}, "histogram", "steps"}}};
  const nlohmann::json chart = ChartJson(f, "styles.csv", 2000);
  EXPECT_EQ(chart["markers"], nlohmann::json::array({true, false, false, false}));
  EXPECT_EQ(chart["points"], nlohmann::json::array({false, false, true, false}));
  EXPECT_EQ(chart["steps"], nlohmann::json::array({false, false, false, true}));
}

// A figure whose every text is hostile, on a time axis shared by two series.
Figure HostileFigure() {
  Series a{{0.0, 0.5, 1.0, 1.5}, {1.25, -2.5, 3.75, 4.0}, kHostile, "lines"};
  Series b{{0.0, 0.5, 1.0, 1.5}, {0.0, 1.0, 0.0, -1.0}, "model \"x\" & <y>", "lines"};
  Figure f{"hostile.png", kHostile, kHostile, "force [N]", {a, b}};
  f.x_link = "time";
  f.x_marks = {{0.5, kHostile}};
  return f;
}

TEST(HtmlReport, EmbedsTheLibraryAndTheDataAndEscapesAHostileName) {
  const fs::path dir = Folder("mb_interactive_embed");
  // A stand-in for the library that holds what an inline script must not: "</script>" in a string.
  const fs::path library = dir / "lib" / "dygraph.min.js";
  fs::create_directories(library.parent_path());
  std::ofstream(library) << "/* Dygraph stand-in */ window.Dygraph = function () { var s = '</SCRIPT>'; };\n"
                            "//# sourceMappingURL=dygraph.min.js.map\n";
  HtmlReport report(kHostile, InteractiveCharts{library, 2000});
  report.Paragraph(kHostile);
  report.AddFigure(HostileFigure(), dir);
  report.Write(dir / "report.html");
  const std::string page = Read(dir / "report.html");
  // Three scripts: the library, the data, the page's; no other element opens or closes one.
  EXPECT_EQ(Count(page, "<script"), 3u);
  EXPECT_EQ(Count(page, "</script>"), 3u);
  EXPECT_THAT(page, Not(HasSubstr("</SCRIPT>")));
  EXPECT_THAT(page, HasSubstr("window.Dygraph = function () { var s = '<\\/SCRIPT>'; };"));
  EXPECT_THAT(page, Not(HasSubstr("sourceMappingURL")));
  EXPECT_THAT(page, Not(HasSubstr("<script>alert(1)")));
  EXPECT_THAT(page, HasSubstr("&lt;/script&gt;&lt;script&gt;alert(1)&lt;/script&gt;"));  // title, paragraph
  EXPECT_THAT(page, HasSubstr("\\u003c/script>\\u003cscript>alert(1)\\u003c/script>"));  // labels in the data
  EXPECT_THAT(page, HasSubstr("[0.5,-2.5,1.0]"));  // a row: x, then each series
  EXPECT_THAT(page, HasSubstr("<a href=\"hostile.full.csv\">hostile.full.csv</a>"));
  // The full data beside the report, texts quoted.
  const std::string csv = Read(dir / "hostile.full.csv");
  EXPECT_THAT(csv, HasSubstr("\"model \"\"x\"\" & <y>\""));
  EXPECT_THAT(csv, HasSubstr("\n0.5,-2.5,1\n"));
  EXPECT_EQ(Count(csv, "\n"), 5u);
}

TEST(HtmlReport, EmbedsTheInstalledDygraphs) {
  if (!fs::exists(kDygraphsPath)) GTEST_SKIP() << kDygraphsPath << " missing: apt-get install libjs-dygraphs";
  const fs::path dir = Folder("mb_interactive_dygraphs");
  HtmlReport report("r", InteractiveCharts{});
  report.AddFigure(HostileFigure(), dir);
  report.Write(dir / "report.html");
  const std::string page = Read(dir / "report.html");
  EXPECT_GT(page.size(), 100'000u);
  EXPECT_THAT(page, HasSubstr("@license https://github.com/danvk/dygraphs"));
  EXPECT_EQ(Count(page, "</script>"), 3u);
}

TEST(HtmlReport, WithoutTheLibraryShowsThePngsAndSaysWhy) {
  const fs::path dir = Folder("mb_interactive_fallback");
  const fs::path missing = dir / "no" / "dygraph.min.js";
  HtmlReport report("r", InteractiveCharts{missing, 2000});
  report.AddFigure(HostileFigure(), dir);
  report.Write(dir / "report.html");
  const std::string page = Read(dir / "report.html");
  EXPECT_THAT(page, Not(HasSubstr("<script")));
  EXPECT_THAT(page, HasSubstr("Interactive charts unavailable: " + missing.string() +
                              " not found. Install Debian's libjs-dygraphs"));
  EXPECT_THAT(page, HasSubstr("<img class=\"mb-static\" loading=\"lazy\" src=\"hostile.png\""));
  EXPECT_TRUE(fs::exists(dir / "hostile.png")) << "the static figure (gnuplot) is drawn whatever the library";
  EXPECT_TRUE(fs::exists(dir / "hostile.full.csv"));
}

// A report draws at most MaxReportFigures() figures (issue 30: 20,000 logged signals started 20,000 gnuplots); the
// rest are listed by title, with the flag that raises the limit.
TEST(HtmlReport, DrawsAtMostTheSetNumberOfFiguresAndListsTheRest) {
  const fs::path dir = Folder("mb_report_figure_limit");
  EXPECT_EQ(MaxReportFigures(), kDefaultMaxReportFigures);
  EXPECT_THROW(SetMaxReportFigures(0), std::invalid_argument);
  SetMaxReportFigures(2);
  HtmlReport report("limited");
  for (int i = 0; i < 5; ++i) {
    Figure f{"f" + std::to_string(i) + ".png", "signal <" + std::to_string(i) + ">", "t [s]", "y", {}};
    f.series.push_back({{0.0, 1.0}, {0.0, double(i)}, "y", "lines"});
    report.AddFigure(f, dir);
  }
  report.Write(dir / "report.html");
  SetMaxReportFigures(kDefaultMaxReportFigures);
  EXPECT_TRUE(fs::exists(dir / "plot" / "f0.gp"));
  EXPECT_TRUE(fs::exists(dir / "plot" / "f1.gp"));
  EXPECT_FALSE(fs::exists(dir / "plot" / "f2.gp"));
  EXPECT_FALSE(fs::exists(dir / "f4.png"));
  EXPECT_THAT(Read(dir / "report.html"),
              HasSubstr("3 more figures not drawn: a report draws at most 2 (raise it with motionblocks --max-plots "
                        "N). Their data is in the command's files. Not drawn: signal &lt;2&gt;, signal &lt;3&gt;, "
                        "signal &lt;4&gt;."));
}

// Issue 28: a figure's script and data are in plot/ beside the PNG, named relative to the script, which goes to its
// own folder first: run from an unrelated working folder (RunProgram's working_directory), through an absolute path
// with a quote and a newline in it, it draws the same PNG again.
TEST(RenderFigure, WritesItsScriptIntoPlotAndTheScriptRerunsFromAnyFolder) {
  const fs::path dir = Folder("mb_render_rerun") / "out '\n\"x";
  const fs::path elsewhere = Folder("mb_render_rerun_cwd");
  Figure f{"f.png", "title", "t [s]", "y", {}};
  f.series.push_back({{0.0, 1.0, 2.0}, {0.0, 1.0, 0.5}, "y", "lines"});
  ASSERT_EQ(RenderFigure(f, dir), "");
  std::vector<std::string> top, plot;
  for (const auto& e : fs::directory_iterator(dir)) top.push_back(e.path().filename().string());
  for (const auto& e : fs::directory_iterator(dir / "plot")) plot.push_back(e.path().filename().string());
  std::sort(top.begin(), top.end());
  std::sort(plot.begin(), plot.end());
  EXPECT_EQ(top, (std::vector<std::string>{"f.png", "plot"}));
  EXPECT_EQ(plot, (std::vector<std::string>{"f.dat", "f.gp", "gnuplot.log"}));
  EXPECT_EQ(FigureFileNames("f.png"),
            (std::vector<std::string>{"f.png", "plot/f.dat", "plot/f.gp", "f.full.csv", "plot/gnuplot.log"}));
  const std::string script = Read(dir / "plot" / "f.gp");
  EXPECT_THAT(script, HasSubstr("set output \"../f.png\"\n"));
  EXPECT_THAT(script, HasSubstr("plot \"f.dat\" index 0"));
  EXPECT_THAT(script, Not(HasSubstr("mb_render_rerun")));  // no absolute path
  const std::string png = Read(dir / "f.png");
  ASSERT_GT(png.size(), 1000u);
  fs::remove(dir / "f.png");
  ASSERT_EQ(RunProgram({"gnuplot", (dir / "plot" / "f.gp").string()}, elsewhere / "log", elsewhere), 0)
      << Read(elsewhere / "log");
  EXPECT_EQ(Read(dir / "f.png"), png);
  EXPECT_FALSE(fs::exists(elsewhere / "f.png"));
  EXPECT_FALSE(fs::exists(elsewhere / ".." / "f.png"));
  // The working folder is the child's: a relative log name is still this process's.
  ASSERT_EQ(RunProgram({"pwd"}, "mb_render_rerun_pwd.log", dir / "plot"), 0);
  EXPECT_EQ(Read("mb_render_rerun_pwd.log"), fs::canonical(dir / "plot").string() + "\n");
  fs::remove("mb_render_rerun_pwd.log");
  EXPECT_EQ(RunProgram({"pwd"}, elsewhere / "log", dir / "no such folder"), -1);
  fs::remove_all(dir.parent_path());
  fs::remove_all(elsewhere);
}

}  // namespace
}  // namespace mb

// A sweep's report.html (sweep_report.h): runs.csv read back (the rows as the sweep wrote them), each parameter made an
// axis (numbers, or named categories), then the page in order: what was swept, each metric's extremes, the charts of
// every metric against every parameter, the heat maps of a two-parameter grid, the failed runs, the runs.
#include "tools/report/sweep_report.h"

#include <algorithm>
#include <cctype>
#include <charconv>
#include <cmath>
#include <map>
#include <optional>
#include <stdexcept>
#include <utility>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "engine/csv.h"
#include "tools/report/report.h"

namespace mb {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr const char* kFigurePrefix = "sweep_";
// Lines drawn in one chart of a two-parameter grid (one per value of the other parameter); with more, dots.
constexpr std::size_t kMaxLinesPerChart = 8;
// Characters of a metric's or a parameter's name kept in a figure's file name.
constexpr std::size_t kMaxNameInFile = 40;

// runs.csv as the report reads it: the columns split into parameters and metrics.
struct SweepTable {
  std::vector<std::string> header;
  std::vector<std::string> parameters;
  std::vector<std::string> metrics;
  std::vector<std::vector<std::string>> rows;  // each as long as the header (shorter ones, cut by a kill, left out)
  std::size_t parameter_column(std::size_t p) const { return 2 + p; }
  std::size_t metric_column(std::size_t m) const { return 2 + parameters.size() + m; }
  std::size_t error_column() const { return header.size() - 1; }
  bool ok(std::size_t r) const { return rows[r][1] == "ok"; }
};

SweepTable ReadSweepTable(const fs::path& csv, const json& runs_json) {
  const CsvTextTable text = ReadCsvTextTable(csv.string());
  SweepTable t;
  t.header = text.header;
  const json parameters = runs_json.value("parameters", json::array());
  if (parameters.is_array()) {
    for (const auto& p : parameters) t.parameters.push_back(p.is_string() ? p.get<std::string>() : p.dump());
  }
  const std::size_t p = t.parameters.size();
  const bool columns_ok = t.header.size() >= 4 + p && t.header[0] == "id" && t.header[1] == "status" &&
                          std::equal(t.parameters.begin(), t.parameters.end(), t.header.begin() + 2) &&
                          t.header[t.header.size() - 2] == "wall_time_s" && t.header.back() == "error";
  if (!columns_ok) {
    throw std::runtime_error(fmt::format("{} has the columns [{}]; a sweep's report needs id, status, the parameters "
                                         "[{}], the metrics, wall_time_s, error: not the runs.csv of this runs.json",
                                         csv.string(), fmt::join(t.header, ", "), fmt::join(t.parameters, ", ")));
  }
  t.metrics.assign(t.header.begin() + static_cast<std::ptrdiff_t>(2 + p), t.header.end() - 2);
  for (const auto& row : text.rows) {
    if (row.size() == t.header.size()) t.rows.push_back(row);
  }
  return t;
}

// A cell as a finite number; nullopt for anything else (empty, nan, text, trailing characters).
std::optional<double> FiniteNumber(const std::string& cell) {
  double value = 0.0;
  const auto [end, error] = std::from_chars(cell.data(), cell.data() + cell.size(), value);
  if (cell.empty() || error != std::errc() || end != cell.data() + cell.size() || !std::isfinite(value)) {
    return std::nullopt;
  }
  return value;
}

// A parameter as an x axis: its value in each row (nullopt: the row does not assign it), numbers as written or the
// index of a named category; its distinct values as written, in sweep order.
struct Axis {
  bool numeric = true;
  std::vector<std::string> values;  // distinct non-empty cells, in order of first appearance
  std::vector<std::optional<double>> x;
};

Axis ParameterAxis(const SweepTable& t, std::size_t p) {
  Axis axis;
  std::map<std::string, std::size_t> index;
  const std::size_t column = t.parameter_column(p);
  for (const auto& row : t.rows) {
    const std::string& cell = row[column];
    if (cell.empty()) continue;
    if (index.emplace(cell, axis.values.size()).second) axis.values.push_back(cell);
    axis.numeric = axis.numeric && FiniteNumber(cell).has_value();
  }
  for (const auto& row : t.rows) {
    const std::string& cell = row[column];
    if (cell.empty()) {
      axis.x.emplace_back();
    } else if (axis.numeric) {
      axis.x.push_back(FiniteNumber(cell));
    } else {
      axis.x.push_back(static_cast<double>(index.at(cell)));
    }
  }
  return axis;
}

std::string Unit(const json& runs_json, const std::string& metric) {
  const json units = runs_json.value("metric_units", json::object());
  const json unit = units.is_object() ? units.value(metric, json()) : json();
  return unit.is_string() ? unit.get<std::string>() : std::string();
}

std::string WithUnit(const std::string& name, const std::string& unit) {
  return unit.empty() ? name : fmt::format("{} [{}]", name, unit);
}

// A name as part of a file name: letters, digits, '.', '-' and '_' kept, anything else '_', at most kMaxNameInFile.
std::string FileNamePart(const std::string& name) {
  std::string out;
  for (char c : name.substr(0, kMaxNameInFile)) {
    const auto byte = static_cast<unsigned char>(c);
    const bool plain = byte < 0x80 && (std::isalnum(byte) != 0 || c == '.' || c == '-' || c == '_');
    out += plain ? c : '_';
  }
  return out;
}

// The value of each "ok" row's metric m (nullopt: failed, empty, or not a finite number).
std::vector<std::optional<double>> MetricValues(const SweepTable& t, std::size_t m) {
  std::vector<std::optional<double>> y;
  for (std::size_t r = 0; r < t.rows.size(); ++r) {
    y.push_back(t.ok(r) ? FiniteNumber(t.rows[r][t.metric_column(m)]) : std::nullopt);
  }
  return y;
}

// A series of the rows `rows` (x and y both known), sorted by x; a line through them when their x are distinct.
Series RowsSeries(const std::vector<std::size_t>& rows, const Axis& axis, const std::vector<std::optional<double>>& y,
                  std::string label) {
  std::vector<std::pair<double, double>> points;
  for (std::size_t r : rows) {
    if (axis.x[r] && y[r]) points.emplace_back(*axis.x[r], *y[r]);
  }
  std::stable_sort(points.begin(), points.end(), [](const auto& a, const auto& b) { return a.first < b.first; });
  const bool distinct = std::adjacent_find(points.begin(), points.end(), [](const auto& a, const auto& b) {
                          return a.first == b.first;
                        }) == points.end();
  Series s{{}, {}, std::move(label), distinct && points.size() > 1 ? "linespoints" : "points"};
  for (const auto& [x, v] : points) {
    s.x.push_back(x);
    s.y.push_back(v);
  }
  return s;
}

// The series of metric y against parameter p: one per value of the other parameter of a two-parameter grid (at most
// kMaxLinesPerChart), else one of every run.
std::vector<Series> MetricSeries(const SweepTable& t, bool two_parameter_grid, std::size_t p, const Axis& axis,
                                 const std::vector<Axis>& axes, const std::vector<std::optional<double>>& y) {
  const std::size_t other = p == 0 ? 1 : 0;
  if (two_parameter_grid && axes[other].values.size() <= kMaxLinesPerChart) {
    std::vector<Series> series;
    for (const std::string& value : axes[other].values) {
      std::vector<std::size_t> rows;
      for (std::size_t r = 0; r < t.rows.size(); ++r) {
        if (t.rows[r][t.parameter_column(other)] == value) rows.push_back(r);
      }
      series.push_back(RowsSeries(rows, axis, y, fmt::format("{} = {}", t.parameters[other], value)));
    }
    return series;
  }
  std::vector<std::size_t> rows(t.rows.size());
  for (std::size_t r = 0; r < rows.size(); ++r) rows[r] = r;
  return {RowsSeries(rows, axis, y, "runs")};
}

// What was swept, how many runs failed, what every run shares.
void AddSummary(const SweepTable& t, const json& runs_json, HtmlReport* report) {
  const std::string description = runs_json.value("description", json()).is_string()
                                      ? runs_json["description"].get<std::string>()
                                      : std::string();
  if (!description.empty()) report->Paragraph(description);
  const auto failed = static_cast<std::size_t>(
      std::count_if(t.rows.begin(), t.rows.end(), [](const auto& row) { return row[1] != "ok"; }));
  std::vector<std::string> metrics;
  for (const auto& m : t.metrics) metrics.push_back(WithUnit(m, Unit(runs_json, m)));
  const json kind = runs_json.value("kind", json());
  const json diagram = runs_json.value("diagram", json());
  report->Paragraph(fmt::format("A {} sweep{}: {} runs ({} ok, {} failed) over {} parameters ({}); metrics: {}.",
                                kind.is_string() ? kind.get<std::string>() : "parameter",
                                diagram.is_string() ? " of " + diagram.get<std::string>() : std::string(),
                                t.rows.size(), t.rows.size() - failed, failed, t.parameters.size(),
                                fmt::join(t.parameters, ", "),
                                metrics.empty() ? std::string("none") : fmt::format("{}", fmt::join(metrics, ", "))));
  const json set = runs_json.value("set", json::object());
  if (set.is_object() && !set.empty()) {
    std::vector<std::string> fixed;
    for (const auto& [k, v] : set.items()) {
      fixed.push_back(fmt::format("{} = {}", k, v.is_string() ? v.get<std::string>() : v.dump()));
    }
    report->Paragraph(fmt::format("Set for every run: {}.", fmt::join(fixed, ", ")));
  }
}

// The values of a row's parameters, "key = value, …" (the keys it assigns).
std::string RowValues(const SweepTable& t, std::size_t r) {
  std::vector<std::string> values;
  for (std::size_t p = 0; p < t.parameters.size(); ++p) {
    const std::string& cell = t.rows[r][t.parameter_column(p)];
    if (!cell.empty()) values.push_back(fmt::format("{} = {}", t.parameters[p], cell));
  }
  return fmt::format("{}", fmt::join(values, ", "));
}

// Each metric's smallest and largest value over the "ok" runs, with the run that gave it.
void AddExtremes(const SweepTable& t, const json& runs_json, HtmlReport* report) {
  std::vector<std::vector<std::string>> rows;
  for (std::size_t m = 0; m < t.metrics.size(); ++m) {
    const std::vector<std::optional<double>> y = MetricValues(t, m);
    std::optional<std::size_t> lo, hi;
    for (std::size_t r = 0; r < y.size(); ++r) {
      if (!y[r]) continue;
      if (!lo || *y[r] < *y[*lo]) lo = r;
      if (!hi || *y[r] > *y[*hi]) hi = r;
    }
    const auto at = [&](const std::optional<std::size_t>& r) {
      return r ? fmt::format("run {}: {}", t.rows[*r][0], RowValues(t, *r)) : std::string("—");
    };
    rows.push_back({t.metrics[m], Unit(runs_json, t.metrics[m]), lo ? fmt::format("{:.6g}", *y[*lo]) : "—", at(lo),
                    hi ? fmt::format("{:.6g}", *y[*hi]) : "—", at(hi)});
  }
  report->Table({"metric", "unit", "smallest", "where", "largest", "where"}, rows);
}

// One chart per metric × parameter, grouped by parameter.
void AddMetricFigures(const SweepTable& t, const json& runs_json, const std::vector<Axis>& axes,
                      bool two_parameter_grid, const fs::path& folder, HtmlReport* report) {
  std::size_t k = 0;
  for (std::size_t p = 0; p < t.parameters.size(); ++p) {
    const Axis& axis = axes[p];
    if (!axis.numeric && axis.values.size() > kSweepReportMaxCategories) {
      report->Warning(fmt::format("{} takes {} values that are not all numbers, more than the {} a chart names: its "
                                  "charts are left out (the values are in runs.csv)",
                                  t.parameters[p], axis.values.size(), kSweepReportMaxCategories));
      continue;
    }
    for (std::size_t m = 0; m < t.metrics.size(); ++m) {
      const std::string unit = Unit(runs_json, t.metrics[m]);
      Figure figure{fmt::format("{}{}_{}_vs_{}.png", kFigurePrefix, ++k, FileNamePart(t.metrics[m]),
                                FileNamePart(t.parameters[p])),
                    fmt::format("{} against {}", t.metrics[m], t.parameters[p]), t.parameters[p],
                    WithUnit(t.metrics[m], unit),
                    MetricSeries(t, two_parameter_grid, p, axis, axes, MetricValues(t, m))};
      const bool empty = std::all_of(figure.series.begin(), figure.series.end(),
                                     [](const Series& s) { return s.x.empty(); });
      if (empty) {  // nothing to draw (a chart without data is no chart: dygraphs refuses it)
        report->Paragraph(fmt::format("{}: no run that finished assigns {} and gives {}; nothing to draw.",
                                      figure.title, t.parameters[p], t.metrics[m]));
        continue;
      }
      if (!axis.numeric) {
        for (std::size_t c = 0; c < axis.values.size(); ++c) {
          figure.x_tick_labels.emplace_back(static_cast<double>(c), axis.values[c]);
        }
      }
      report->AddFigure(figure, folder);
    }
  }
}

// A heat map per metric over the two parameters of a grid: rows the first's values, columns the second's.
void AddHeatMaps(const SweepTable& t, const json& runs_json, const std::vector<Axis>& axes, HtmlReport* report) {
  const std::vector<std::string>& rows = axes[0].values;
  const std::vector<std::string>& columns = axes[1].values;
  if (rows.size() * columns.size() > kSweepReportMaxHeatMapCells) {
    report->Paragraph(fmt::format("No heat map: the grid has {} × {} cells, more than the {} a heat map shows.",
                                  rows.size(), columns.size(), kSweepReportMaxHeatMapCells));
    return;
  }
  std::map<std::string, std::size_t> row_of, column_of;
  for (std::size_t i = 0; i < rows.size(); ++i) row_of[rows[i]] = i;
  for (std::size_t j = 0; j < columns.size(); ++j) column_of[columns[j]] = j;
  for (std::size_t m = 0; m < t.metrics.size(); ++m) {
    std::vector<std::vector<double>> values(rows.size(), std::vector<double>(columns.size(), std::nan("")));
    std::vector<std::vector<std::string>> text(rows.size(), std::vector<std::string>(columns.size(), "—"));
    const std::vector<std::optional<double>> y = MetricValues(t, m);
    for (std::size_t r = 0; r < t.rows.size(); ++r) {
      const auto i = row_of.find(t.rows[r][t.parameter_column(0)]);
      const auto j = column_of.find(t.rows[r][t.parameter_column(1)]);
      if (i == row_of.end() || j == column_of.end()) continue;
      if (y[r]) {
        values[i->second][j->second] = *y[r];
        text[i->second][j->second] = fmt::format("{:.4g}", *y[r]);
      } else {
        text[i->second][j->second] = t.ok(r) ? "—" : "failed";
      }
    }
    report->HeatMap(WithUnit(t.metrics[m], Unit(runs_json, t.metrics[m])), t.parameters[0], rows, t.parameters[1],
                    columns, values, text);
  }
}

// The failed runs with their values and error.
void AddFailures(const SweepTable& t, HtmlReport* report) {
  std::vector<std::vector<std::string>> rows;
  std::size_t failed = 0;
  for (std::size_t r = 0; r < t.rows.size(); ++r) {
    if (t.ok(r)) continue;
    if (++failed > kSweepReportMaxRows) continue;
    std::vector<std::string> row = {t.rows[r][0], t.rows[r][1]};
    for (std::size_t p = 0; p < t.parameters.size(); ++p) row.push_back(t.rows[r][t.parameter_column(p)]);
    row.push_back(t.rows[r][t.error_column()]);
    rows.push_back(std::move(row));
  }
  if (failed == 0) {
    report->Paragraph("No run failed.");
    return;
  }
  std::vector<std::string> header = {"id", "status"};
  header.insert(header.end(), t.parameters.begin(), t.parameters.end());
  header.push_back("error");
  report->Table(header, rows);
  if (failed > kSweepReportMaxRows) {
    report->Paragraph(fmt::format("The first {} of {} failed runs; every one is in runs.csv.", kSweepReportMaxRows,
                                  failed));
  }
}

// runs.csv's rows as they are (the first kSweepReportMaxRows).
void AddRuns(const SweepTable& t, HtmlReport* report) {
  const std::size_t shown = std::min(t.rows.size(), kSweepReportMaxRows);
  report->Table(t.header, std::vector<std::vector<std::string>>(
                              t.rows.begin(), t.rows.begin() + static_cast<std::ptrdiff_t>(shown)));
  if (shown < t.rows.size()) {
    report->Paragraph(fmt::format("The first {} of {} runs; every one is in runs.csv.", shown, t.rows.size()));
  }
}

}  // namespace

std::vector<std::string> SweepReportFileNames() {
  std::vector<std::string> names = {kSweepReportFile};
  for (const auto& name : FigureFileNames(std::string(kFigurePrefix) + "*.png")) names.push_back(name);
  return names;
}

void WriteSweepReport(const fs::path& folder, const json& runs_json) {
  if (!runs_json.is_object()) {
    throw std::runtime_error(fmt::format("{}: the sweep's runs.json is no JSON object", folder.string()));
  }
  const SweepTable t = ReadSweepTable(folder / "runs.csv", runs_json);
  std::vector<Axis> axes;
  for (std::size_t p = 0; p < t.parameters.size(); ++p) axes.push_back(ParameterAxis(t, p));
  const json kind = runs_json.value("kind", json());
  const bool two_parameter_grid = kind.is_string() && kind.get<std::string>() == "grid" && t.parameters.size() == 2;
  const json diagram = runs_json.value("diagram", json());
  HtmlReport report(fmt::format("motionblocks sweep{}",
                                diagram.is_string() ? ": " + fs::path(diagram.get<std::string>()).filename().string()
                                                    : std::string()),
                    InteractiveCharts{});
  AddSummary(t, runs_json, &report);
  if (t.metrics.empty()) {
    report.Paragraph("The diagram defines no metrics (its \"metrics\"): there is nothing to draw against the "
                     "parameters. Add metrics to the diagram to see them here.");
  } else {
    report.Heading("Each metric's smallest and largest value");
    AddExtremes(t, runs_json, &report);
    report.Heading("Metrics against the swept parameters");
    AddMetricFigures(t, runs_json, axes, two_parameter_grid, folder, &report);
    if (two_parameter_grid) {
      report.Heading(fmt::format("Heat maps over {} × {}", t.parameters[0], t.parameters[1]));
      AddHeatMaps(t, runs_json, axes, &report);
    }
  }
  report.Heading("Failed runs");
  AddFailures(t, &report);
  report.Heading("Runs (runs.csv)");
  AddRuns(t, &report);
  report.Write(folder / kSweepReportFile);
}

}  // namespace mb

#include "tools/report/chart_data.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <map>
#include <set>
#include <utility>

#include <fmt/format.h>

#include "tools/report/report.h"

namespace mb {

using nlohmann::json;

std::vector<std::size_t> DecimateMinMax(const std::vector<double>& y, std::size_t columns) {
  const std::size_t n = y.size();
  std::vector<std::size_t> kept;
  if (columns == 0 || n <= 2 * columns) {
    kept.resize(n);
    for (std::size_t i = 0; i < n; ++i) kept[i] = i;
    return kept;
  }
  kept.reserve(2 * columns + 2);
  kept.push_back(0);
  for (std::size_t c = 0; c < columns; ++c) {
    const std::size_t lo = c * n / columns, hi = (c + 1) * n / columns;
    std::size_t imin = n, imax = n;  // n: no finite value in the run yet
    for (std::size_t i = lo; i < hi; ++i) {
      if (!std::isfinite(y[i])) continue;
      if (imin == n || y[i] < y[imin]) imin = i;
      if (imax == n || y[i] > y[imax]) imax = i;
    }
    if (imin == n) continue;
    const auto [first, second] = std::minmax(imin, imax);
    if (first != kept.back()) kept.push_back(first);
    if (second != kept.back()) kept.push_back(second);
  }
  if (kept.back() != n - 1) kept.push_back(n - 1);
  return kept;
}

std::vector<std::size_t> DecimateScatter(const std::vector<double>& x, const std::vector<double>& y,
                                         std::size_t columns, std::size_t rows) {
  const std::size_t n = std::min(x.size(), y.size());
  std::vector<std::size_t> finite;
  finite.reserve(n);
  for (std::size_t i = 0; i < n; ++i) {
    if (std::isfinite(x[i]) && std::isfinite(y[i])) finite.push_back(i);
  }
  if (columns == 0 || rows == 0 || finite.size() <= 2 * columns) return finite;
  double x0 = x[finite[0]], x1 = x0, y0 = y[finite[0]], y1 = y0;
  for (std::size_t i : finite) {
    x0 = std::min(x0, x[i]);
    x1 = std::max(x1, x[i]);
    y0 = std::min(y0, y[i]);
    y1 = std::max(y1, y[i]);
  }
  const auto cell = [](double v, double lo, double hi, std::size_t count) {
    if (!(hi > lo)) return std::size_t{0};
    const double f = (v - lo) / (hi - lo) * static_cast<double>(count);
    return std::min(count - 1, static_cast<std::size_t>(std::max(0.0, f)));
  };
  std::vector<char> occupied(columns * rows, 0);
  std::vector<std::size_t> col_min(columns, n), col_max(columns, n);
  std::vector<char> keep(n, 0);
  for (std::size_t i : finite) {
    const std::size_t c = cell(x[i], x0, x1, columns), r = cell(y[i], y0, y1, rows);
    if (!occupied[c * rows + r]) {
      occupied[c * rows + r] = 1;
      keep[i] = 1;
    }
    if (col_min[c] == n || y[i] < y[col_min[c]]) col_min[c] = i;
    if (col_max[c] == n || y[i] > y[col_max[c]]) col_max[c] = i;
  }
  for (std::size_t c = 0; c < columns; ++c) {
    if (col_min[c] != n) keep[col_min[c]] = 1;
    if (col_max[c] != n) keep[col_max[c]] = 1;
  }
  std::vector<std::size_t> kept;
  for (std::size_t i = 0; i < n; ++i) {
    if (keep[i]) kept.push_back(i);
  }
  return kept;
}

namespace {

// A value at the display's precision (7 significant digits: nlohmann-json then writes at most that many).
double Rounded(double v) { return std::strtod(fmt::format("{:.7g}", v).c_str(), nullptr); }

bool IsBars(const Series& s) { return s.style == "boxes" || s.style == "impulses"; }
bool IsDots(const Series& s) { return s.style == "dots" || s.style == "points"; }

// The series' labels made unique (the chart keys its series by label): a repeat gets " (2)", " (3)", ….
std::vector<std::string> UniqueLabels(const Figure& figure) {
  std::vector<std::string> labels;
  std::set<std::string> seen{figure.xlabel};
  for (const auto& s : figure.series) {
    std::string label = s.label.empty() ? "series" : s.label;
    for (int k = 2; seen.count(label); ++k) label = fmt::format("{} ({})", s.label, k);
    seen.insert(label);
    labels.push_back(label);
  }
  return labels;
}

// Whether every series has the same x vector as the first.
bool SharedX(const Figure& figure) {
  for (const auto& s : figure.series) {
    if (s.x != figure.series.front().x) return false;
  }
  return !figure.series.empty();
}

std::string CsvField(const std::string& text) {
  std::string out = "\"";
  for (char c : text) {
    if (c == '"') out += '"';
    out += (c == '\n' || c == '\r') ? ' ' : c;
  }
  return out + "\"";
}

std::string CsvNumber(double v) { return std::isfinite(v) ? fmt::format("{:.17g}", v) : std::string(); }

}  // namespace

json ChartJson(const Figure& figure, const std::string& csv_file, std::size_t columns) {
  const std::vector<std::string> labels = UniqueLabels(figure);
  const std::size_t k = figure.series.size();
  // (x, series, y) of every kept point, then merged into rows on equal x (a second point of the same series at the
  // same x starts a new row).
  std::vector<std::tuple<double, std::size_t, double>> points;
  std::size_t samples = 0;
  bool decimated = false;
  json point_styles = json::array(), step_styles = json::array(), marker_styles = json::array();
  for (std::size_t s = 0; s < k; ++s) {
    const Series& series = figure.series[s];
    const std::size_t n = std::min(series.x.size(), series.y.size());
    samples = std::max(samples, n);
    const std::vector<double> y(series.y.begin(), series.y.begin() + static_cast<std::ptrdiff_t>(n));
    const std::vector<std::size_t> kept =
        IsDots(series) ? DecimateScatter(series.x, y, columns * 3 / 10, columns * 3 / 40)  // ~1.5 px cells
                       : DecimateMinMax(y, columns);
    decimated = decimated || kept.size() < n;
    for (std::size_t i : kept) {
      if (std::isfinite(series.x[i])) points.emplace_back(Rounded(series.x[i]), s, Rounded(series.y[i]));
    }
    point_styles.push_back(IsDots(series) || IsBars(series));
    step_styles.push_back(series.style == "steps");
    marker_styles.push_back(series.style == "linespoints");
  }
  std::stable_sort(points.begin(), points.end(),
                   [](const auto& a, const auto& b) { return std::get<0>(a) < std::get<0>(b); });
  json data = json::array();
  json row;
  std::vector<char> filled;
  const auto flush = [&] {
    if (!row.is_null()) data.push_back(std::move(row));
    row = json();
  };
  for (const auto& [x, s, y] : points) {
    if (row.is_null() || row[0].get<double>() != x || filled[s]) {
      flush();
      row = json::array();
      row.push_back(x);
      for (std::size_t j = 0; j < k; ++j) row.push_back(nullptr);
      filled.assign(k, 0);
    }
    if (std::isfinite(y)) row[s + 1] = y;  // a non-finite value is a gap (null)
    filled[s] = 1;
  }
  flush();
  json label_list = json::array({figure.xlabel});
  for (const auto& l : labels) label_list.push_back(l);
  json shaded = json::array(), marks = json::array();
  for (const auto& [x0, x1] : figure.shaded_x_ranges) shaded.push_back({x0, x1});
  for (const auto& [x, text] : figure.x_marks) marks.push_back({x, text});
  return {{"title", figure.title},   {"xlabel", figure.xlabel}, {"ylabel", figure.ylabel},
          {"labels", label_list},    {"points", point_styles},  {"data", std::move(data)},
          {"steps", step_styles},    {"markers", marker_styles},
          {"logx", figure.log_x},    {"logy", figure.log_y},    {"link", figure.x_link},
          {"shaded", shaded},        {"marks", marks},          {"samples", samples},
          {"decimated", decimated},  {"csv", csv_file},
          {"yrange", figure.y_range ? json::array({figure.y_range->first, figure.y_range->second}) : json()}};
}

std::string FigureCsv(const Figure& figure) {
  const std::vector<std::string> labels = UniqueLabels(figure);
  std::string out;
  if (SharedX(figure)) {
    out += CsvField(figure.xlabel);
    for (const auto& l : labels) out += "," + CsvField(l);
    out += "\n";
    const auto& x = figure.series.front().x;
    for (std::size_t i = 0; i < x.size(); ++i) {
      out += CsvNumber(x[i]);
      for (const auto& s : figure.series) out += "," + (i < s.y.size() ? CsvNumber(s.y[i]) : std::string());
      out += "\n";
    }
    return out;
  }
  out += "\"series\"," + CsvField(figure.xlabel) + "," + CsvField(figure.ylabel) + "\n";
  for (std::size_t s = 0; s < figure.series.size(); ++s) {
    const Series& series = figure.series[s];
    const std::string name = CsvField(labels[s]);
    for (std::size_t i = 0; i < std::min(series.x.size(), series.y.size()); ++i) {
      out += name + "," + CsvNumber(series.x[i]) + "," + CsvNumber(series.y[i]) + "\n";
    }
  }
  return out;
}

std::string ScriptSafeJson(const json& value) {
  const std::string text = value.dump(-1, ' ', false, json::error_handler_t::replace);
  std::string out;
  out.reserve(text.size());
  for (char c : text) {
    if (c == '<') {
      out += "\\u003c";
    } else {
      out += c;
    }
  }
  return out;
}

}  // namespace mb

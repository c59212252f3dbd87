#include "tools/report/report.h"

#include <algorithm>
#include <atomic>
#include <cctype>
#include <cmath>
#include <fstream>
#include <limits>
#include <sstream>
#include <stdexcept>
#include <string_view>

#include <fmt/format.h>
#include <fmt/ranges.h>

#include "engine/output_file.h"
#include "tools/report/chart_data.h"
#include "tools/report/run_program.h"

namespace mb {

namespace fs = std::filesystem;

namespace {

// The points drawn by gnuplot: min/max per bucket (DecimateMinMax, max_points / 2 buckets), so that peaks survive.
std::vector<std::pair<double, double>> Thin(const Series& s, std::size_t max_points) {
  const std::size_t n = std::min(s.x.size(), s.y.size());
  const std::vector<double> y(s.y.begin(), s.y.begin() + static_cast<std::ptrdiff_t>(n));
  std::vector<std::pair<double, double>> out;
  for (std::size_t i : DecimateMinMax(y, max_points < 4 ? 0 : max_points / 2)) out.emplace_back(s.x[i], s.y[i]);
  return out;
}

// A gnuplot string literal holding the bytes of `s` as data: double-quoted, every byte but letters, digits, space
// and ._-+:,/()[]=%* written as a three-digit octal escape (\047 for a quote, \140 for a backquote, \303\251 for
// "é"), so that no character of a name, title or path is read by gnuplot's parser: no quote ends the string, no
// backquote or @ is substituted. (A single-quoted string cannot hold every name: gnuplot 5.4 reads '''a' as a
// syntax error, and the figure of a signal named 'a was lost.) Every user string reaches gnuplot only through this.
std::string GnuplotLiteral(const std::string& s) {
  std::string out = "\"";
  for (char c : s) {
    const auto byte = static_cast<unsigned char>(c);
    const bool plain = (byte < 0x80 && std::isalnum(byte) != 0) ||
                       std::string_view(" ._-+:,/()[]=%*").find(c) != std::string_view::npos;
    out += plain ? std::string(1, c) : fmt::format("\\{:03o}", byte);
  }
  return out + "\"";
}

// A text shown in a figure (title, label, key) as a gnuplot string: control characters (a newline, ESC) as spaces.
std::string GnuplotQuote(std::string s) {
  for (char& c : s) {
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = ' ';
  }
  return GnuplotLiteral(s);
}

// A path as a gnuplot string: every byte kept (an --out folder with a newline in its name still gets its PNGs).
std::string GnuplotPath(const fs::path& path) { return GnuplotLiteral(path.string()); }

// One line of text in a data-file comment: control characters as spaces.
std::string CommentText(std::string s) {
  for (char& c : s) {
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = ' ';
  }
  return s;
}


// A file's text, or "" if it cannot be read.
std::string ReadTextFile(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  if (!in) return {};
  std::ostringstream text;
  text << in.rdbuf();
  return text.str();
}

// The charting library's text ready to stand inside <script>: its source-map comment dropped (the map is not
// embedded), and "</" written "<\/" wherever "</script" occurs in any case (inside a JavaScript string or regular
// expression, where the library could hold it, both mean the same). "" and `why` set if the file cannot be read or
// is no dygraphs.
std::string ReadChartLibrary(const fs::path& path, std::string* why) {
  std::error_code ec;
  if (!fs::is_regular_file(path, ec)) {
    *why = path.string() + " not found";
    return {};
  }
  std::string text = ReadTextFile(path);
  if (text.find("Dygraph") == std::string::npos) {
    *why = path.string() + " is no dygraphs library";
    return {};
  }
  const std::size_t map = text.rfind("//# sourceMappingURL=");
  if (map != std::string::npos) text.erase(map);
  std::string lower = text;
  std::transform(lower.begin(), lower.end(), lower.begin(), [](unsigned char c) { return std::tolower(c); });
  for (std::size_t at = lower.find("</script"); at != std::string::npos; at = lower.find("</script", at + 1)) {
    text.replace(at, 2, "<\\/");
    lower.replace(at, 2, "<\\/");
  }
  return text;
}

// The charts' style: a chart above its legend and toggles; the PNG shown instead without script (or when a chart
// fails), and in print.
constexpr const char* kChartCss =
    ".mb-title{font-weight:bold;margin:.3em 0}.mb-plot{width:100%;height:340px}"
    ".mb-legend{font-size:12px;min-height:1.4em}.mb-toggles{font-size:12px}.mb-toggles label{margin-right:1em}"
    "figcaption{font-size:12px;color:#555}.mb-js .mb-static{display:none}.mb-js .mb-failed .mb-static{display:block}"
    "@media print{.mb-chart{display:none}.mb-js .mb-static{display:block}}";

// The page's script: one dygraphs chart per <div class="mb-chart" data-chart="i">, drawn from the JSON in
// #mb-charts (ChartJson). Text reaches the page as text (textContent, canvas fillText) or escaped (dygraphs writes
// axis labels as HTML; it escapes legend labels itself).
constexpr const char* kChartScript = R"JS((function () {
  'use strict';
  var specs = JSON.parse(document.getElementById('mb-charts').textContent);
  var palette = ['#1f77b4', '#d62728', '#2ca02c', '#9467bd', '#ff7f0e', '#8c564b', '#e377c2', '#7f7f7f'];
  var groups = {}, syncing = false;
  function esc(s) {
    return String(s).replace(/[&<>"']/g, function (c) {
      return {'&': '&amp;', '<': '&lt;', '>': '&gt;', '"': '&quot;', "'": '&#39;'}[c];
    });
  }
  function num(v) {
    if (v === null || !isFinite(v)) return String(v);
    var a = Math.abs(v);
    if (a !== 0 && (a >= 1e6 || a < 1e-4)) return v.toExponential(4).replace(/\.?0+e/, 'e');
    return String(parseFloat(v.toPrecision(6)));
  }
  function pale(hex) {
    var v = parseInt(hex.slice(1), 16);
    return 'rgba(' + (v >> 16) + ',' + ((v >> 8) & 255) + ',' + (v & 255) + ',0.35)';
  }
  function underlay(spec) {
    return function (ctx, area, g) {
      ctx.save();
      ctx.fillStyle = 'rgba(0,0,0,0.08)';
      function dom(v) { return area.x + g.toPercentXCoord(v) * area.w; }  // linear or logarithmic x
      spec.shaded.forEach(function (r) {
        var a = dom(r[0]), b = dom(r[1]);
        ctx.fillRect(Math.min(a, b), area.y, Math.abs(b - a), area.h);
      });
      ctx.strokeStyle = '#b00'; ctx.fillStyle = '#b00'; ctx.font = '11px sans-serif'; ctx.setLineDash([4, 3]);
      spec.marks.forEach(function (m, k) {  // labels one under the other: near marks stay legible
        var x = dom(m[0]);
        if (!(x >= area.x && x <= area.x + area.w)) return;
        ctx.beginPath(); ctx.moveTo(x, area.y); ctx.lineTo(x, area.y + area.h); ctx.stroke();
        var w = ctx.measureText(m[1]).width;  // a label that would leave the plot on the right goes left of its line
        ctx.fillText(m[1], x + 3 + w > area.x + area.w ? x - 3 - w : x + 3, area.y + 12 + 13 * k);
      });
      ctx.restore();
    };
  }
  function link(g, initial) {  // the x range of one chart of a group set on the others
    if (initial || syncing || !g.mbLink) return;
    syncing = true;
    var r = g.xAxisRange();
    groups[g.mbLink].forEach(function (o) {
      var q = o.xAxisRange();
      if (o !== g && (q[0] !== r[0] || q[1] !== r[1])) o.updateOptions({dateWindow: r});
    });
    syncing = false;
  }
  function draw(box, spec) {
    var toggles = document.createElement('div'), plot = document.createElement('div'),
        legend = document.createElement('div');
    toggles.className = 'mb-toggles'; plot.className = 'mb-plot'; legend.className = 'mb-legend';
    box.appendChild(toggles); box.appendChild(plot); box.appendChild(legend);
    var series = {}, colors = [];
    spec.labels.slice(1).forEach(function (label, k) {
      colors.push(palette[k % palette.length]);
      series[label] = spec.points[k] ? {strokeWidth: 0, drawPoints: true, pointSize: 1.5, highlightCircleSize: 3,
                                        color: pale(colors[k])}  // dots pale: the lines drawn over them show
                                     : {strokeWidth: spec.points.some(Boolean) ? 2 : 1.2,
                                        stepPlot: !!(spec.steps && spec.steps[k]),
                                        drawPoints: !!(spec.markers && spec.markers[k]), pointSize: 2.5};
    });
    var g = new Dygraph(plot, spec.data, {
      labels: spec.labels, colors: colors, series: series, xlabel: esc(spec.xlabel), ylabel: esc(spec.ylabel),
      labelsDiv: legend, legend: 'always', connectSeparatedPoints: true, logscale: spec.logy,
      valueRange: spec.yrange,
      axes: {x: {logscale: spec.logx, valueFormatter: num, axisLabelFormatter: num},
             y: {valueFormatter: num, axisLabelFormatter: num}},
      underlayCallback: underlay(spec), drawCallback: link
    });
    g.mbLink = spec.link;
    box.mbDygraph = g;  // the chart's object, for the browser's console and tests/browser
    if (spec.link) (groups[spec.link] = groups[spec.link] || []).push(g);
    spec.labels.slice(1).forEach(function (label, k) {
      var l = document.createElement('label'), c = document.createElement('input'), swatch = document.createElement('span');
      c.type = 'checkbox'; c.checked = true;
      c.addEventListener('change', function () { g.setVisibility(k, c.checked); });
      swatch.style.color = colors[k]; swatch.textContent = '\u25A0 ';
      l.appendChild(c); l.appendChild(swatch); l.appendChild(document.createTextNode(label));
      toggles.appendChild(l);
    });
    var hint = document.createElement('span');
    hint.textContent = ' drag: zoom · shift-drag: pan · double-click: reset' + (spec.link ? ' (time axes linked)' : '');
    hint.style.color = '#777';
    toggles.appendChild(hint);
  }
  document.documentElement.className += ' mb-js';
  var boxes = document.querySelectorAll('.mb-chart');
  for (var i = 0; i < boxes.length; ++i) {
    try {
      draw(boxes[i], specs[+boxes[i].getAttribute('data-chart')]);
    } catch (e) {  // that figure falls back to its PNG
      boxes[i].parentNode.className += ' mb-failed';
      boxes[i].textContent = 'chart failed: ' + e;
    }
  }
})();
)JS";
}  // namespace

namespace {
std::atomic<std::size_t> g_max_report_figures{kDefaultMaxReportFigures};
}  // namespace

void SetMaxReportFigures(std::size_t count) {
  if (count == 0) throw std::invalid_argument("--max-plots: a report draws at least 1 figure; give N >= 1");
  g_max_report_figures = count;
}

std::size_t MaxReportFigures() { return g_max_report_figures; }

std::vector<std::string> FigureFileNames(const std::string& file) {
  const std::string stem = fs::path(file).stem().string();
  const std::string plot = std::string(kPlotFolder) + "/";
  return {file, plot + stem + ".dat", plot + stem + ".gp", stem + ".full.csv", plot + "gnuplot.log"};
}

std::string RenderFigure(const Figure& figure, const fs::path& directory) {
  const fs::path plot_folder = directory / kPlotFolder;
  fs::create_directories(plot_folder);
  const std::vector<std::string> names = FigureFileNames(figure.file);
  const fs::path data = directory / names[1];
  const fs::path script = directory / names[2];
  // The script's own paths, relative to its folder: the data beside it, the PNG in the output folder above.
  const fs::path png_from_script = fs::path("..") / names[0];
  const fs::path data_from_script = data.filename();
  {
    std::ostringstream out;
    for (const auto& s : figure.series) {
      out << "# " << CommentText(s.label) << "\n";
      for (const auto& [x, y] : Thin(s, figure.max_points)) {
        if (std::isfinite(x) && std::isfinite(y)) out << fmt::format("{:.10g} {:.10g}\n", x, y);
      }
      out << "\n\n";  // gnuplot data block separator (index)
    }
    WriteFileSafely(data, out.str());
  }
  {
    std::ostringstream gp;
    // Go to the script's folder first (ARG0: the script as gnuplot was given it), so that its relative paths hold
    // whatever the working folder: `gnuplot plot/x.gp` from the output folder, or `gnuplot x.gp` in plot/.
    gp << "# " << CommentText(figure.file) << ": paths relative to this script's folder (the next line goes there)\n";
    gp << "if (exists(\"ARG0\")) { mb_i = strlen(ARG0); "
          "while (mb_i > 0 && ARG0[mb_i:mb_i] ne '/') { mb_i = mb_i - 1 }; if (mb_i > 0) { cd ARG0[1:mb_i] } }\n";
    gp << "set terminal pngcairo size 900,420 font 'Sans,10'\n";
    gp << "set output " << GnuplotPath(png_from_script) << "\n";
    gp << "set title " << GnuplotQuote(figure.title) << " noenhanced\n";  // every text verbatim, no markup
    gp << "set xlabel " << GnuplotQuote(figure.xlabel) << " noenhanced\n";
    gp << "set ylabel " << GnuplotQuote(figure.ylabel) << " noenhanced\n";
    gp << "set grid\nset key outside right top noenhanced\nset datafile commentschars '#'\n";
    if (figure.log_x) gp << "set logscale x\n";
    if (figure.log_y) gp << "set logscale y\n";
    if (figure.y_range) {
      gp << fmt::format("set yrange [{:.10g}:{:.10g}]\n", figure.y_range->first, figure.y_range->second);
    }
    if (!figure.x_tick_labels.empty()) {
      gp << "set xtics (";
      for (std::size_t i = 0; i < figure.x_tick_labels.size(); ++i) {
        gp << (i ? ", " : "") << GnuplotQuote(figure.x_tick_labels[i].second) << " "
           << fmt::format("{:.10g}", figure.x_tick_labels[i].first);
      }
      gp << ") noenhanced\n";  // labels verbatim: "position_periodic" is no subscript
      const auto [lo, hi] = std::minmax_element(figure.x_tick_labels.begin(), figure.x_tick_labels.end());
      gp << fmt::format("set xrange [{:.10g}:{:.10g}]\n", lo->first - 0.6, hi->first + 0.6);
    }
    for (const auto& [x0, x1] : figure.shaded_x_ranges) {
      gp << fmt::format("set object rect from {:.10g}, graph 0 to {:.10g}, graph 1 behind fillcolor rgb '#e4e4e4' "
                        "fillstyle solid 1.0 noborder\n", x0, x1);
    }
    for (std::size_t k = 0; k < figure.x_marks.size(); ++k) {  // labels one under the other
      const auto& [x, text] = figure.x_marks[k];
      gp << fmt::format("set arrow from {0:.10g}, graph 0 to {0:.10g}, graph 1 nohead dashtype 2 lc rgb '#bb0000'\n", x);
      gp << "set label " << GnuplotQuote(text)
         << fmt::format(" at {:.10g}, graph {:.3f} offset 0.4,0 ", x, 0.96 - 0.05 * static_cast<double>(k))
         << "textcolor rgb '#bb0000' font 'Sans,8' noenhanced\n";
    }
    const bool bars = std::any_of(figure.series.begin(), figure.series.end(),
                                  [](const Series& s) { return s.style == "boxes"; });
    if (bars) gp << "set style fill solid 0.7 border -1\nset boxwidth 0.35 absolute\nset yrange [0:*]\n";
    gp << "plot ";
    for (std::size_t i = 0; i < figure.series.size(); ++i) {
      const auto& s = figure.series[i];
      gp << (i ? ", " : "") << GnuplotPath(data_from_script) << " index " << i << " using 1:2 with " << s.style
         << (s.style == "points" ? " pt 7 ps 0.3" : " lw 1.2") << " title " << GnuplotQuote(s.label) << " noenhanced";
    }
    gp << "\n";
    WriteFileSafely(script, gp.str());
  }
  // No shell: the script is one argument ("./name", so that a name starting with '-' is no option), run in its
  // folder so that its relative paths resolve as they will when someone reruns it.
  const fs::path log = directory / names[4];
  const int status = RunProgram({"gnuplot", "./" + script.filename().string()}, log, plot_folder);
  if (status != 0) {
    return fmt::format("gnuplot failed for {} (exit {}); see {} — is gnuplot installed? (scripts/install-deps.sh)",
                       figure.file, status, log.string());
  }
  return {};
}

std::string HtmlEscape(const std::string& text) {
  std::string out;
  for (char c : text) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;  // text may end up in an attribute (alt)
      default: out += c;
    }
  }
  return out;
}

void HtmlReport::Heading(const std::string& text) { body_ += "<h2>" + HtmlEscape(text) + "</h2>\n"; }

void HtmlReport::Heading(const std::string& text, const std::string& id) {
  body_ += "<h2 id=\"" + HtmlEscape(id) + "\">" + HtmlEscape(text) + "</h2>\n";
}

std::string FigureId(const std::string& file) {
  std::string id = "fig-" + fs::path(file).stem().string();
  for (char& c : id) {
    if (std::isalnum(static_cast<unsigned char>(c)) == 0 && c != '_' && c != '-') c = '_';
  }
  return id;
}

void HtmlReport::Paragraph(const std::string& text) { body_ += "<p>" + HtmlEscape(text) + "</p>\n"; }

void HtmlReport::Table(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows) {
  Table(header, rows, {});
}

void HtmlReport::Table(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows,
                       const std::vector<std::string>& row_links) {
  body_ += "<table>\n<tr>";
  for (const auto& h : header) body_ += "<th>" + HtmlEscape(h) + "</th>";
  body_ += "</tr>\n";
  for (std::size_t r = 0; r < rows.size(); ++r) {
    body_ += "<tr>";
    for (std::size_t c = 0; c < rows[r].size(); ++c) {
      const std::string cell = HtmlEscape(rows[r][c]);
      const bool linked = c == 0 && r < row_links.size() && !row_links[r].empty();
      body_ += "<td>" + (linked ? "<a href=\"#" + HtmlEscape(row_links[r]) + "\">" + cell + "</a>" : cell) + "</td>";
    }
    body_ += "</tr>\n";
  }
  body_ += "</table>\n";
}

void HtmlReport::AddFigure(const Figure& figure, const fs::path& directory) {
  if (figures_ >= MaxReportFigures()) {
    not_drawn_.push_back(figure.title.empty() ? figure.file : figure.title);
    return;
  }
  ++figures_;
  const std::string error = RenderFigure(figure, directory);
  const bool bars = std::any_of(figure.series.begin(), figure.series.end(),
                                [](const Series& s) { return s.style == "boxes" || s.style == "impulses"; });
  if (!interactive_ || figure.series.empty() || bars || !figure.x_tick_labels.empty()) {
    if (error.empty()) {
      body_ += fmt::format("<figure id=\"{}\"><img src=\"{}\" alt=\"{}\"><figcaption>{}</figcaption></figure>\n",
                           FigureId(figure.file), HtmlEscape(figure.file), HtmlEscape(figure.title),
                           HtmlEscape(figure.title));
    } else {
      Warning("Figure missing: " + error);
    }
    return;
  }
  const std::string csv = FigureFileNames(figure.file)[3];
  WriteFileSafely(directory / csv, FigureCsv(figure));
  const nlohmann::json spec = ChartJson(figure, csv, interactive_->columns);
  body_ += fmt::format("<figure class=\"mb-figure\" id=\"{}\"><div class=\"mb-title\">{}</div>"
                       "<div class=\"mb-chart\" data-chart=\"{}\"></div>\n",
                       FigureId(figure.file), HtmlEscape(figure.title), charts_.size());
  if (error.empty()) {
    body_ += fmt::format("<img class=\"mb-static\" loading=\"lazy\" src=\"{}\" alt=\"{}\">\n",
                         HtmlEscape(figure.file), HtmlEscape(figure.title));
  } else {
    body_ += "<p class=\"warn mb-static\">Static figure missing: " + HtmlEscape(error) + "</p>\n";
  }
  const std::size_t samples = spec["samples"].get<std::size_t>(), rows = spec["data"].size();
  body_ += fmt::format("<figcaption>{} samples{}. Full data: <a href=\"{}\">{}</a>{}</figcaption></figure>\n",
                       samples,
                       spec["decimated"].get<bool>()
                           ? fmt::format(", drawn as {} rows (the extremes of each pixel column kept)", rows)
                           : std::string(),
                       HtmlEscape(csv), HtmlEscape(csv),
                       error.empty() ? fmt::format(" · static: <a href=\"{0}\">{0}</a>", HtmlEscape(figure.file))
                                     : std::string());
  charts_.push_back(ScriptSafeJson(spec));
}

void HtmlReport::Image(const std::string& file, const std::string& caption) {
  body_ += fmt::format("<figure><img src=\"{}\" alt=\"{}\"><figcaption>{}</figcaption></figure>\n", file,
                       HtmlEscape(caption), HtmlEscape(caption));
}

void HtmlReport::Warning(const std::string& text) { body_ += "<p class=\"warn\">" + HtmlEscape(text) + "</p>\n"; }

namespace {

// The colour of t ∈ [0, 1] on the viridis scale (matplotlib's, five stops linearly interpolated), as #rrggbb.
std::string ViridisColour(double t) {
  static constexpr int kStops[5][3] = {{68, 1, 84}, {59, 82, 139}, {33, 145, 140}, {94, 201, 98}, {253, 231, 37}};
  const double at = std::clamp(t, 0.0, 1.0) * 4.0;
  const auto k = std::min(3, static_cast<int>(at));
  const double f = at - k;
  int rgb[3];
  for (int i = 0; i < 3; ++i) {
    rgb[i] = static_cast<int>(std::lround((1.0 - f) * kStops[k][i] + f * kStops[k + 1][i]));
  }
  return fmt::format("#{:02x}{:02x}{:02x}", rgb[0], rgb[1], rgb[2]);
}

}  // namespace

void HtmlReport::HeatMap(const std::string& caption, const std::string& row_label,
                         const std::vector<std::string>& row_names, const std::string& column_label,
                         const std::vector<std::string>& column_names, const std::vector<std::vector<double>>& values,
                         const std::vector<std::vector<std::string>>& text) {
  const auto shaped = [&](const auto& m) {
    return m.size() == row_names.size() &&
           std::all_of(m.begin(), m.end(), [&](const auto& r) { return r.size() == column_names.size(); });
  };
  if (!shaped(values) || !shaped(text)) {
    throw std::invalid_argument(fmt::format("HtmlReport::HeatMap: give {} × {} values and texts (one per cell)",
                                            row_names.size(), column_names.size()));
  }
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (const auto& r : values) {
    for (double v : r) {
      if (!std::isfinite(v)) continue;
      lo = std::min(lo, v);
      hi = std::max(hi, v);
    }
  }
  const auto scale = [&](double v) { return hi > lo ? (v - lo) / (hi - lo) : 0.5; };
  std::string html = "<table class=\"mb-heatmap\"><caption>" + HtmlEscape(caption) + "</caption>\n<tr><th>" +
                     HtmlEscape(row_label) + " ↓ · " + HtmlEscape(column_label) + " →</th>";
  for (const auto& c : column_names) html += "<th>" + HtmlEscape(c) + "</th>";
  html += "</tr>\n";
  for (std::size_t r = 0; r < row_names.size(); ++r) {
    html += "<tr><th>" + HtmlEscape(row_names[r]) + "</th>";
    for (std::size_t c = 0; c < column_names.size(); ++c) {
      const double v = values[r][c];
      const std::string style = std::isfinite(v) ? fmt::format("background:{};color:{}", ViridisColour(scale(v)),
                                                               scale(v) < 0.6 ? "#fff" : "#000")
                                                 : std::string("background:#ddd;color:#555");
      html += "<td style=\"" + style + "\">" + HtmlEscape(text[r][c]) + "</td>";
    }
    html += "</tr>\n";
  }
  html += "</table>\n";
  if (lo <= hi) {
    html += fmt::format("<p class=\"mb-heatmap-scale\">Colour: <span style=\"background:{};color:#fff\">&nbsp;"
                        "{:.4g}&nbsp;</span> (smallest) to <span style=\"background:{};color:#000\">&nbsp;{:.4g}"
                        "&nbsp;</span> (largest); grey: no value.</p>\n",
                        ViridisColour(0.0), lo, ViridisColour(1.0), hi);
  }
  body_ += html;
}

void HtmlReport::Write(const fs::path& path) const {
  std::string head_extra, scripts, warning;
  if (!charts_.empty()) {
    std::string why;
    const std::string library = ReadChartLibrary(interactive_->library, &why);
    if (library.empty()) {
      warning = "<p class=\"warn\">" +
                HtmlEscape(fmt::format("Interactive charts unavailable: {}. Install Debian's libjs-dygraphs "
                                       "(scripts/install-deps.sh); the figures below are the static PNGs.",
                                       why)) +
                "</p>\n";
    } else {
      std::string css = ReadTextFile(interactive_->library.parent_path() / "dygraph.min.css");
      css.erase(std::remove(css.begin(), css.end(), '<'), css.end());  // no "</style>" from a file
      head_extra = "<style>" + css + kChartCss + "</style>\n";
      std::string data = "[";
      for (std::size_t i = 0; i < charts_.size(); ++i) data += (i ? ",\n" : "") + charts_[i];
      data += "]";
      scripts = "<script>\n" + library + "\n</script>\n<script type=\"application/json\" id=\"mb-charts\">" + data +
                "</script>\n<script>\n" + kChartScript + "</script>\n";
    }
  }
  std::string not_drawn;
  if (!not_drawn_.empty()) {
    not_drawn = "<p class=\"warn\">" +
                HtmlEscape(fmt::format("{} more figures not drawn: a report draws at most {} (raise it with "
                                       "motionblocks --max-plots N). Their data is in the command's files. Not drawn: "
                                       "{}.",
                                       not_drawn_.size(), MaxReportFigures(), fmt::join(not_drawn_, ", "))) +
                "</p>\n";
  }
  const std::string page =
      "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>" + HtmlEscape(title_) + "</title>\n" +
      "<style>body{font-family:sans-serif;max-width:1000px;margin:2em auto;color:#222}"
      "table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #bbb;padding:3px 8px;text-align:right}"
      "th{background:#eee}figure{margin:1em 0}img{max-width:100%}.warn{color:#a00}</style>\n" + head_extra +
      "</head><body>\n<h1>" + HtmlEscape(title_) + "</h1>\n" + warning + body_ + not_drawn + scripts +
      "</body></html>\n";
  WriteFileSafely(path, page);
}

}  // namespace mb

#include "tools/report/report.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

#include <fmt/format.h>

#include "engine/output_file.h"
#include "tools/report/run_program.h"

namespace mb {

namespace fs = std::filesystem;

namespace {

// Keeps the first/last point and, per bucket, the points with the smallest and largest y, so that peaks
// survive thinning.
std::vector<std::pair<double, double>> Thin(const Series& s, std::size_t max_points) {
  std::vector<std::pair<double, double>> out;
  const std::size_t n = std::min(s.x.size(), s.y.size());
  if (n <= max_points || max_points < 4) {
    for (std::size_t i = 0; i < n; ++i) out.emplace_back(s.x[i], s.y[i]);
    return out;
  }
  const std::size_t buckets = max_points / 2;
  for (std::size_t b = 0; b < buckets; ++b) {
    const std::size_t lo = b * n / buckets, hi = (b + 1) * n / buckets;
    std::size_t imin = lo, imax = lo;
    for (std::size_t i = lo; i < hi; ++i) {
      if (s.y[i] < s.y[imin]) imin = i;
      if (s.y[i] > s.y[imax]) imax = i;
    }
    out.emplace_back(s.x[std::min(imin, imax)], s.y[std::min(imin, imax)]);
    if (imin != imax) out.emplace_back(s.x[std::max(imin, imax)], s.y[std::max(imin, imax)]);
  }
  return out;
}

// A gnuplot string literal holding `s` as data: single-quoted (gnuplot expands neither backquotes nor
// backslashes there; a quote is written twice), control characters (a newline would end the command)
// written as spaces. Every user string (names, titles, paths) reaches gnuplot only through this.
std::string GnuplotQuote(const std::string& s) {
  std::string out = "'";
  for (char c : s) {
    if (c == '\'') out += '\'';
    out += (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) ? ' ' : c;
  }
  return out + "'";
}

// One line of text in a data-file comment: control characters as spaces.
std::string CommentText(std::string s) {
  for (char& c : s) {
    if (static_cast<unsigned char>(c) < 0x20 || c == 0x7f) c = ' ';
  }
  return s;
}

}  // namespace

std::vector<std::string> FigureFileNames(const std::string& file) {
  const std::string stem = fs::path(file).stem().string();
  return {file, stem + ".dat", stem + ".gp"};
}

std::string RenderFigure(const Figure& figure, const fs::path& directory) {
  fs::create_directories(directory);
  const std::vector<std::string> names = FigureFileNames(figure.file);
  const fs::path png = directory / names[0];
  const fs::path data = directory / names[1];
  const fs::path script = directory / names[2];
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
    gp << "set terminal pngcairo size 900,420 font 'Sans,10'\n";
    gp << "set output " << GnuplotQuote(png.string()) << "\n";
    gp << "set title " << GnuplotQuote(figure.title) << " noenhanced\n";  // every text verbatim, no markup
    gp << "set xlabel " << GnuplotQuote(figure.xlabel) << " noenhanced\n";
    gp << "set ylabel " << GnuplotQuote(figure.ylabel) << " noenhanced\n";
    gp << "set grid\nset key outside right top noenhanced\nset datafile commentschars '#'\n";
    if (figure.log_x) gp << "set logscale x\n";
    if (figure.log_y) gp << "set logscale y\n";
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
    const bool bars = std::any_of(figure.series.begin(), figure.series.end(),
                                  [](const Series& s) { return s.style == "boxes"; });
    if (bars) gp << "set style fill solid 0.7 border -1\nset boxwidth 0.35 absolute\nset yrange [0:*]\n";
    gp << "plot ";
    for (std::size_t i = 0; i < figure.series.size(); ++i) {
      const auto& s = figure.series[i];
      gp << (i ? ", " : "") << GnuplotQuote(data.string()) << " index " << i << " using 1:2 with " << s.style
         << (s.style == "points" ? " pt 7 ps 0.3" : " lw 1.2") << " title " << GnuplotQuote(s.label) << " noenhanced";
    }
    gp << "\n";
    WriteFileSafely(script, gp.str());
  }
  // No shell: the script's path is one argument (absolute, so that a name starting with '-' is no option).
  const fs::path log = directory / "gnuplot.log";
  const int status = RunProgram({"gnuplot", fs::absolute(script).string()}, log);
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

void HtmlReport::Paragraph(const std::string& text) { body_ += "<p>" + HtmlEscape(text) + "</p>\n"; }

void HtmlReport::Table(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows) {
  body_ += "<table>\n<tr>";
  for (const auto& h : header) body_ += "<th>" + HtmlEscape(h) + "</th>";
  body_ += "</tr>\n";
  for (const auto& row : rows) {
    body_ += "<tr>";
    for (const auto& cell : row) body_ += "<td>" + HtmlEscape(cell) + "</td>";
    body_ += "</tr>\n";
  }
  body_ += "</table>\n";
}

void HtmlReport::AddFigure(const Figure& figure, const fs::path& directory) {
  const std::string error = RenderFigure(figure, directory);
  if (error.empty()) {
    Image(figure.file, figure.title);
  } else {
    Warning("Figure missing: " + error);
  }
}

void HtmlReport::Image(const std::string& file, const std::string& caption) {
  body_ += fmt::format("<figure><img src=\"{}\" alt=\"{}\"><figcaption>{}</figcaption></figure>\n", file,
                       HtmlEscape(caption), HtmlEscape(caption));
}

void HtmlReport::Warning(const std::string& text) { body_ += "<p class=\"warn\">" + HtmlEscape(text) + "</p>\n"; }

void HtmlReport::Write(const fs::path& path) const {
  const std::string page =
      "<!DOCTYPE html>\n<html><head><meta charset=\"utf-8\"><title>" + HtmlEscape(title_) + "</title>\n" +
      "<style>body{font-family:sans-serif;max-width:1000px;margin:2em auto;color:#222}"
      "table{border-collapse:collapse;margin:1em 0}td,th{border:1px solid #bbb;padding:3px 8px;text-align:right}"
      "th{background:#eee}figure{margin:1em 0}img{max-width:100%}.warn{color:#a00}</style></head><body>\n" +
      "<h1>" + HtmlEscape(title_) + "</h1>\n" + body_ + "</body></html>\n";
  WriteFileSafely(path, page);
}

}  // namespace mb

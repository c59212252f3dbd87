#pragma once
// Reports that people look at: figures rendered by gnuplot (PNG, pngcairo) and one self-contained HTML page
// per command (tables, paragraphs, figures). No hand-drawn charts.

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

namespace mb {

/// One curve of a figure. `style`: gnuplot's "lines", "linespoints", "points", "dots", "impulses" or "boxes" (bars
/// from 0, width 0.35 in x units: place side-by-side bars at x ± 0.18).
struct Series {
  std::vector<double> x;
  std::vector<double> y;
  std::string label;
  std::string style = "lines";
};

/// A 2-D plot. Series longer than `max_points` are thinned for drawing (min/max per bucket keeps peaks).
struct Figure {
  std::string file;  ///< PNG name inside the report folder, e.g. "residual_vs_time.png"
  std::string title;
  std::string xlabel;
  std::string ylabel;
  std::vector<Series> series;
  bool log_x = false;
  bool log_y = false;
  /// Named x ticks (position, label) instead of numbers, e.g. the steps of a bar chart; empty: numeric ticks.
  std::vector<std::pair<double, std::string>> x_tick_labels{};
  /// Ranges of x [x0, x1] shaded behind the series (e.g. a training window), in x's unit; empty: none.
  std::vector<std::pair<double, double>> shaded_x_ranges{};
  std::size_t max_points = 4000;
};

/// Renders `figure` to `directory/figure.file` with gnuplot. Returns "" on success, else the reason (gnuplot
/// missing or failing) — the caller notes it in the report; a missing figure never loses the numbers.
std::string RenderFigure(const Figure& figure, const std::filesystem::path& directory);

/// The files RenderFigure writes for a figure named `file` (a name or a pattern such as "signal_*.png"): `file`, and
/// its data and gnuplot script, <stem>.dat and <stem>.gp.
std::vector<std::string> FigureFileNames(const std::string& file);

/// An HTML report assembled in order and written once.
class HtmlReport {
 public:
  explicit HtmlReport(std::string title) : title_(std::move(title)) {}
  void Heading(const std::string& text);
  void Paragraph(const std::string& text);
  /// A table: header row and rows of cells (already formatted).
  void Table(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows);
  /// Renders the figure into the report's folder and embeds it (or notes why it is missing).
  void AddFigure(const Figure& figure, const std::filesystem::path& directory);
  /// Shows the image `file` (a name inside the report's folder: PNG or SVG) with `caption`.
  void Image(const std::string& file, const std::string& caption);
  /// A paragraph marked as a warning (what is missing from the report and why).
  void Warning(const std::string& text);
  /// Writes `path` (report.html). @throws std::runtime_error if it cannot be written.
  void Write(const std::filesystem::path& path) const;

 private:
  std::string title_;
  std::string body_;
};

/// Escapes &, <, > and " for HTML text and attribute values.
std::string HtmlEscape(const std::string& text);

}  // namespace mb

#pragma once
// Reports that people look at: figures rendered by gnuplot (PNG, pngcairo) and one self-contained HTML page
// per command (tables, paragraphs, figures). No hand-drawn charts. With InteractiveCharts, each figure is also an
// interactive chart (zoom, pan, hover read-out, series toggles, x axes linked) drawn by Debian's libjs-dygraphs, read
// at report time from its installed path and embedded inline; the PNGs stay as the static fallback and for print.

#include <cstddef>
#include <filesystem>
#include <optional>
#include <string>
#include <utility>
#include <vector>

namespace mb {

/// One curve of a figure. `style`: gnuplot's "lines", "linespoints", "points", "dots", "steps" (y_i held until
/// x_{i+1}: a histogram from its bins' left edges, the last point at the right edge), "impulses" or "boxes" (bars
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
  /// Vertical lines at x with a label (e.g. the periods a diagnosis chose), in x's unit; empty: none.
  std::vector<std::pair<double, std::string>> x_marks{};
  /// Interactive charts with the same non-empty `x_link` zoom and pan together (the time plots of one record).
  std::string x_link{};
  /// The y range shown [y0, y1] (e.g. without a few outliers), in y's unit; none: every point.
  std::optional<std::pair<double, double>> y_range{};
};

/// The subfolder of an output folder that holds what draws its pictures: each figure's gnuplot script and data, the
/// gnuplot log and a diagram's DOT text. The output folder itself keeps what a user opens (report, JSON, CSV, PNG).
inline constexpr const char* kPlotFolder = "plot";

/// Renders `figure` to `directory/figure.file` with gnuplot, from the data and script it writes into
/// `directory`/plot/ (<stem>.dat, <stem>.gp; gnuplot's messages in plot/gnuplot.log). The script names its data and
/// its PNG relative to its own folder and goes there first, so `gnuplot plot/<stem>.gp` redraws the PNG from any
/// working folder, wherever the output folder was moved. Returns "" on success, else the reason (gnuplot missing or
/// failing) — the caller notes it in the report; a missing figure never loses the numbers.
std::string RenderFigure(const Figure& figure, const std::filesystem::path& directory);

/// The files a report writes for a figure named `file` (a name or a pattern such as "signal_*.png"), relative to
/// its output folder, in this order: `file`; its data and gnuplot script, plot/<stem>.dat and plot/<stem>.gp
/// (RenderFigure); its full data <stem>.full.csv (interactive reports; a name no measurement log is likely to have,
/// as an input in the output folder is refused under these); and plot/gnuplot.log (shared by the folder's figures).
std::vector<std::string> FigureFileNames(const std::string& file);

/// Where Debian's libjs-dygraphs (scripts/install-deps.sh) installs the charting library.
inline constexpr const char* kDygraphsPath = "/usr/share/javascript/dygraphs/dygraph.min.js";

/// How a report draws its figures interactively.
struct InteractiveCharts {
  /// The charting library (dygraphs 2.x, minified), read when the report is written and embedded inline. Missing or
  /// unreadable: the report shows the PNGs and says why.
  std::filesystem::path library = kDygraphsPath;
  /// Pixel columns a line is decimated to (min/max per column: chart_data.h); dots keep ~1.5 px cells.
  std::size_t columns = 2000;
};

/// Most figures one report draws unless raised (`motionblocks --max-plots N`): a run logging 20,000 signals would
/// otherwise start 20,000 gnuplots. The figures beyond are listed by title in the report, not drawn.
inline constexpr std::size_t kDefaultMaxReportFigures = 100;

/// Sets the most figures each report draws (process-wide, like the progress mode: call it at setup).
/// @throws std::invalid_argument if `count` is 0.
void SetMaxReportFigures(std::size_t count);
std::size_t MaxReportFigures();

/// An HTML report assembled in order and written once.
class HtmlReport {
 public:
  /// `interactive`: draw figures as interactive charts (each figure's full data in <stem>.full.csv beside the report),
  /// with the PNGs as fallback; none: PNGs only.
  explicit HtmlReport(std::string title, std::optional<InteractiveCharts> interactive = std::nullopt)
      : title_(std::move(title)), interactive_(std::move(interactive)) {}
  void Heading(const std::string& text);
  /// A heading that a link "#`id`" goes to (FigureId's characters).
  void Heading(const std::string& text, const std::string& id);
  void Paragraph(const std::string& text);
  /// A table: header row and rows of cells (already formatted).
  void Table(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows);
  /// The same, the first cell of row i a link to "#`row_links[i]`" (a Heading's or FigureId's id); no link where
  /// row_links[i] is empty or i is beyond it.
  void Table(const std::vector<std::string>& header, const std::vector<std::vector<std::string>>& rows,
             const std::vector<std::string>& row_links);
  /// Renders the figure into the report's folder and embeds it (or notes why it is missing); beyond
  /// MaxReportFigures() figures, only notes its title (Write lists them). Interactive (and the
  /// figure no bar chart and without named x ticks): also writes directory/<stem>.full.csv (FigureCsv) and adds the
  /// chart (ChartJson), linked to the CSV. @throws std::runtime_error if the CSV cannot be written.
  void AddFigure(const Figure& figure, const std::filesystem::path& directory);
  /// Shows the image `file` (a name inside the report's folder: PNG or SVG) with `caption`.
  void Image(const std::string& file, const std::string& caption);
  /// Appends `html` as it is: markup built by a function that escaped every string in it (ClickableDiagramHtml,
  /// diagram_panel.h), never a user's text.
  void Fragment(const std::string& html) { body_ += html; }
  /// A paragraph marked as a warning (what is missing from the report and why).
  void Warning(const std::string& text);
  /// A heat map as a table (no script: it shows and prints as it is): cell (r, c) coloured by `values[r][c]` on one
  /// scale (viridis: dark purple at the map's smallest finite value, yellow at its largest; one colour if they are
  /// equal), `text[r][c]` written in it; a non-finite value is a grey cell. The rows are named by `row_names` under
  /// `row_label`, the columns by `column_names` under `column_label`; `caption` above, the scale's two ends below.
  /// Drawn whatever MaxReportFigures(). @throws std::invalid_argument if `values` or `text` is not
  /// row_names.size() × column_names.size().
  void HeatMap(const std::string& caption, const std::string& row_label, const std::vector<std::string>& row_names,
               const std::string& column_label, const std::vector<std::string>& column_names,
               const std::vector<std::vector<double>>& values, const std::vector<std::vector<std::string>>& text);
  /// Writes `path` (report.html): one file, the charting library, the charts' data (ScriptSafeJson) and the page's
  /// script inline. With charts and the library missing or unreadable, no script: the PNGs and a warning naming the
  /// file and the package. @throws std::runtime_error if it cannot be written.
  void Write(const std::filesystem::path& path) const;

 private:
  std::string title_;
  std::optional<InteractiveCharts> interactive_;
  std::string body_;
  std::vector<std::string> charts_;  // ChartJson of each interactive chart (ScriptSafeJson text), in page order
  std::size_t figures_ = 0;          // figures drawn (AddFigure)
  std::vector<std::string> not_drawn_;  // titles of the figures beyond MaxReportFigures()
};

/// The id of a figure's element in its report (AddFigure, interactive or not): "fig-" and the stem of its PNG name,
/// each character outside [A-Za-z0-9_-] written '_' ("effect_1.png" → "fig-effect_1"): what a link "#fig-…" names.
std::string FigureId(const std::string& file);

/// Escapes &, <, > and " for HTML text and attribute values.
std::string HtmlEscape(const std::string& text);

}  // namespace mb

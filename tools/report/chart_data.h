#pragma once
// What an interactive chart of a report holds (report.h): the series decimated for display without losing a peak,
// as the rows the charting library (Debian's libjs-dygraphs) reads, the full data as CSV, and JSON that is safe
// inside an HTML <script> element.

#include <cstddef>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace mb {

struct Figure;

/// Min/max decimation of a line for display: the samples 0..n−1 (n = y.size()) are cut into `columns` runs of
/// consecutive indices (one per pixel column, runs of ⌊n/columns⌋ or ⌈n/columns⌉ samples), and of each run the
/// indices of its smallest and of its largest finite y are kept, with the first and the last sample. Returns the
/// kept indices, increasing, at most 2·columns + 2 of them: every local extreme that is a run's extreme survives, so a
/// one-sample spike is never lost. Non-finite values are kept only as the first or last sample. With n ≤ 2·columns
/// (or columns = 0) every index is returned.
std::vector<std::size_t> DecimateMinMax(const std::vector<double>& y, std::size_t columns);

/// Decimation of a scatter (x, y) for display: the bounding box of the finite points is cut into columns × rows
/// cells; of each occupied cell the first point is kept, and of each column the points with the smallest and the
/// largest y (the envelope is exact). Returns the kept indices, increasing. With n ≤ 2·columns every finite point is
/// returned. Pairs with a non-finite x or y are dropped.
std::vector<std::size_t> DecimateScatter(const std::vector<double>& x, const std::vector<double>& y,
                                         std::size_t columns, std::size_t rows);

/// A figure as the interactive chart reads it: {"title", "xlabel", "ylabel", "labels" (x's label, then each series'
/// label made unique), "points" (per series: drawn as dots), "steps" (per series: drawn as steps, style "steps"),
/// "markers" (per series: a line with a marker at each point, style "linespoints"),
/// "data" (rows [x, y₁|null, …] sorted by x: the series
/// decimated — DecimateMinMax for lines, DecimateScatter for dots — and merged on equal x), "logx", "logy", "link"
/// (Figure::x_link), "shaded" ([[x0, x1]]), "marks" ([[x, label]]), "samples" (the longest series' length), "decimated"
/// (whether any series lost points), "csv" (the full data's file name), "yrange" ([y0, y1] or null)}. Values are
/// rounded to 7 significant digits (the display's precision; the CSV keeps every digit). Text is raw: escape it where
/// it meets HTML.
nlohmann::json ChartJson(const Figure& figure, const std::string& csv_file, std::size_t columns);

/// The figure's full data as CSV text: with series sharing one x vector, a column for x (headed by the x label)
/// and one per series, in the samples' order; otherwise three columns "series", "x", "y". Every value with 17
/// significant digits, text fields quoted (a quote doubled). Non-finite values are empty fields.
std::string FigureCsv(const Figure& figure);

/// `value` as JSON text that can stand inside an HTML <script> element: nlohmann-json's dump (invalid UTF-8
/// replaced by U+FFFD) with every '<' written as \u003c, so that no "</script>" or "<!--" can occur in it. '<' occurs
/// only inside JSON strings, where \u003c is the same character.
std::string ScriptSafeJson(const nlohmann::json& value);

}  // namespace mb

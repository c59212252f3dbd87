#pragma once
// The picture of a parameter sweep (`motionblocks sweep`, `sweep-merge`; tools/batch/sweep.h): DIR/report.html, one
// self-contained page (HtmlReport, report.h: interactive charts with the gnuplot PNGs as fallback) written from the
// sweep's own record in DIR, so that a sweep run, resumed or merged from shards gets the same page: each of the
// diagram's metrics against each swept parameter (one chart per metric × parameter), a heat map of each metric when
// a grid sweeps exactly two parameters, the smallest and largest value of each metric with its run, the failed runs
// with their errors, and the runs as runs.csv holds them.

#include <cstddef>
#include <filesystem>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace mb {

/// The report's file name in the sweep's folder.
inline constexpr const char* kSweepReportFile = "report.html";

/// Most runs the report's tables list (the runs, the failed runs); every run is in runs.csv.
inline constexpr std::size_t kSweepReportMaxRows = 1000;

/// Most cells (rows × columns) a heat map has; a larger grid is drawn only as charts.
inline constexpr std::size_t kSweepReportMaxHeatMapCells = 2500;

/// Most distinct values a parameter whose values are not all numbers (a string, an array) is drawn with, as named
/// categories on the x axis; with more, its charts are left out (a note says so).
inline constexpr std::size_t kSweepReportMaxCategories = 30;

/// The names WriteSweepReport writes into the sweep's folder, as OutputFolder::names (output_files.h) takes them:
/// report.html and the figures' files (FigureFileNames of "sweep_*.png").
std::vector<std::string> SweepReportFileNames();

/// Writes `folder`/report.html and its figures beside it (sweep_<k>_<metric>_vs_<parameter>.png, their gnuplot
/// data and script in plot/, their full data in sweep_<k>_….full.csv) from `folder`/runs.csv and `runs_json`, the
/// content of `folder`/runs.json as the sweep wrote it. The rows, their values and metrics come from runs.csv, cell
/// for cell; from `runs_json` only "kind", "description", "diagram", "set", "parameters" (which of runs.csv's columns
/// are parameters) and "metric_units" are read.
///
/// What the page shows, in runs.csv's units (SI; each metric's unit as the diagram declares it):
///   - per swept parameter and metric, the metric of every "ok" run against the parameter's value (a metric cell
///     that is empty or not a finite number is left out). Runs whose x values are all distinct are joined by a line
///     in x order; in a grid of two parameters, one line per value of the other parameter (at most 8 of them; else
///     dots). Values that are not all numbers are drawn as named categories (at most kSweepReportMaxCategories);
///   - a heat map per metric (HtmlReport::HeatMap) when "kind" is "grid" and exactly two parameters are swept: rows
///     the first parameter's values, columns the second's, in sweep order (at most kSweepReportMaxHeatMapCells);
///   - the failed runs (status other than "ok") with their values and error, and runs.csv's rows as a table, each
///     at most kSweepReportMaxRows (the rest counted).
/// A figure gnuplot cannot draw is a note in the page, and figures beyond MaxReportFigures() are listed, not drawn.
/// @throws std::runtime_error if `runs_json` is no object, runs.csv cannot be read or its columns are not id, status,
/// the parameters, the metrics, wall_time_s and error; or if a file cannot be written.
void WriteSweepReport(const std::filesystem::path& folder, const nlohmann::json& runs_json);

}  // namespace mb

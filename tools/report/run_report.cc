#include "tools/report/run_report.h"

#include <fmt/format.h>

#include "tools/report/diagram_drawing.h"
#include "tools/report/output_files.h"
#include "tools/report/report.h"

namespace mb {

namespace fs = std::filesystem;
using nlohmann::json;

namespace {

constexpr const char* kSignalsFile = "signals.csv";
constexpr const char* kSummaryFile = "summary.json";
constexpr const char* kReportFile = "report.html";
constexpr const char* kSignalFigures = "signal_{}.png";  // one per logged signal, numbered

// A logged signal's axis label: its name, and its unit when it is a connector's (the only signals with a declared
// unit; a block port's is the block's documented one).
std::string SignalLabel(const Diagram& diagram, const std::string& name) {
  for (const auto& c : diagram.inputs()) {
    if (c.name == name && !c.unit.empty()) return fmt::format("{} [{}]", name, c.unit);
  }
  for (const auto& c : diagram.outputs()) {
    if (c.name == name && !c.unit.empty()) return fmt::format("{} [{}]", name, c.unit);
  }
  return name;
}

}  // namespace

fs::path RunSignalsFile(const fs::path& out) { return out / kSignalsFile; }

std::vector<std::string> RunOutputNames() {
  std::vector<std::string> names{kSignalsFile, kSummaryFile, kReportFile};
  for (const auto& name : FigureFileNames(fmt::format(kSignalFigures, "*"))) names.push_back(name);
  for (const auto& name : DiagramDrawingFileNames()) names.push_back(name);
  return names;
}

int RemoveEarlierRunFiles(const fs::path& out) {
  std::error_code error;
  int removed = 0;
  for (const auto& path : OutputFilesIn(out, RunOutputNames())) {
    if (!fs::remove(path, error) && error) {
      throw std::runtime_error(fmt::format("{}: cannot remove this file of an earlier run ({}): remove it, or give "
                                           "another --out",
                                           path.string(), error.message()));
    }
    ++removed;
  }
  return removed;
}

json RunSummaryJson(const Diagram& diagram, const RunFiles& files, const RunOutcome& outcome) {
  const SimulationResult& result = outcome.result;
  json summary = {{"diagram", fs::absolute(files.diagram).string()},
                  {"name", diagram.name()},
                  {"overrides", files.overrides},
                  {"metrics", result.metrics},
                  {"metric_units", json::object()},
                  {"solver",
                   {{"type", diagram.solver().type},
                    {"steps", result.solver_stats.steps},
                    {"rhs_evaluations", result.solver_stats.rhs_evaluations},
                    {"roots_found", result.solver_stats.roots_found},
                    {"reinitialisations", result.solver_stats.reinitialisations}}},
                  {"wall_time_s", result.wall_time_s},
                  {"samples", outcome.samples}};
  for (const auto& m : diagram.metrics()) summary["metric_units"][m.name] = m.unit;
  return summary;
}

void WriteRunResults(const Diagram& diagram, const RunFiles& files, const RunOutcome& outcome) {
  const SimulationResult& result = outcome.result;
  WriteJsonFile(RunSummaryJson(diagram, files, outcome), files.out / kSummaryFile);

  HtmlReport report(fmt::format("motionblocks run: {}", diagram.name()), InteractiveCharts{});
  report.Paragraph(fmt::format("Diagram {} simulated from {} s to {} s with {} ({} steps) in {:.3f} s wall time.",
                               files.diagram, diagram.experiment().start_time, diagram.experiment().stop_time,
                               diagram.solver().type, result.solver_stats.steps, result.wall_time_s));
  AddDiagramDrawing(&report, diagram, {}, files.out);
  if (!result.metrics.empty()) {
    std::vector<std::vector<std::string>> rows;
    for (const auto& m : diagram.metrics()) {
      rows.push_back({m.name, fmt::format("{:.6g}", result.metrics.at(m.name)), m.unit, std::string(Name(m.type)),
                      m.signal});
    }
    report.Heading("Metrics");
    report.Table({"metric", "value", "unit", "type", "signal"}, rows);
  }
  report.Heading("Logged signals");
  report.Paragraph(fmt::format("{} samples per signal in {} (the charts: its envelope, each stretch's minimum and "
                               "maximum, in {} rows; zoom one and the others follow).",
                               outcome.samples, kSignalsFile, result.log.time.size()));
  for (std::size_t i = 0; i < result.log.names.size(); ++i) {
    Figure f;
    f.file = fmt::format(kSignalFigures, i);
    f.title = result.log.names[i];
    f.xlabel = "time [s]";
    f.ylabel = SignalLabel(diagram, result.log.names[i]);
    f.x_link = "time";
    f.series.push_back({result.log.time, result.log.columns[i], result.log.names[i], "lines"});
    report.AddFigure(f, files.out);
  }
  report.Write(files.out / kReportFile);
}

}  // namespace mb

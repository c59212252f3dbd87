// Running a sweep (sweep.h, sweep_runner.h) and writing its results: each run's diagram with the sweep's values written
// in (ApplySweepAssignments) and simulated (SweepRunner::Execute), the rows appended to runs.csv as runs finish and
// read back on resume (ReadDoneRows), runs.csv and runs.json rewritten in sweep order at the end (WriteSweepResults)
// with the report drawn from them (tools/report/sweep_report.h), and RunSweep's TBB threads. Reading the sweep file
// and generating its runs: sweep_spec.cc.
#include "tools/batch/sweep.h"

#include <algorithm>
#include <charconv>
#include <chrono>
#include <cmath>
#include <fstream>
#include <map>
#include <memory>
#include <mutex>
#include <optional>
#include <stdexcept>
#include <thread>

#include <fmt/format.h>
#include <tbb/parallel_for.h>
#include <tbb/task_arena.h>

#include "engine/csv.h"
#include "engine/diagram_loader.h"
#include "engine/diagram_schema.h"
#include "engine/output_file.h"
#include "engine/text_excerpt.h"
#include "tools/batch/shard.h"
#include "tools/batch/sweep_runner.h"
#include "tools/report/output_files.h"
#include "tools/report/progress.h"
#include "tools/report/sweep_report.h"

namespace mb {

namespace fs = std::filesystem;
using json = nlohmann::json;

namespace {

constexpr const char* kExperimentSection = "defaultExperiment";
constexpr const char* kSolverSection = "solver";

std::vector<std::string> Header(const SweepSpec& spec, const std::vector<std::string>& metric_names) {
  std::vector<std::string> h = {"id", "status"};
  h.insert(h.end(), spec.parameters.begin(), spec.parameters.end());
  h.insert(h.end(), metric_names.begin(), metric_names.end());
  h.push_back("wall_time_s");
  h.push_back("error");
  return h;
}

// The parameter cells of a run, in column order ("" where the run does not assign the key).
std::vector<std::string> ParameterCells(const SweepSpec& spec, const SweepRun& run) {
  std::vector<std::string> cells;
  for (const auto& key : spec.parameters) {
    std::string cell;
    for (const auto& [k, v] : run.assignments) {
      if (k == key) cell = SweepValueText(v);
    }
    cells.push_back(cell);
  }
  return cells;
}

std::string RowLine(const SweepSpec& spec, const SweepRun& run, const SweepRow& row,
                    const std::vector<std::string>& metric_names) {
  std::vector<std::string> cells = {row.id, row.status};
  const auto params = ParameterCells(spec, run);
  cells.insert(cells.end(), params.begin(), params.end());
  for (const auto& m : metric_names) {
    const auto it = row.metrics.find(m);
    cells.push_back(it == row.metrics.end() ? "" : fmt::format("{:.17g}", it->second));
  }
  cells.push_back(fmt::format("{:.6f}", row.wall_time_s));
  cells.push_back(row.error);
  return CsvLine(cells);
}

// A runs.csv cell as a finite number; nullopt for anything else (nan, inf, text, trailing characters).
std::optional<double> FiniteCell(const std::string& cell) {
  double value = 0.0;
  const auto [end, error] = std::from_chars(cell.data(), cell.data() + cell.size(), value);
  if (error != std::errc() || end != cell.data() + cell.size() || !std::isfinite(value)) return std::nullopt;
  return value;
}

// Rows recorded "ok" in an existing runs.csv, by id (the last row of an id wins: a retried run is appended).
std::map<std::string, SweepRow> ReadDoneRows(const fs::path& csv, const SweepSpec& spec,
                                            const std::vector<std::string>& metric_names) {
  std::map<std::string, SweepRow> done;
  if (!fs::exists(csv)) return done;
  const CsvTextTable table = ReadCsvTextTable(csv.string());
  if (table.header.empty()) return done;
  const auto expected = Header(spec, metric_names);
  if (table.header != expected) {
    throw std::runtime_error(fmt::format("{} has the columns [{}], this sweep writes [{}]: it was written by another "
                                         "sweep or diagram; use another --out or delete it",
                                         csv.string(), fmt::join(table.header, ", "), fmt::join(expected, ", ")));
  }
  const std::size_t first_metric = 2 + spec.parameters.size();
  for (std::size_t r = 0; r < table.rows.size(); ++r) {
    const auto& cells = table.rows[r];
    const std::size_t line_number = table.row_lines[r];
    if (cells.size() != expected.size()) continue;  // a row cut short by an interrupted run: run it again
    const std::optional<std::size_t> position = spec.PositionOf(cells[0]);
    if (!position) {
      throw std::runtime_error(fmt::format("{}:{}: run id '{}' is not in this sweep ({} runs): written by another "
                                           "sweep; use another --out or delete it",
                                           csv.string(), line_number, Excerpt(cells[0]), spec.run_count()));
    }
    const SweepRun run = spec.run(*position);
    const auto params = ParameterCells(spec, run);
    for (std::size_t p = 0; p < params.size(); ++p) {
      if (cells[2 + p] != params[p]) {
        throw std::runtime_error(fmt::format("{}:{}: run {} has {} = {} there, but this sweep gives {}: written by "
                                             "another sweep; use another --out or delete it",
                                             csv.string(), line_number, run.id, spec.parameters[p], cells[2 + p],
                                             params[p]));
      }
    }
    if (cells[1] != "ok") {
      done.erase(run.id);
      continue;
    }
    SweepRow row;
    row.id = run.id;
    row.status = "ok";
    row.assignments = run.assignments;
    row.resumed = true;
    // A row is kept only if every metric cell reads back as a finite number (empty: a metric the run did not give):
    // a NaN or infinite metric, or an edited cell, is no result to keep; the run is run again.
    bool finite = true;
    for (std::size_t m = 0; m < metric_names.size() && finite; ++m) {
      const std::string& cell = cells[first_metric + m];
      if (cell.empty()) continue;
      const std::optional<double> value = FiniteCell(cell);
      if (value) row.metrics[metric_names[m]] = *value;
      finite = value.has_value();
    }
    const std::optional<double> wall_time = FiniteCell(cells[first_metric + metric_names.size()]);
    if (!finite || !wall_time) {
      done.erase(run.id);
      continue;
    }
    row.wall_time_s = *wall_time;
    done[run.id] = row;
  }
  return done;
}

json RowJson(const SweepRow& row) {
  json params = json::object();
  for (const auto& [k, v] : row.assignments) params[k] = v;
  json j = {{"id", row.id},           {"status", row.status},           {"parameters", params},
            {"metrics", row.metrics}, {"wall_time_s", row.wall_time_s}};
  if (!row.error.empty()) j["error"] = row.error;
  return j;
}


}  // namespace

std::string SweepValueText(const json& value) {
  return value.is_string() ? value.get<std::string>() : value.dump();
}

json ApplySweepAssignments(json diagram, const std::vector<std::pair<std::string, json>>& assignments,
                           const std::string& source) {
  std::vector<ParameterOverride> overrides;  // "solver.step" and "defaultExperiment.stopTime" as --set takes them
  for (const auto& [key, value] : assignments) {
    const auto dot = key.find('.');
    overrides.push_back(ParameterOverride{key.substr(0, dot), key.substr(dot + 1), value});
  }
  ApplyOverrides(&diagram, overrides, source);
  return diagram;
}

namespace {

// Every element named by the sweep is checked before anything runs (DiagramError lists the elements); a misspelled
// defaultExperiment.<key> or solver.<key> would otherwise be ignored by every run.
void CheckSweepSettings(const json& base, const SweepSpec& spec, const std::string& source) {
  std::vector<std::pair<std::string, json>> all = spec.fixed;
  const auto assigned = spec.AllAssignments();
  all.insert(all.end(), assigned.begin(), assigned.end());
  // A misspelled defaultExperiment.<key> or solver.<key> would otherwise be ignored by every run.
  std::vector<std::string> problems;
  for (const auto& p : DiagramSchemaProblems(ApplySweepAssignments(base, all, source))) {
    if (p.pointer.rfind(fmt::format("/{}/", kExperimentSection), 0) == 0 ||
        p.pointer.rfind(fmt::format("/{}/", kSolverSection), 0) == 0) {
      problems.push_back(p.Text() + " (set by the sweep)");
    }
  }
  if (!problems.empty()) throw DiagramError(source, problems);
}

// Rewrites runs.csv and runs.json in sweep order (one row per run), counting the runs run now and those failed; then
// report.html from them (with `report`).
void WriteSweepResults(const fs::path& diagram_path, const SweepSpec& spec, const fs::path& out, bool report,
                       SweepOutcome* outcome) {
  const fs::path csv = out / "runs.csv";
  std::string text = CsvLine(Header(spec, outcome->metric_names)) + "\n";
  json rows = json::array();
  for (std::size_t i = 0; i < spec.run_count(); ++i) {
    const SweepRow& row = outcome->rows[i];
    if (!row.resumed) ++outcome->ran;
    if (row.status != "ok") ++outcome->failed;
    text += RowLine(spec, spec.run(i), row, outcome->metric_names) + "\n";
    rows.push_back(RowJson(row));
  }
  WriteFileSafely(csv, text);
  json fixed = json::object();
  for (const auto& [k, v] : spec.fixed) fixed[k] = v;
  const json summary = {{"diagram", fs::absolute(diagram_path).string()},
                        {"kind", spec.kind},
                        {"description", spec.description},
                        {"seed", spec.seed},
                        {"set", fixed},
                        {"parameters", spec.parameters},
                        {"metric_units", outcome->metric_units},
                        {"runs", rows}};
  WriteJsonFile(summary, out / "runs.json");
  if (report) WriteSweepReport(out, summary);
}

}  // namespace

struct SweepRunner::State {
  State(const fs::path& diagram, const SweepSpec& sweep, const fs::path& folder, const SweepOptions& run_options)
      : diagram_path(diagram), spec(sweep), out(folder), options(run_options), base(ReadDiagramJson(diagram)),
        source(diagram.string()) {}
  fs::path diagram_path;
  const SweepSpec& spec;
  fs::path out;
  SweepOptions options;
  json base;
  std::string source;
  SweepOutcome outcome;
  std::mutex mutex;  // guards the appended runs.csv, the progress line and the counters
  std::ofstream append;
  std::unique_ptr<ProgressLine> progress;
  std::size_t todo = 0;
  std::size_t finished = 0;
};

SweepRunner::SweepRunner(const fs::path& diagram_path, const SweepSpec& spec, const fs::path& out,
                         const SweepOptions& options)
    : state_(std::make_unique<State>(diagram_path, spec, out, options)) {
  for (const auto& m : state_->base.value("metrics", json::array())) {
    state_->outcome.metric_names.push_back(m.value("name", ""));
    state_->outcome.metric_units[m.value("name", "")] = m.value("unit", "");
  }
  CheckSweepSettings(state_->base, spec, state_->source);
}

SweepRunner::~SweepRunner() = default;

const std::vector<std::string>& SweepRunner::metric_names() const { return state_->outcome.metric_names; }

std::vector<std::size_t> SweepRunner::Start() {
  State& s = *state_;
  fs::create_directories(s.out);
  const fs::path csv = s.out / "runs.csv";
  std::map<std::string, SweepRow> done;
  if (s.options.resume) {
    done = ReadDoneRows(csv, s.spec, s.outcome.metric_names);
  } else {
    fs::remove(csv);
  }
  s.outcome.rows.resize(s.spec.run_count());
  std::vector<std::size_t> todo;
  for (std::size_t i = 0; i < s.spec.run_count(); ++i) {
    const auto it = done.find(SweepRunId(s.spec.kept.empty() ? i : s.spec.kept[i]));
    if (it != done.end()) {
      s.outcome.rows[i] = it->second;
      ++s.outcome.resumed;
    } else {
      todo.push_back(i);
    }
  }
  const bool new_file = !fs::exists(csv) || fs::file_size(csv) == 0;
  s.append.open(csv, std::ios::app);
  if (!s.append) throw std::runtime_error("cannot write " + csv.string());
  if (new_file) s.append << CsvLine(Header(s.spec, s.outcome.metric_names)) << "\n" << std::flush;
  s.todo = todo.size();
  if (s.options.progress) {
    s.progress = std::make_unique<ProgressLine>(fmt::format("sweep {} ({} runs, {} to run)",
                                                            s.diagram_path.filename().string(),
                                                            s.spec.run_count(), todo.size()));
    if (!todo.empty()) s.progress->Update(0.0);
  }
  return todo;
}

SweepRow SweepRunner::Execute(std::size_t position) const {
  const State& s = *state_;
  const SweepRun run = s.spec.run(position);
  SweepRow row;
  row.id = run.id;
  row.assignments = run.assignments;
  const auto start = std::chrono::steady_clock::now();
  try {
    json j = ApplySweepAssignments(s.base, s.spec.fixed, s.source);
    j = ApplySweepAssignments(std::move(j), run.assignments, s.source);
    const Diagram diagram =
        BuildDiagram(j, s.diagram_path.parent_path(), fmt::format("{} (sweep run {})", s.source, run.id));
    Simulator simulator(diagram);
    const SimulationResult result = simulator.Run();
    row.metrics = result.metrics;
    row.status = "ok";
    if (s.options.save_logs) {
      const fs::path dir = s.out / "runs" / run.id;
      fs::create_directories(dir);
      WriteSignalLog(result.log, dir / "signals.csv");
    }
    if (s.options.on_result) s.options.on_result(position, result);
  } catch (const std::exception& e) {
    row.status = "failed";
    row.error = e.what();
  }
  row.wall_time_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  return row;
}

void SweepRunner::Record(std::size_t position, SweepRow row) {
  State& s = *state_;
  std::lock_guard<std::mutex> lock(s.mutex);
  s.append << RowLine(s.spec, s.spec.run(position), row, s.outcome.metric_names) << "\n" << std::flush;
  ++s.finished;
  if (s.progress) s.progress->Update(static_cast<double>(s.finished) / static_cast<double>(s.todo));
  s.outcome.rows.at(position) = std::move(row);
}

SweepOutcome SweepRunner::Finish() {
  State& s = *state_;
  if (s.progress && s.todo > 0) s.progress->Done();
  s.append.close();
  WriteSweepResults(s.diagram_path, s.spec, s.out, s.options.report, &s.outcome);
  return std::move(s.outcome);
}

SweepOutcome RunSweep(const fs::path& diagram_path, const SweepSpec& spec, const fs::path& out,
                      const SweepOptions& options) {
  SweepRunner runner(diagram_path, spec, out, options);
  const std::vector<std::size_t> todo = runner.Start();
  const int jobs = options.jobs > 0 ? options.jobs
                                    : std::max(1, static_cast<int>(std::thread::hardware_concurrency()));
  tbb::task_arena arena(jobs);
  arena.execute([&] {
    tbb::parallel_for(tbb::blocked_range<std::size_t>(0, todo.size(), 1),
                      [&](const tbb::blocked_range<std::size_t>& r) {
                        for (std::size_t k = r.begin(); k != r.end(); ++k) runner.Record(todo[k], runner.Execute(todo[k]));
                      },
                      tbb::simple_partitioner());
  });
  return runner.Finish();
}

std::vector<std::string> SweepOutputNames() {
  std::vector<std::string> outputs = {"runs.csv", "runs.json", kShardManifest};
  for (const auto& name : SweepReportFileNames()) outputs.push_back(name);
  return outputs;
}

namespace {

// Memory a sweep's rows take by the time runs.csv and runs.json are written (measured: 100,000 runs of one parameter
// and two metrics peaked at 245 MB), per run [bytes].
constexpr double kSweepBytesPerRun = 2500.0;

}  // namespace

void NoteSweepMemory(const SweepSpec& spec) {
  if (spec.run_count() <= kDefaultMaxSweepRuns) return;
  ProgressNote(fmt::format("sweep: {} runs; every row is kept until runs.csv and runs.json are written at the end: "
                           "about {:.1f} GB of memory (more with more parameters and metrics)",
                           spec.run_count(), static_cast<double>(spec.run_count()) * kSweepBytesPerRun / 1e9));
}

void PrintSweepSummary(const SweepOutcome& outcome, const std::string& kind, const std::string& shard_label,
                       const std::string& folder, bool saved_logs, std::ostream& out) {
  out << fmt::format("{} runs ({}{}): {} run now, {} already done, {} failed\n", outcome.rows.size(), kind,
                     shard_label.empty() ? "" : ", shard " + shard_label, outcome.ran, outcome.resumed,
                     outcome.failed);
  for (const auto& row : outcome.rows) {
    if (row.status != "ok") out << fmt::format("  run {} failed: {}\n", row.id, row.error);
  }
  out << fmt::format("wrote {0}/runs.csv, {0}/runs.json, {0}/{1}{2}\n", folder, kSweepReportFile,
                     saved_logs ? ", runs/<id>/signals.csv" : "");
}

}  // namespace mb

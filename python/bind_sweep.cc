// motionblocks.sweep: `motionblocks sweep` as a call (tools/batch RunSweep): the runs in parallel (TBB), returned
// as a SweepResult — one dict per run, and a DataFrame of them. The settings made on the Diagram with set() apply
// to every run (as the sweep file's "set").

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <optional>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <pybind11/stl.h>

#include "engine/registry.h"
#include "python/bindings.h"
#include "tools/batch/sweep.h"
#include "tools/report/temporary_folder.h"

namespace mb::python {

namespace fs = std::filesystem;

namespace {

py::dict RowDict(const SweepRow& row) {
  py::dict d;
  d["id"] = row.id;
  d["status"] = row.status;
  for (const auto& [key, value] : row.assignments) d[py::str(key)] = FromJson(value);
  for (const auto& [name, value] : row.metrics) d[py::str(name)] = value;
  d["wall_time_s"] = row.wall_time_s;
  d["error"] = row.error;
  return d;
}

// A swept key's unit: a parameter's SI unit (its block type's declaration), seconds for the experiment's times and
// the solver's steps; "" when unknown (a subsystem's inner element, a dimensionless parameter).
std::string KeyUnit(const DiagramDocument& document, const std::string& key) {
  const auto dot = key.find('.');
  if (dot == std::string::npos) return "";
  const std::string element = key.substr(0, dot);
  const std::string name = key.substr(dot + 1, key.find('[', dot) - dot - 1);  // "gains[2]": gains
  if (DiagramDocument::IsSettingSection(element) && !document.Has(element)) {
    return name == "startTime" || name == "stopTime" || name == "stepSize" || name == "step" || name == "maxStep" ? "s"
                                                                                                                   : "";
  }
  if (!document.Has(element)) return "";
  const BlockType* type = BlockRegistry::Global().Find(document.TypeOf(element));
  if (type == nullptr) return "";
  for (const auto& spec : type->parameters) {
    if (spec.name == name) return spec.unit;
  }
  return "";
}

/// motionblocks.SweepResult: the runs of a sweep, as the list of dicts it always was (len, index, iterate) and as a
/// table.
struct PySweep {
  std::vector<SweepRow> runs;
  py::list rows;                       ///< RowDict of each run
  std::vector<std::string> swept;      ///< the keys given values per run, in order of first appearance
  std::vector<std::string> metrics;    ///< the metrics' names, in the diagram's order, then any other a run gave
  std::map<std::string, std::string> units;  ///< swept key or metric → unit
};

PySweep SweepResultOf(const PyDiagram& diagram, std::vector<SweepRow> runs) {
  PySweep out;
  for (const auto& m : diagram.document.json().value("metrics", nlohmann::json::array())) {
    if (!m.is_object() || !m.contains("name") || !m["name"].is_string()) continue;
    out.metrics.push_back(m["name"].get<std::string>());
    out.units[out.metrics.back()] = m.value("unit", "");
  }
  for (const auto& row : runs) {
    out.rows.append(RowDict(row));
    for (const auto& [key, value] : row.assignments) {
      if (std::find(out.swept.begin(), out.swept.end(), key) == out.swept.end()) {
        out.swept.push_back(key);
        out.units[key] = KeyUnit(diagram.document, key);
      }
    }
    for (const auto& [name, value] : row.metrics) {
      if (std::find(out.metrics.begin(), out.metrics.end(), name) == out.metrics.end()) out.metrics.push_back(name);
    }
  }
  out.units["wall_time_s"] = "s";
  out.runs = std::move(runs);
  return out;
}

py::object SweepFrame(const PySweep& s) {
  const double nan = std::numeric_limits<double>::quiet_NaN();
  py::list ids, status, wall, error;
  std::vector<py::list> swept(s.swept.size()), metrics(s.metrics.size());
  for (const auto& row : s.runs) {
    ids.append(row.id);
    status.append(row.status);
    for (std::size_t k = 0; k < s.swept.size(); ++k) {
      const auto it = std::find_if(row.assignments.begin(), row.assignments.end(),
                                   [&](const auto& a) { return a.first == s.swept[k]; });
      swept[k].append(it == row.assignments.end() ? py::object(py::none()) : FromJson(it->second));
    }
    for (std::size_t k = 0; k < s.metrics.size(); ++k) {
      const auto it = row.metrics.find(s.metrics[k]);
      metrics[k].append(it == row.metrics.end() ? nan : it->second);  // a failed run has none: NaN
    }
    wall.append(row.wall_time_s);
    error.append(row.error);
  }
  const auto unit = [&](const std::string& name) {
    const auto it = s.units.find(name);
    return it == s.units.end() ? std::string() : it->second;
  };
  std::vector<FrameColumn> columns{{"status", status, ""}};
  for (std::size_t k = 0; k < s.swept.size(); ++k) columns.push_back({s.swept[k], swept[k], unit(s.swept[k])});
  for (std::size_t k = 0; k < s.metrics.size(); ++k) columns.push_back({s.metrics[k], metrics[k], unit(s.metrics[k])});
  columns.push_back({"wall_time_s", wall, "s"});
  columns.push_back({"error", error, ""});
  return DataFrame(columns, ids, "id", "SweepResult.to_pandas()");
}

std::string SweepRepr(const PySweep& s) {
  const auto ok = std::count_if(s.runs.begin(), s.runs.end(), [](const SweepRow& r) { return r.status == "ok"; });
  std::vector<std::string> ranges;
  for (const auto& name : s.metrics) {
    if (ranges.size() == 3) {
      ranges.push_back("…");
      break;
    }
    double low = std::numeric_limits<double>::infinity(), high = -low;
    for (const auto& row : s.runs) {
      const auto it = row.metrics.find(name);
      if (it == row.metrics.end() || !std::isfinite(it->second)) continue;
      low = std::min(low, it->second);
      high = std::max(high, it->second);
    }
    if (low > high) continue;
    const auto unit = s.units.find(name);
    ranges.push_back(fmt::format("{} {:.3g} … {:.3g}{}", name, low, high,
                                 unit == s.units.end() || unit->second.empty() ? "" : " " + unit->second));
  }
  return fmt::format("<SweepResult {} runs ({} ok, {} failed){}{}{}>", s.runs.size(), ok,
                     static_cast<long>(s.runs.size()) - ok,
                     s.swept.empty() ? "" : fmt::format(" over {}", fmt::join(s.swept, ", ")),
                     ranges.empty() ? "" : "; ", fmt::join(ranges, ", "));
}

PySweep Sweep(const PyDiagram& diagram, const py::object& spec, int jobs, const py::object& out, bool save_logs) {
  if (diagram.path.empty()) {
    throw std::invalid_argument("sweep: the diagram has no file (made from a dict or a fit): save() it and sweep "
                                "Diagram.load of that file");
  }
  if (jobs < 0) {  // as the command line's --jobs (CLI::NonNegativeNumber)
    throw std::invalid_argument(fmt::format("sweep(): jobs = {}: give the number of parallel runs, 0 for all cores",
                                            jobs));
  }
  SweepSpec parsed = py::isinstance<py::dict>(spec) ? ParseSweep(ToJson(spec, "sweep(): spec"), "<sweep dict>")
                                                    : ReadSweepFile(PathText(spec));
  // The diagram's own settings first, then the sweep's "set", then each run's values.
  parsed.fixed.insert(parsed.fixed.begin(), diagram.settings.begin(), diagram.settings.end());
  SweepOptions options;
  options.jobs = jobs;
  options.resume = !out.is_none();
  options.save_logs = save_logs;
  options.progress = false;
  options.report = !out.is_none();  // report.html only where it is kept
  std::optional<TemporaryFolder> scratch;
  if (out.is_none()) scratch.emplace("motionblocks-sweep");
  const fs::path folder = out.is_none() ? scratch->path() : fs::path(PathText(out));
  SweepOutcome outcome;
  {
    py::gil_scoped_release release;
    outcome = RunSweep(diagram.path, parsed, folder, options);
  }
  return SweepResultOf(diagram, std::move(outcome.rows));
}

}  // namespace

void BindSweep(py::module_& m) {
  py::class_<PySweep>(m, "SweepResult",
                      "The runs of a sweep, in sweep order: a sequence of dicts (len(r), r[0], r[-1], r[1:3], "
                      "iteration), each id, status ('ok' or 'failed'), the swept keys' values (SI), the diagram's "
                      "metrics (SI units), wall_time_s [s], error; r.to_pandas() is a table of them.")
      .def("__len__", [](const PySweep& s) { return s.runs.size(); }, "The number of runs.")
      .def("__getitem__", [](const PySweep& s, const py::object& index) { return py::object(s.rows[index]); }, py::arg("index"),
           "Run `index` as a dict (negative indices and slices as a list's). Raises IndexError.")
      .def("__iter__", [](const PySweep& s) { return py::iter(s.rows); }, "Iterates over the runs' dicts.")
      .def_property_readonly("rows", [](const PySweep& s) { return s.rows; }, "The runs as a list of dicts.")
      .def_property_readonly("swept", [](const PySweep& s) { return s.swept; },
                             "The keys given a value per run ('element.parameter', …), in order.")
      .def_property_readonly("metrics", [](const PySweep& s) { return s.metrics; }, "The metrics' names.")
      .def_property_readonly("units", [](const PySweep& s) { return s.units; },
                             "dict column → unit: the swept parameters' SI units, the metrics' declared units, "
                             "wall_time_s 's' ('' when none is declared).")
      .def("to_pandas", &SweepFrame,
           "A pandas.DataFrame with one row per run, index 'id': status, the swept keys, the metrics (NaN for a "
           "failed run), wall_time_s [s], error; df.attrs['units'] = {column: unit} as `units`. Raises ImportError "
           "naming Debian's python3-pandas when pandas is missing.")
      .def("__repr__", &SweepRepr);
  m.def("sweep", &Sweep, py::arg("diagram"), py::arg("spec"), py::kw_only(), py::arg("jobs") = 0,
        py::arg("out") = py::none(), py::arg("save_logs") = false,
        "Runs a parameter sweep of `diagram` (loaded with Diagram.load; its set() calls apply to every run) as "
        "`motionblocks sweep`: `spec` a sweep file's path or its JSON as a dict (grid, list or random; "
        "tools/batch/sweep_spec.h), `jobs` parallel runs (0 = all cores). Returns a SweepResult: one dict per run in "
        "sweep order (id, status 'ok' or 'failed', the swept keys' values, the diagram's metrics in SI units, "
        "wall_time_s, error), and to_pandas(). With `out`, runs.csv, runs.json and report.html are written there and a second "
        "call resumes; without, nothing is kept. Raises DiagramError for an unknown element, ValueError for a bad "
        "sweep (with its JSON pointer) or negative `jobs`.");
}

}  // namespace mb::python

// motionblocks.sweep: `motionblocks sweep` as a call (tools/batch RunSweep): the runs in parallel (TBB), one row per
// run as a dict. The settings made on the Diagram with set() apply to every run (as the sweep file's "set").

#include <optional>

#include <fmt/format.h>
#include <pybind11/stl.h>

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

py::list Sweep(const PyDiagram& diagram, const py::object& spec, int jobs, const py::object& out, bool save_logs) {
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
  std::optional<TemporaryFolder> scratch;
  if (out.is_none()) scratch.emplace("motionblocks-sweep");
  const fs::path folder = out.is_none() ? scratch->path() : fs::path(PathText(out));
  SweepOutcome outcome;
  {
    py::gil_scoped_release release;
    outcome = RunSweep(diagram.path, parsed, folder, options);
  }
  py::list rows;
  for (const auto& row : outcome.rows) rows.append(RowDict(row));
  return rows;
}

}  // namespace

void BindSweep(py::module_& m) {
  m.def("sweep", &Sweep, py::arg("diagram"), py::arg("spec"), py::kw_only(), py::arg("jobs") = 0,
        py::arg("out") = py::none(), py::arg("save_logs") = false,
        "Runs a parameter sweep of `diagram` (loaded with Diagram.load; its set() calls apply to every run) as "
        "`motionblocks sweep`: `spec` a sweep file's path or its JSON as a dict (grid, list or random; "
        "tools/batch/sweep.h), `jobs` parallel runs (0 = all cores; negative: ValueError). Returns one dict per run in sweep order: id, "
        "status ('ok' or 'failed'), the swept keys' values, the diagram's metrics (SI units), wall_time_s, error. "
        "With `out`, runs.csv and runs.json are written there and a second call resumes; without, nothing is kept. "
        "Raises DiagramError for an unknown element, ValueError for a bad sweep (with its JSON pointer).");
}

}  // namespace mb::python

// motionblocks.Diagram (load, set, get, blocks), motionblocks.simulate and its SimulationResult: the `run`
// command's library calls (LoadDiagram's parts, Simulator::Run) with the logged signals as NumPy arrays that share
// the result's memory.

#include <algorithm>
#include <filesystem>
#include <map>
#include <memory>
#include <sstream>

#include <fmt/format.h>
#include <fmt/ranges.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "engine/closest_names.h"
#include "engine/diagram_loader.h"
#include "engine/input_file.h"
#include "engine/json_limits.h"
#include "engine/json_parsing.h"
#include "engine/text_excerpt.h"
#include "engine/simulator.h"
#include "python/bindings.h"
#include "tools/report/output_files.h"

namespace mb::python {

using nlohmann::json;

namespace {

// "element.parameter" split at its first '.' (set() and get() read keys alike). @throws std::invalid_argument
// saying how to write a key, naming the call (`call`: "set" or "get").
std::pair<std::string, std::string> SplitKey(const DiagramDocument& document, const char* call,
                                             const std::string& key) {
  const auto dot = key.find('.');
  if (dot == std::string::npos || dot == 0 || dot + 1 == key.size()) {
    throw std::invalid_argument(fmt::format(
        "{}: {}('{}'): write element.parameter (e.g. plant.payload_mass), solver.<key> or defaultExperiment.<key>",
        document.source(), call, key));
  }
  return {key.substr(0, dot), key.substr(dot + 1)};
}

// What the loader takes for a solver or defaultExperiment key the diagram leaves out: the engine's own defaults
// (SolverSpec, Experiment; engine/diagram.h), under the schema's key names.
json SectionDefaults(const std::string& section) {
  if (section == "solver") {
    const SolverSpec s;
    return {{"type", s.type}, {"method", s.method}, {"step", s.step},
            {"rtol", s.rtol}, {"atol", s.atol},     {"maxStep", s.max_step}};
  }
  const Experiment x;
  return {{"startTime", x.start_time}, {"stopTime", x.stop_time}, {"stepSize", x.step_size}};
}

}  // namespace

void PyDiagram::Set(const std::string& key, const json& value) {
  const auto [element, name] = SplitKey(document, "set", key);
  if (DiagramDocument::IsSettingSection(element) && !document.Has(element)) {
    document.SetSectionSetting(element, name, value);
  } else {
    document.SetParameterChecked(element, name, value);  // the element built with it, as simulate will (issue 41)
  }
  settings.emplace_back(key, value);
}

json PyDiagram::Get(const std::string& key) const {
  const auto [element, name] = SplitKey(document, "get", key);
  if (!DiagramDocument::IsSettingSection(element) || document.Has(element)) return document.Parameter(element, name);
  const json section = document.json().value(element, json::object());
  if (section.is_object() && section.contains(name)) return section[name];
  const json defaults = SectionDefaults(element);
  if (defaults.contains(name)) return defaults[name];
  std::vector<std::string> keys;
  for (const auto& item : defaults.items()) keys.push_back(item.key());
  const auto closest = ClosestNames(name, keys);
  throw std::invalid_argument(fmt::format("{}: get('{}'): {} has no key '{}'{}; it takes: {}", document.source(), key,
                                          element, name,
                                          closest.empty() ? "" : fmt::format("; did you mean: {}", fmt::join(closest, ", ")),
                                          fmt::join(keys, ", ")));
}

Diagram PyDiagram::Build() const {
  return BuildDiagram(document.json(), document.base_directory(), document.source());
}

json ToJson(const py::handle& object, const std::string& argument) {
  const py::module_ json_module = py::module_::import("json");
  const py::module_ numpy = py::module_::import("numpy");
  // NumPy arrays and scalars: their Python equivalents (tolist), which the json module writes.
  const py::object plain = py::isinstance(object, numpy.attr("ndarray")) || py::isinstance(object, numpy.attr("generic"))
                               ? object.attr("tolist")()
                               : py::reinterpret_borrow<py::object>(object);
  // Inside dicts and lists too: NumPy values are written as their tolist().
  const py::cpp_function as_list([](const py::object& value) { return value.attr("tolist")(); });
  try {
    // allow_nan=False: NaN and infinity have no JSON form (the json module would write the token NaN, which no JSON
    // reader takes: issue 41's "parse error at line 1, column 1 … last read: 'N'").
    return json::parse(json_module.attr("dumps")(plain, py::arg("default") = as_list, py::arg("allow_nan") = false)
                           .cast<std::string>());
  } catch (const py::error_already_set& e) {
    if (e.matches(PyExc_ValueError)) {  // the json module's "Out of range float values are not JSON compliant"
      throw py::value_error(fmt::format("{}: {} is not finite: NaN and infinity are no parameter's or setting's "
                                        "value; give finite numbers",
                                        argument, Excerpt(py::repr(object).cast<std::string>(), 120)));
    }
    // an object JSON cannot hold (AttributeError: no tolist, TypeError)
    throw py::type_error(fmt::format("{}: a {} is no JSON value; give a number, str, bool, None, or a list or dict "
                                     "of them (NumPy arrays and scalars are converted)",
                                     argument, py::str(py::type::of(object).attr("__name__")).cast<std::string>()));
  }
}

py::object FromJson(const json& value) {
  return py::module_::import("json").attr("loads")(value.dump());
}

std::string PathText(const py::handle& path) {
  return py::module_::import("os").attr("fspath")(path).cast<std::string>();
}

py::object DataFrame(const std::vector<FrameColumn>& columns, const py::object& index, const std::string& index_name,
                     const std::string& caller) {
  py::module_ pandas;
  try {
    pandas = py::module_::import("pandas");
  } catch (const py::error_already_set& e) {
    if (!e.matches(PyExc_ImportError)) throw;
    throw py::import_error(fmt::format(
        "{} needs pandas, which this Python ({}) cannot import: install Debian's python3-pandas (sudo apt install "
        "python3-pandas; `make deps` does) — the arrays themselves need no pandas",
        caller, py::str(py::module_::import("sys").attr("executable")).cast<std::string>()));
  }
  py::dict data, units;  // in insertion order: the columns' order
  for (const auto& c : columns) {
    data[py::str(c.name)] = c.values;
    units[py::str(c.name)] = c.unit;
  }
  const py::object rows =
      index.is_none() ? py::none() : pandas.attr("Index")(index, py::arg("copy") = true, py::arg("name") = index_name);
  py::object frame = pandas.attr("DataFrame")(data, py::arg("index") = rows, py::arg("copy") = true);
  if (index.is_none() && !index_name.empty()) frame.attr("index").attr("name") = index_name;
  frame.attr("attrs")["units"] = units;
  return frame;
}

std::string BeforeAfter(double before, double after, const std::string& unit) {
  return fmt::format("{:.3g} → {:.3g}{}{}", before, after, unit.empty() ? "" : " ", unit);
}

namespace {

// The diagram file's JSON syntax, checked before DiagramDocument::Load reads it: a syntax error is a DiagramError
// (a ValueError naming the file, the line and the column), as a diagram's other problems are, not a RuntimeError.
void RequireDiagramJsonSyntax(const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) return;  // Load says why (missing, a folder, a device)
  const std::string text = ReadInputFile(path, "diagram file");
  try {
    RefuseNulBytes(text);  // as ReadDiagramJson: no comments, no NUL byte (issue 41)
    // Parsed only to be checked (GCC ignores a cast to void of a [[nodiscard]] result: a named, unused value).
    [[maybe_unused]] const nlohmann::json parsed =
        nlohmann::json::parse(text, nullptr, /*allow_exceptions=*/true, /*ignore_comments=*/false);
  } catch (const nlohmann::json::parse_error& e) {
    throw DiagramError(path, {fmt::format("not valid JSON: {}{}", JsonErrorText(e), JsonCommentHint(text, e.byte))});
  }
}

// A finished run, kept alive by the arrays that view its log (their NumPy base), with the units of its logged
// columns (in log.names' order) and of its metrics.
struct PyResult {
  SimulationResult result;
  std::vector<std::string> units;
  std::map<std::string, std::string> metric_units;
};

// The unit of a logged signal: its connector's when it is one, else the unit its block's port declares ("" for a
// port of any unit: a gain's output, a sum's).
std::string LoggedUnit(const Diagram& d, const LoggedSignal& l) {
  for (const auto& out : d.outputs()) {
    if (out.name == l.name && !out.unit.empty()) return out.unit;
  }
  const auto port = static_cast<std::size_t>(l.source.port);
  if (l.source.is_external()) return d.inputs()[port].unit;
  return d.blocks()[static_cast<std::size_t>(l.source.block)]->output_ports()[port].unit;
}

// The units of the log's columns: one per column, a width-n signal's unit for each of its n columns (the order in
// which Simulator names them: engine/simulator.cc).
std::vector<std::string> LoggedUnits(const Diagram& d) {
  std::vector<std::string> units;
  for (const auto& l : d.logged()) units.insert(units.end(), static_cast<std::size_t>(l.width), LoggedUnit(d, l));
  return units;
}

// The extra signals of simulate(log=…): a list (or any iterable) of str, or one str.
std::vector<std::string> LogNames(const py::object& log) {
  std::vector<std::string> names;
  if (log.is_none()) return names;
  if (py::isinstance<py::str>(log)) return {log.cast<std::string>()};
  if (!py::isinstance<py::iterable>(log)) {
    throw py::type_error(fmt::format("simulate(): log: a {} is no list of signal names; give e.g. "
                                     "log=['plant.x', 'dob.d_hat'] (element.port or a connector's name)",
                                     py::str(py::type::of(log).attr("__name__")).cast<std::string>()));
  }
  for (const auto& item : log) {
    if (!py::isinstance<py::str>(item)) {
      throw py::type_error(fmt::format("simulate(): log: {} is no signal name; give str such as 'plant.x'",
                                       py::repr(item).cast<std::string>()));
    }
    names.push_back(item.cast<std::string>());
  }
  return names;
}

// "a, b, c, … (+n)": the first `shown` of `items`.
std::string FirstOf(const std::vector<std::string>& items, std::size_t shown) {
  std::string s;
  for (std::size_t i = 0; i < items.size() && i < shown; ++i) s += (i ? ", " : "") + items[i];
  if (items.size() > shown) s += fmt::format(", … (+{})", items.size() - shown);
  return s;
}

// The logged column `values` as a read-only 1-D array over the result's own memory.
py::array ViewOf(const std::vector<double>& values, const py::object& owner) {
  py::array_t<double> a(static_cast<py::ssize_t>(values.size()), values.data(), owner);
  a.attr("setflags")(py::arg("write") = false);
  return a;
}

py::dict SolverStatsDict(const SolverStats& s) {
  py::dict d;
  d["steps"] = s.steps;
  d["rhs_evaluations"] = s.rhs_evaluations;
  d["root_evaluations"] = s.root_evaluations;
  d["reinitialisations"] = s.reinitialisations;
  d["roots_found"] = s.roots_found;
  return d;
}

std::shared_ptr<PyResult> Simulate(const PyDiagram& diagram, const py::object& stop_time, const py::dict& inputs,
                                   const py::object& log) {
  PyDiagram run = diagram;
  if (!stop_time.is_none()) run.document.SetSectionSetting("defaultExperiment", "stopTime", stop_time.cast<double>());
  // log=[…]: the diagram's "log" list extended on this run's copy (the loader resolves and checks each name, as
  // for a name written in the file; the diagram itself is unchanged).
  if (const auto extra = LogNames(log); !extra.empty()) {
    std::vector<std::string> logged = run.document.LoggedSignals();
    for (const auto& name : extra) {
      if (std::find(logged.begin(), logged.end(), name) == logged.end()) logged.push_back(name);
    }
    run.document.SetLoggedSignals(logged);
  }
  const Diagram built = run.Build();
  Simulator sim(built);
  for (const auto& [name, series] : inputs) {
    if (!py::isinstance<py::str>(name)) {
      throw py::type_error(fmt::format("simulate(): inputs: the key {} is no str; key each series by its input "
                                       "connector's name",
                                       py::repr(name).cast<std::string>()));
    }
    std::pair<std::vector<double>, std::vector<double>> pair;
    try {
      pair = series.cast<std::pair<std::vector<double>, std::vector<double>>>();
    } catch (const py::cast_error&) {
      throw py::type_error(fmt::format("simulate(): inputs['{}']: a {} is no (time, values) pair; give two 1-D "
                                       "sequences of numbers of one length, time [s] increasing",
                                       name.cast<std::string>(),
                                       py::str(py::type::of(series).attr("__name__")).cast<std::string>()));
    }
    sim.SetInput(name.cast<std::string>(), InputSeries{pair.first, pair.second});
  }
  auto out = std::make_shared<PyResult>();
  {
    py::gil_scoped_release release;
    out->result = sim.Run();
  }
  out->result.solver_name = built.solver().type;
  out->units = LoggedUnits(built);
  for (const auto& metric : built.metrics()) out->metric_units[metric.name] = metric.unit;
  return out;
}

py::list BlockList(const PyDiagram& d) {
  py::list blocks;
  for (const auto& name : d.document.ElementNames()) {
    py::dict b;
    b["name"] = name;
    b["type"] = d.document.TypeOf(name);
    blocks.append(b);
  }
  return blocks;
}

py::dict UnitsDict(const PyResult& r) {
  py::dict d;
  for (std::size_t i = 0; i < r.result.log.names.size(); ++i) d[py::str(r.result.log.names[i])] = r.units[i];
  return d;
}

std::string ResultRepr(const PyResult& r) {
  const SignalLog& log = r.result.log;
  std::vector<std::string> signals, metrics;
  for (std::size_t i = 0; i < log.names.size(); ++i) {
    signals.push_back(r.units[i].empty() ? log.names[i] : fmt::format("{} [{}]", log.names[i], r.units[i]));
  }
  for (const auto& [name, value] : r.result.metrics) {
    const auto unit = r.metric_units.find(name);
    metrics.push_back(fmt::format("{} = {:.4g}{}", name, value,
                                  unit == r.metric_units.end() || unit->second.empty() ? "" : " " + unit->second));
  }
  const std::string span =
      log.time.empty() ? "no samples" : fmt::format("{:g}–{:g} s, {} samples", log.time.front(), log.time.back(),
                                                    log.time.size());
  return fmt::format("<SimulationResult {} ({}, {} steps); {} signals: {}{}{}>", span, r.result.solver_name,
                     r.result.solver_stats.steps, log.names.size(), FirstOf(signals, 6),
                     metrics.empty() ? "" : "; ", FirstOf(metrics, 4));
}

void BindResult(py::module_& m) {
  py::class_<PyResult, std::shared_ptr<PyResult>>(
      m, "SimulationResult",
      "A finished run: the logged signals on the log grid (read-only float64 arrays of shape (N,) that share the "
      "result's memory, no copy), their units, the diagram's metrics (SI units) and the solver's statistics. A "
      "mapping of the signals: r['plant.x'], r.keys(), 'plant.x' in r, len(r); r.to_pandas() is a DataFrame.")
      .def_property_readonly(
          "time", [](py::object self) { return ViewOf(self.cast<PyResult&>().result.log.time, self); },
          "Sample times, shape (N,) [s].")
      .def_property_readonly(
          "names", [](const PyResult& r) { return r.result.log.names; },
          "Logged signal names: 'block.port' or a connector's name; a width-n signal gives 'name[0]' … 'name[n-1]'.")
      .def("keys", [](const PyResult& r) { return r.result.log.names; },
           "The logged signal names (list of str, as `names`): the diagram's \"log\", its connectors, and what "
           "simulate(log=…) added.")
      .def_property_readonly(
          "units", &UnitsDict,
          "dict name → unit of each logged signal: its connector's, else the unit its block's port declares ('m', "
          "'m/s', 'N', …; '' for a port of any unit, such as a gain's or a sum's output).")
      .def_property_readonly(
          "signals",
          [](py::object self) {
            const SignalLog& log = self.cast<PyResult&>().result.log;
            py::dict d;
            for (std::size_t i = 0; i < log.names.size(); ++i) d[py::str(log.names[i])] = ViewOf(log.columns[i], self);
            return d;
          },
          "dict name → signal, each shape (N,), in the signal's unit (`units`).")
      .def(
          "__getitem__",
          [](py::object self, const std::string& name) {
            const SignalLog& log = self.cast<PyResult&>().result.log;
            if (!log.Has(name)) throw py::key_error(fmt::format("'{}' is not logged; logged: {}; simulate(log=['{}']) "
                                                                "logs it", name, fmt::join(log.names, ", "), name));
            return ViewOf(log.Column(name), self);
          },
          py::arg("name"),
          "The logged signal `name`, shape (N,), in its unit (`units[name]`). Raises KeyError listing the logged "
          "names.")
      .def("__contains__", [](const PyResult& r, const py::object& name) {
        return py::isinstance<py::str>(name) && r.result.log.Has(name.cast<std::string>());
      })
      .def("__len__", [](const PyResult& r) { return r.result.log.names.size(); }, "The number of logged signals.")
      .def("__iter__", [](const PyResult& r) { return py::iter(py::cast(r.result.log.names)); },
           "Iterates over the logged signal names.")
      .def(
          "to_pandas",
          [](py::object self) {
            const PyResult& r = self.cast<PyResult&>();
            std::vector<FrameColumn> columns;
            for (std::size_t i = 0; i < r.result.log.names.size(); ++i) {
              columns.push_back({r.result.log.names[i], ViewOf(r.result.log.columns[i], self), r.units[i]});
            }
            return DataFrame(columns, ViewOf(r.result.log.time, self), "time_s", "SimulationResult.to_pandas()");
          },
          "A pandas.DataFrame (a copy): index 'time_s' [s], shape (N,); one float64 column per logged signal, named "
          "as `names`; df.attrs['units'] = {column: unit} as `units`. Raises ImportError naming Debian's "
          "python3-pandas when pandas is missing.")
      .def_property_readonly(
          "metrics", [](const PyResult& r) { return r.result.metrics; },
          "dict metric name → value in SI units (the diagram's \"metrics\"; `run`'s summary.json).")
      .def_property_readonly(
          "metric_units", [](const PyResult& r) { return r.metric_units; },
          "dict metric name → its unit as the diagram declares it ('' when it declares none).")
      .def_property_readonly(
          "solver_stats", [](const PyResult& r) { return SolverStatsDict(r.result.solver_stats); },
          "dict: steps, rhs_evaluations, root_evaluations, reinitialisations, roots_found.")
      .def_property_readonly(
          "solver", [](const PyResult& r) { return r.result.solver_name; }, "Solver type: euler, rk4 or cvode.")
      .def_property_readonly(
          "wall_time_s", [](const PyResult& r) { return r.result.wall_time_s; }, "Wall time of the run [s].")
      .def("__repr__", &ResultRepr);
}

}  // namespace

void BindDiagram(py::module_& m) {
  py::class_<PyDiagram>(m, "Diagram",
                        "A diagram (JSON, diagrams/schema.json) held as a typed document: load it, set parameters, "
                        "simulate it; compare, fit, improve and sweep take it.")
      .def_static(
          "load",
          [](const py::object& path) {
            const std::string p = PathText(path);
            RequireDiagramJsonSyntax(p);
            PyDiagram diagram{DiagramDocument::Load(p), p, {}};
            // Its subsystems read as the command line reads them (issue 41: a subsystem that includes itself was
            // loaded, and failed only when simulated): a cycle, a missing or unreadable file is a DiagramError now.
            (void)ExpandSubsystems(diagram.document.json(), diagram.document.base_directory(), p);
            return diagram;
          },
          py::arg("path"),
          "Reads a diagram file (str or os.PathLike) and the subsystem files it names. Files it names resolve "
          "against its folder. Raises OSError if it cannot be opened, DiagramError (a ValueError) with the line and "
          "column on a JSON syntax error, or naming the subsystem for one that includes itself (directly or "
          "through others), is missing or lies outside the diagram's folder, TypeError if `path` is no str or "
          "os.PathLike.")
      .def_static(
          "from_dict",
          [](const py::object& diagram, const py::object& base_directory) {
            const std::string base = base_directory.is_none() ? "" : PathText(base_directory);
            return PyDiagram{DiagramDocument(ToJson(diagram, "from_dict(): diagram"), base, "<dict>"), "", {}};
          },
          py::arg("diagram"), py::arg("base_directory") = py::none(),
          "A diagram from its JSON as a dict; relative file names resolve against `base_directory`.")
      .def("set",
           [](PyDiagram& d, const std::string& key, const py::object& value) {
             d.Set(key, ToJson(value, fmt::format("set('{}', …): value", Excerpt(key, 120))));
           },
           py::arg("key"), py::arg("value"),
           "Sets 'element.parameter' (a number in the parameter's SI unit whatever unit the diagram wrote, as "
           "`motionblocks --set` reads it; or {'value': v, 'unit': 'mm'}), 'solver.<key>' or "
           "'defaultExperiment.<key>' (e.g. 'defaultExperiment.stopTime' [s]). The element is built with the new "
           "value at once, as simulate will build it. Raises ValueError for an unknown element or parameter (naming "
           "the closest) or a value that is no finite number (NaN, infinity), DiagramError for a value the "
           "parameter or its element refuses (a 3-entry array for a gain of width 1), TypeError (naming `value`) for "
           "an object JSON cannot hold.")
      .def(
          "get",
          [](const PyDiagram& d, const std::string& key, const py::object& parameter) {
            if (parameter.is_none()) return FromJson(d.Get(key));
            if (!py::isinstance<py::str>(parameter)) {
              throw py::type_error("get(): give one key 'element.parameter', e.g. get('plant.payload_mass')");
            }
            const std::string dotted = key + "." + parameter.cast<std::string>();
            const std::string warning =
                fmt::format("get('{}', '{}') is deprecated: write get('{}'), the key set() takes", key,
                            parameter.cast<std::string>(), dotted);
            if (PyErr_WarnEx(PyExc_DeprecationWarning, warning.c_str(), 1) != 0) throw py::error_already_set();
            return FromJson(d.Get(dotted));
          },
          py::arg("key"), py::arg("parameter") = py::none(),
          "The value set(key, …) would change, key as set() takes it: 'element.parameter' in the parameter's SI "
          "unit (a value written as {'value': v, 'unit': 'g'} converted; the block type's default when the diagram "
          "leaves it out; a list for a vector parameter), 'solver.<key>' or 'defaultExperiment.<key>' (e.g. "
          "'defaultExperiment.stopTime' [s]; the engine's default when absent). Raises ValueError for a key without "
          "'.' or an unknown element, parameter or key (naming the closest). get('element', 'parameter') still "
          "works but is deprecated (DeprecationWarning).")
      .def("blocks", &BlockList, "The elements, in file order: list of {'name', 'type'}.")
      .def("free_parameters", [](const PyDiagram& d) { return d.document.FreeParameters(); },
           "The diagram's \"free\" list ('element.parameter'): what compare and fit refit by default.")
      .def("validate", [](const PyDiagram& d) { d.Build(); },
           "Builds the diagram as simulate would. Raises DiagramError (every problem, with its JSON pointer) or "
           "AlgebraicLoopError.")
      .def("to_dict", [](const PyDiagram& d) { return FromJson(d.document.json()); }, "The diagram's JSON.")
      .def(
          "save",
          [](const PyDiagram& d, const py::object& path) {
            return WriteDiagramFile(d.document.json(), d.document.base_directory(), PathText(path));
          },
          py::arg("path"),
          "Writes the diagram's JSON to `path`, the files it names rewritten to name the same files from there. "
          "Returns those that lie outside that folder (loading the copy needs them allowed, `--allow-path`).")
      .def_property_readonly("path", [](const PyDiagram& d) { return d.path; },
                             "The file it was loaded from ('' if made from a dict).")
      .def("__repr__", [](const PyDiagram& d) {
        return fmt::format("<Diagram {} ({} elements)>", d.document.source(), d.document.ElementNames().size());
      });
  BindResult(m);
  m.def("simulate", &Simulate, py::arg("diagram"), py::kw_only(), py::arg("stop_time") = py::none(),
        py::arg("inputs") = py::dict(), py::arg("log") = py::none(),
        "Simulates `diagram` from its defaultExperiment's start to `stop_time` [s] (default: its stopTime), with "
        "input connectors fed from `inputs` = {connector: (time [s], values)} (1-D sequences of one length, time "
        "increasing; linear interpolation, held outside). `log`: extra signals to record besides the diagram's "
        "\"log\" and connectors, e.g. ['plant.velocity', 'dob.d_hat'] ('element.port', 'element' for its first "
        "output, or a connector's name), for this run only. Returns a SimulationResult whose signals have shape (N,) "
        "on the log grid. Raises DiagramError for a diagram with problems (an unknown signal in `log` is one, at "
        "/log/<k>), TypeError for a `log` that is no list of str or `inputs` of the wrong form, ValueError for bad "
        "inputs or a run beyond its limits, NumericalError if a signal becomes NaN/Inf (naming the block and the "
        "time).");
}

}  // namespace mb::python

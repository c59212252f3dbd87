// motionblocks.Diagram (load, set, get, blocks), motionblocks.simulate and its SimulationResult: the `run`
// command's library calls (LoadDiagram's parts, Simulator::Run) with the logged signals as NumPy arrays that share
// the result's memory.

#include <filesystem>
#include <memory>
#include <sstream>

#include <fmt/format.h>
#include <pybind11/numpy.h>
#include <pybind11/stl.h>

#include "engine/diagram_loader.h"
#include "engine/input_file.h"
#include "engine/text_excerpt.h"
#include "engine/simulator.h"
#include "python/bindings.h"
#include "tools/report/output_files.h"

namespace mb::python {

using nlohmann::json;

void PyDiagram::Set(const std::string& key, const json& value) {
  const auto dot = key.find('.');
  if (dot == std::string::npos || dot == 0 || dot + 1 == key.size()) {
    throw std::invalid_argument(fmt::format(
        "{}: set('{}'): write element.parameter (e.g. plant.payload_mass), solver.<key> or defaultExperiment.<key>",
        document.source(), key));
  }
  const std::string element = key.substr(0, dot), name = key.substr(dot + 1);
  if (DiagramDocument::IsSettingSection(element) && !document.Has(element)) {
    document.SetSectionSetting(element, name, value);
  } else {
    document.SetParameter(element, name, value);
  }
  settings.emplace_back(key, value);
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
    return json::parse(json_module.attr("dumps")(plain, py::arg("default") = as_list).cast<std::string>());
  } catch (const py::error_already_set& e) {  // an object JSON cannot hold (AttributeError: no tolist, TypeError)
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

namespace {

// The diagram file's JSON syntax, checked before DiagramDocument::Load reads it: a syntax error is a DiagramError
// (a ValueError naming the file, the line and the column), as a diagram's other problems are, not a RuntimeError.
void RequireJsonSyntax(const std::string& path) {
  if (!std::filesystem::is_regular_file(path)) return;  // Load says why (missing, a folder, a device)
  std::istringstream in(ReadInputFile(path, "diagram file"));
  try {
    (void)nlohmann::json::parse(in, nullptr, /*allow_exceptions=*/true, /*ignore_comments=*/true);
  } catch (const nlohmann::json::parse_error& e) {
    throw DiagramError(path, {fmt::format("not valid JSON: {}", JsonErrorText(e))});
  }
}

// A finished run, kept alive by the arrays that view its log (their NumPy base).
struct PyResult {
  SimulationResult result;
};

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

std::shared_ptr<PyResult> Simulate(const PyDiagram& diagram, const py::object& stop_time, const py::dict& inputs) {
  PyDiagram run = diagram;
  if (!stop_time.is_none()) run.document.SetSectionSetting("defaultExperiment", "stopTime", stop_time.cast<double>());
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

void BindResult(py::module_& m) {
  py::class_<PyResult, std::shared_ptr<PyResult>>(
      m, "SimulationResult",
      "A finished run: the logged signals on the log grid (read-only float64 arrays of shape (N,) that share the "
      "result's memory, no copy), the diagram's metrics (SI units) and the solver's statistics.")
      .def_property_readonly(
          "time", [](py::object self) { return ViewOf(self.cast<PyResult&>().result.log.time, self); },
          "Sample times, shape (N,) [s].")
      .def_property_readonly(
          "names", [](const PyResult& r) { return r.result.log.names; },
          "Logged signal names: 'block.port' or a connector's name; a width-n signal gives 'name[0]' … 'name[n-1]'.")
      .def_property_readonly(
          "signals",
          [](py::object self) {
            const SignalLog& log = self.cast<PyResult&>().result.log;
            py::dict d;
            for (std::size_t i = 0; i < log.names.size(); ++i) d[py::str(log.names[i])] = ViewOf(log.columns[i], self);
            return d;
          },
          "dict name → signal, each shape (N,), in the signal's unit (SI).")
      .def(
          "__getitem__",
          [](py::object self, const std::string& name) {
            return ViewOf(self.cast<PyResult&>().result.log.Column(name), self);
          },
          "The logged signal `name`, shape (N,). Raises ValueError listing the logged names.")
      .def_property_readonly(
          "metrics", [](const PyResult& r) { return r.result.metrics; },
          "dict metric name → value in SI units (the diagram's \"metrics\"; `run`'s summary.json).")
      .def_property_readonly(
          "solver_stats", [](const PyResult& r) { return SolverStatsDict(r.result.solver_stats); },
          "dict: steps, rhs_evaluations, root_evaluations, reinitialisations, roots_found.")
      .def_property_readonly(
          "solver", [](const PyResult& r) { return r.result.solver_name; }, "Solver type: euler, rk4 or cvode.")
      .def_property_readonly(
          "wall_time_s", [](const PyResult& r) { return r.result.wall_time_s; }, "Wall time of the run [s].")
      .def("__repr__", [](const PyResult& r) {
        return fmt::format("<SimulationResult {} samples, {} signals, {} metrics>", r.result.log.time.size(),
                           r.result.log.names.size(), r.result.metrics.size());
      });
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
            RequireJsonSyntax(p);
            return PyDiagram{DiagramDocument::Load(p), p, {}};
          },
          py::arg("path"),
          "Reads a diagram file (str or os.PathLike). Files it names resolve against its folder. Raises OSError if "
          "it cannot be opened, DiagramError (a ValueError) with the line and column on a JSON syntax error, "
          "TypeError if `path` is no str or os.PathLike.")
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
             d.Set(key, ToJson(value, "set(): value"));
           },
           py::arg("key"), py::arg("value"),
           "Sets 'element.parameter' (a number in the parameter's SI unit whatever unit the diagram wrote, as "
           "`motionblocks --set` reads it; or {'value': v, 'unit': 'mm'}), 'solver.<key>' or "
           "'defaultExperiment.<key>' (e.g. 'defaultExperiment.stopTime' [s]). Raises ValueError for an unknown "
           "element or parameter (naming the closest), DiagramError for a value the parameter refuses, TypeError "
           "(naming `value`) for an object JSON cannot hold.")
      .def("get", [](const PyDiagram& d, const std::string& element, const std::string& parameter) {
             return FromJson(d.document.Parameter(element, parameter));
           },
           py::arg("element"), py::arg("parameter"),
           "The value of element.parameter in its SI unit (a value written as {'value': v, 'unit': 'g'} converted), "
           "else the block type's default.")
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
        py::arg("inputs") = py::dict(),
        "Simulates `diagram` from its defaultExperiment's start to `stop_time` [s] (default: its stopTime), with "
        "input connectors fed from `inputs` = {connector: (time [s], values)} (1-D sequences of one length, time "
        "increasing; linear interpolation, held outside). Returns a SimulationResult. Raises DiagramError for a "
        "diagram with problems, ValueError for bad inputs or a run beyond its limits, NumericalError if a signal "
        "becomes NaN/Inf (naming the block and the time).");
}

}  // namespace mb::python

#pragma once
// The motionblocks Python module: what each binding file registers, and what they share — the diagram held for
// Python (a DiagramDocument and the settings made on it) and the JSON ⇄ Python conversion.

#include <filesystem>
#include <string>
#include <utility>
#include <vector>

#include <nlohmann/json.hpp>
#include <pybind11/pybind11.h>

#include "engine/diagram.h"
#include "engine/diagram_document.h"

namespace mb::python {

namespace py = pybind11;

/// motionblocks.Diagram: a diagram file read into a DiagramDocument and edited through it. `path` is the file it was
/// loaded from ("" for a diagram made from JSON, e.g. a fitted one); `settings` the set() calls made so far, in order
/// (a sweep applies them to every run).
struct PyDiagram {
  DiagramDocument document;
  std::string path;
  std::vector<std::pair<std::string, nlohmann::json>> settings;

  /// Sets "element.parameter", "solver.<key>" or "defaultExperiment.<key>" to `value` (DiagramDocument: the
  /// element, the parameter and the value checked now). @throws std::invalid_argument for a key without '.', an
  /// unknown element or parameter; DiagramError for a value the parameter refuses.
  void Set(const std::string& key, const nlohmann::json& value);
  /// Validates and builds the diagram (BuildDiagram). @throws DiagramError, AlgebraicLoopError.
  Diagram Build() const;
};

/// Python object → JSON (dict, list, str, bool, int, float, None, NumPy scalars and arrays) through Python's json
/// module. @throws py::type_error naming `argument` (e.g. "set(): value") for what JSON cannot hold.
nlohmann::json ToJson(const py::handle& object, const std::string& argument = "the value");
/// JSON → Python (dicts, lists, str, int, float, bool, None).
py::object FromJson(const nlohmann::json& value);
/// A diagram file name given as str or os.PathLike.
std::string PathText(const py::handle& path);

void BindErrors(py::module_& m);
void BindDiagram(py::module_& m);
void BindWorkflow(py::module_& m);
void BindGpr(py::module_& m);
void BindSweep(py::module_& m);

}  // namespace mb::python

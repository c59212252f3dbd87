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
  /// The value set() would change: "element.parameter" in its SI unit (the type's default when the diagram leaves
  /// it out), "solver.<key>" or "defaultExperiment.<key>" (the engine's default when absent). @throws
  /// std::invalid_argument as Set, and for a solver/defaultExperiment key the schema does not know ("did you mean").
  nlohmann::json Get(const std::string& key) const;
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

/// One column of a result's DataFrame: its name, its values (copied into the frame) and its unit ("" =
/// dimensionless or not declared).
struct FrameColumn {
  std::string name;
  py::object values;  ///< a 1-D sequence (NumPy array, list)
  std::string unit;
};
/// A pandas.DataFrame of `columns` (in order) over `index` (None: 0…N-1) named `index_name`; the units go to
/// df.attrs["units"] (column → unit). pandas is imported now: `caller` (e.g. "SimulationResult.to_pandas()") names
/// the call in the ImportError that says how to install it (Debian's python3-pandas).
py::object DataFrame(const std::vector<FrameColumn>& columns, const py::object& index, const std::string& index_name,
                     const std::string& caller);
/// "1.23 → 4.56 N": a figure before and after, 3 significant digits, for the results' repr.
std::string BeforeAfter(double before, double after, const std::string& unit);

void BindErrors(py::module_& m);
void BindDiagram(py::module_& m);
void BindWorkflow(py::module_& m);
void BindGpr(py::module_& m);
void BindSweep(py::module_& m);
void BindHil(py::module_& m);
void BindLinearize(py::module_& m);

}  // namespace mb::python

// motionblocks.linearize and its LinearModel: the `linearize` command's library call (engine/linearization.h) with
// A, B, C, D as NumPy arrays and the frequency response as a complex array.

#include <map>
#include <optional>
#include <string>

#include <pybind11/complex.h>
#include <pybind11/eigen.h>
#include <pybind11/stl.h>

#include "engine/linearization.h"
#include "python/bindings.h"

namespace mb::python {

namespace {

LinearModel Linearise(const PyDiagram& diagram, const std::map<std::string, double>& inputs,
                      const std::optional<double>& time) {
  const Diagram built = diagram.Build();
  return Linearize(built, OperatingPoint{inputs, time});
}

}  // namespace

void BindLinearize(py::module_& m) {
  py::class_<LinearModel>(m, "LinearModel",
                          "ẋ = A x + B u, y = C x + D u about an operating point (motionblocks.linearize).")
      .def_readonly("a", &LinearModel::a, "A, n × n [1/s]")
      .def_readonly("b", &LinearModel::b, "B, n × m")
      .def_readonly("c", &LinearModel::c, "C, p × n")
      .def_readonly("d", &LinearModel::d, "D, p × m (direct feedthrough)")
      .def_readonly("state_names", &LinearModel::state_names, "the n continuous states, in block order")
      .def_readonly("input_names", &LinearModel::input_names, "the m input connectors")
      .def_readonly("input_units", &LinearModel::input_units)
      .def_readonly("output_names", &LinearModel::output_names, "the p output connectors")
      .def_readonly("output_units", &LinearModel::output_units)
      .def_readonly("x0", &LinearModel::x0, "the operating point's state")
      .def_readonly("u0", &LinearModel::u0, "the operating point's inputs")
      .def_readonly("y0", &LinearModel::y0, "the outputs there")
      .def_readonly("time", &LinearModel::time, "[s]")
      .def("frequency_response", &LinearModel::FrequencyResponse, py::arg("output"), py::arg("input"),
           py::arg("frequency_hz"),
           "C (j2πf I − A)⁻¹ B + D from input index `input` to output index `output` at each frequency [Hz]: a "
           "complex array, output unit per input unit. Raises IndexError for an index outside the model.")
      .def("to_dict", [](const LinearModel& model) { return FromJson(model.ToJson()); },
           "{'time', 'states', 'inputs', 'outputs', 'A', 'B', 'C', 'D'}: the JSON `motionblocks linearize` writes, "
           "without its Bode data.")
      .def("__repr__", [](const LinearModel& model) {
        return "<LinearModel " + std::to_string(model.a.rows()) + " states, " + std::to_string(model.b.cols()) +
               " inputs, " + std::to_string(model.c.rows()) + " outputs>";
      });
  m.def("linearize", &Linearise, py::arg("diagram"), py::kw_only(), py::arg("inputs") = std::map<std::string, double>{},
        py::arg("time") = py::none(),
        "Linearises `diagram` about an operating point, as Simulink's linmod (central differences of its continuous "
        "part; discrete blocks hold their outputs): the diagram initialised at `time` [s] (default: its start time), "
        "each input connector held at inputs[name] in its unit (default: the connector's default, 0 for a required "
        "one). Returns a LinearModel. Raises ValueError for an unknown input connector (naming the known ones) and "
        "DiagramError for a diagram with problems.");
}

}  // namespace mb::python

// The library's exceptions as Python exceptions with the same messages: DiagramError (a ValueError, with the list
// of problems), AlgebraicLoopError (a DiagramError), NumericalError (a RuntimeError), a file that cannot be opened
// (OSError); std::invalid_argument is pybind11's ValueError, std::out_of_range its IndexError.

#include <exception>
#include <filesystem>

#include "engine/diagram_loader.h"
#include "engine/execution_order.h"
#include "engine/file_error.h"
#include "engine/numerical_error.h"
#include "python/bindings.h"

namespace mb::python {

namespace {

// Created once, never destroyed: the interpreter owns the classes (pybind11's exception idiom).
py::exception<DiagramError>* diagram_error = nullptr;
py::exception<AlgebraicLoopError>* algebraic_loop_error = nullptr;
py::exception<NumericalError>* numerical_error = nullptr;

void RaiseDiagramError(const DiagramError& e) {
  py::list problems;
  for (const auto& p : e.problems()) problems.append(p);
  py::object instance = py::handle(diagram_error->ptr())(e.what());
  py::setattr(instance, "problems", problems);
  PyErr_SetObject(diagram_error->ptr(), instance.ptr());
}

void Translate(std::exception_ptr p) {
  try {
    if (p) std::rethrow_exception(p);
  } catch (const AlgebraicLoopError& e) {
    PyErr_SetString(algebraic_loop_error->ptr(), e.what());
  } catch (const DiagramError& e) {
    RaiseDiagramError(e);
  } catch (const NumericalError& e) {
    PyErr_SetString(numerical_error->ptr(), e.what());
  } catch (const FileOpenError& e) {
    PyErr_SetString(PyExc_OSError, e.what());
  } catch (const std::filesystem::filesystem_error& e) {
    PyErr_SetString(PyExc_OSError, e.what());
  }
}

}  // namespace

void BindErrors(py::module_& m) {
  diagram_error = new py::exception<DiagramError>(m, "DiagramError", PyExc_ValueError);
  diagram_error->doc() =
      "A diagram the loader refuses: every problem at once, each '<file>: <JSON pointer>: <message and fix>' "
      "(attribute `problems`: the list).";
  algebraic_loop_error = new py::exception<AlgebraicLoopError>(m, "AlgebraicLoopError", diagram_error->ptr());
  algebraic_loop_error->doc() =
      "A cycle of direct feedthrough: the message names every block and port of the cycle and how to break it.";
  numerical_error = new py::exception<NumericalError>(m, "NumericalError", PyExc_RuntimeError);
  numerical_error->doc() =
      "A run whose numbers failed: a NaN/Inf signal or state (block, port, time), a solver failure, or repeating "
      "events.";
  py::register_exception_translator(&Translate);
}

}  // namespace mb::python

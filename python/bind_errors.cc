// The library's exceptions as Python exceptions with the same messages: DiagramError (a ValueError, with the list
// of problems), AlgebraicLoopError (a DiagramError), NumericalError (a RuntimeError), a file that cannot be opened
// (OSError); std::invalid_argument (and std::domain_error, std::length_error) a ValueError, std::out_of_range an
// IndexError, any other library exception a RuntimeError — each with the text the command line prints
// (tools/workflow/error_text.h): a library's or an internal check's wording replaced by what happened and the fix.

#include <exception>
#include <filesystem>
#include <new>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "engine/diagram_loader.h"
#include "engine/execution_order.h"
#include "engine/file_error.h"
#include "engine/numerical_error.h"
#include "python/bindings.h"
#include "tools/workflow/error_text.h"

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
    PyErr_SetString(PyExc_OSError, ErrorText(e, {}).c_str());
  } catch (const py::builtin_exception&) {
    throw;  // py::value_error, py::type_error, py::cast_error …: pybind11's own translation
  } catch (const std::bad_alloc&) {
    throw;  // MemoryError
  } catch (const std::overflow_error& e) {
    PyErr_SetString(PyExc_OverflowError, ErrorText(e, {}).c_str());
  } catch (const std::invalid_argument& e) {
    PyErr_SetString(PyExc_ValueError, ErrorText(e, {}).c_str());
  } catch (const std::domain_error& e) {
    PyErr_SetString(PyExc_ValueError, ErrorText(e, {}).c_str());
  } catch (const std::length_error& e) {
    PyErr_SetString(PyExc_ValueError, ErrorText(e, {}).c_str());
  } catch (const std::out_of_range& e) {
    PyErr_SetString(PyExc_IndexError, ErrorText(e, {}).c_str());
  } catch (const nlohmann::json::exception& e) {
    PyErr_SetString(PyExc_ValueError, ErrorText(e, {}).c_str());
  } catch (const std::exception& e) {
    PyErr_SetString(PyExc_RuntimeError, ErrorText(e, {}).c_str());
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

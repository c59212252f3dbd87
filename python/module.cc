// PYBIND11_MODULE(motionblocks): the library for Python (README "Python"). One binding file per area.

#include "python/bindings.h"

PYBIND11_MODULE(motionblocks, m) {
  m.doc() =
      "motionblocks: block-diagram simulation for precision motion control, model-vs-measurement diagnosis and the "
      "TISO-GPR disturbance model, as a library. SI units throughout (positions m, velocities m/s, forces N, "
      "time s).";
  mb::python::BindErrors(m);
  mb::python::BindDiagram(m);
  mb::python::BindWorkflow(m);
  mb::python::BindGpr(m);
  mb::python::BindSweep(m);
  mb::python::BindHil(m);
  mb::python::BindLinearize(m);
}

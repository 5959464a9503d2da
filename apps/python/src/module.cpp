// graftnav._graftnav: the compiled part of the Python package (graftnav/__init__.py wraps it).
// Every call that runs C++ for long releases the GIL; arrays cross as 2-D float64 (arrays.h).
#include <pybind11/pybind11.h>
#include <pybind11/stl.h>

#include "bindings.h"

namespace py = pybind11;

PYBIND11_MODULE(_graftnav, m) {
  m.doc() = "graftnav: the SG method's estimators, evaluation and mismatch finder from Python";
  graftnav::python::registerErrors(m);
  graftnav::python::bindCase(m);
  graftnav::python::bindNavigate(m);
  graftnav::python::bindEvaluate(m);
  graftnav::python::bindDiagnose(m);
  graftnav::python::bindSimulate(m);
}

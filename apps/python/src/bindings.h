#pragma once
// One function per part of the Python module; module.cpp calls them in order.
#include <pybind11/pybind11.h>

namespace graftnav::python {

namespace py = pybind11;

// MissingFileError -> FileNotFoundError (filename set), OptionError and std::invalid_argument ->
// ValueError, other std::exception -> RuntimeError.
void registerErrors(py::module_& m);
void bindCase(py::module_& m);      // Case, load_case, from_arrays, the column lists
void bindNavigate(py::module_& m);  // navigate
void bindEvaluate(py::module_& m);  // evaluate
void bindDiagnose(py::module_& m);  // diagnose
void bindSimulate(py::module_& m);  // simulate

}  // namespace graftnav::python

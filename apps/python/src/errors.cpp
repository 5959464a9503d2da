#include <cerrno>
#include <stdexcept>

#include "bindings.h"
#include "graftnav/io/file_errors.h"
#include "run_options.h"

namespace graftnav::python {

void registerErrors(py::module_& m) {
  (void)m;
  py::register_exception_translator([](std::exception_ptr p) {
    try {
      if (p) std::rethrow_exception(p);
    } catch (const MissingFileError& e) {
      // FileNotFoundError(errno, message, filename): e.filename is the path.
      py::object error =
          py::reinterpret_borrow<py::object>(PyExc_FileNotFoundError)(ENOENT, e.what(), e.path());
      PyErr_SetObject(PyExc_FileNotFoundError, error.ptr());
    } catch (const OptionError& e) {
      PyErr_SetString(PyExc_ValueError, e.what());
    }
  });
}

}  // namespace graftnav::python

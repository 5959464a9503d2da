// simulate(): a case from a sim config (core/sim), written to `out`, or to a temporary folder
// that lives as long as the returned case (its lab data and files are read from there).
#include <pybind11/stl.h>

#include <cstdlib>
#include <filesystem>
#include <memory>
#include <optional>

#include "bindings.h"
#include "graftnav/sim/case_simulator.h"
#include "graftnav/sim/sim_config.h"
#include "py_case.h"

namespace graftnav::python {
namespace {

namespace fs = std::filesystem;

// A folder under the system's temporary directory, removed with everything in it on destruction.
class TemporaryFolder {
 public:
  TemporaryFolder() {
    std::string pattern = (fs::temp_directory_path() / "graftnav-sim-XXXXXX").string();
    if (!mkdtemp(pattern.data()))
      throw std::runtime_error("cannot create a temporary folder under " +
                               fs::temp_directory_path().string());
    path_ = pattern;
  }
  ~TemporaryFolder() {
    std::error_code ec;
    fs::remove_all(path_, ec);
  }
  TemporaryFolder(const TemporaryFolder&) = delete;
  TemporaryFolder& operator=(const TemporaryFolder&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

py::tuple simulate(const std::string& sim_config, const std::optional<std::uint64_t>& seed,
                   const std::string& out, bool ideal) {
  std::vector<std::string> warnings;
  SimConfig cfg = loadSimConfig(sim_config, &warnings);
  if (seed) cfg.seed = *seed;
  cfg.ideal = ideal;
  std::shared_ptr<TemporaryFolder> temporary;
  std::string dir = out;
  std::shared_ptr<PyCase> c;
  {
    py::gil_scoped_release release;
    if (dir.empty()) {
      temporary = std::make_shared<TemporaryFolder>();
      dir = (fs::path(temporary->path()) / cfg.name).string();
    }
    simulateCase(cfg, dir);
    c = PyCase::load(dir);
  }
  if (temporary) c->keepAlive(temporary);
  return py::make_tuple(c, warnings);
}

}  // namespace

void bindSimulate(py::module_& m) {
  m.def("simulate", &simulate, py::arg("sim_config"), py::arg("seed"), py::arg("out"),
        py::arg("ideal"));
}

}  // namespace graftnav::python

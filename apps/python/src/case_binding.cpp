// Case, load_case and from_arrays.
#include <pybind11/stl.h>

#include <map>
#include <utility>

#include "arrays.h"
#include "bindings.h"
#include "graftnav/io/case_config.h"
#include "py_case.h"
#include "run_options.h"

namespace graftnav::python {
namespace {

// case.yaml's content: a path, a dict of its keys, or None (a name and the IMU rate only).
CaseConfig caseConfigOf(const py::object& config, const Array& imu,
                        std::vector<std::string>* warnings) {
  if (py::isinstance<py::str>(config)) return loadCaseConfig(config.cast<std::string>(), warnings);
  if (py::isinstance<py::dict>(config)) return parseCaseConfig(toYaml(config), "config", warnings);
  if (!config.is_none()) throw std::invalid_argument("config: expected a case.yaml path or a dict");
  CaseConfig c;
  c.name = "arrays";
  const auto r = imu.unchecked<2>();
  if (r.shape(0) < 2) throw std::invalid_argument("imu: fewer than two samples and no config");
  c.imu_rate_hz = 1.0 / (r(1, 0) - r(0, 0));
  return c;
}

ImuSelection selectionOf(ImuSeries imu, const std::optional<ImuProfile>& profile, bool noise_given,
                         double rate_hz, const std::string& which) {
  ImuSelection s;
  s.imu = std::move(imu);
  if (profile) s.profile = *profile;
  s.profile_given = noise_given;
  s.read_options.nominal_rate_hz = rate_hz;
  s.label = profile && !profile->name.empty() ? profile->name : which;
  s.path = which + " (array)";
  return s;
}

std::shared_ptr<PyCase> fromArrays(const Array& imu, const Array& gnss, const py::object& truth,
                                   const py::object& tested_imu, const py::object& odometer,
                                   const py::object& config) {
  CaseInputs c;
  c.config = caseConfigOf(config, imu, &c.warnings);
  c.gnss = gnssFromArray(gnss, "gnss");
  if (!truth.is_none()) {
    c.reference = navFromArray(truth.cast<Array>(), "truth");
    c.reference_name = "truth (array)";
    c.reference_is_truth = true;
  }
  std::map<std::string, ImuSelection> imus;
  const CaseConfig& cfg = c.config;
  imus.emplace("ref", selectionOf(imuFromArray(imu, cfg.imu_rate_hz, "imu"), cfg.reference_imu,
                                  cfg.reference_imu_noise_given, cfg.imu_rate_hz, "ref"));
  if (!tested_imu.is_none())
    imus.emplace(
        "tested",
        selectionOf(imuFromArray(tested_imu.cast<Array>(), cfg.testedImuRateHz(), "tested_imu"),
                    cfg.tested_imu, cfg.tested_imu_noise_given, cfg.testedImuRateHz(), "tested"));
  OdometerSeries odo;
  if (!odometer.is_none()) odo = odometerFromArray(odometer.cast<Array>(), "odometer");
  return PyCase::fromInputs(std::move(c), std::move(imus), std::move(odo));
}

}  // namespace

void bindCase(py::module_& m) {
  m.attr("IMU_COLUMNS") = imuColumns();
  m.attr("GNSS_COLUMNS") = gnssColumns();
  m.attr("NAV_COLUMNS") = navColumns();
  m.attr("SIGMA_COLUMNS") = sigmaColumns();
  m.attr("IMU_ERROR_COLUMNS") = imuErrorColumns();
  m.attr("ODOMETER_COLUMNS") = odometerColumns();

  py::class_<PyCase, std::shared_ptr<PyCase>>(m, "Case")
      .def_property_readonly("name", [](const PyCase& c) { return c.inputs().config.name; })
      .def_property_readonly("dir",
                             [](const PyCase& c) -> py::object {
                               return c.hasFolder() ? py::object(py::str(c.inputs().dir))
                                                    : py::object(py::none());
                             })
      .def_property_readonly("imu_rate_hz",
                             [](const PyCase& c) { return c.inputs().config.imu_rate_hz; })
      .def_property_readonly("warnings", [](const PyCase& c) { return c.inputs().warnings; })
      .def_property_readonly("reference_name",
                             [](const PyCase& c) { return c.inputs().reference_name; })
      .def_property_readonly("default_imu", &PyCase::defaultImu)
      .def("has_imu", &PyCase::hasImu, py::arg("which"))
      .def(
          "imu",
          [](const PyCase& c, const std::string& which) {
            const ImuSelection* s = nullptr;
            {
              py::gil_scoped_release release;
              s = &c.imu(which);
            }
            return imuToArray(s->imu);
          },
          py::arg("which"))
      .def("imu_label",
           [](const PyCase& c, const std::string& which) { return c.imu(which).label; })
      .def("gnss", [](const PyCase& c) { return gnssToArray(c.inputs().gnss); })
      .def("reference", [](const PyCase& c) -> py::object {
        if (c.inputs().reference.empty()) return py::none();
        return navToArray(c.inputs().reference);
      });

  m.def(
      "load_case",
      [](const std::string& path) {
        py::gil_scoped_release release;
        return PyCase::load(path);
      },
      py::arg("path"));
  m.def("from_arrays", &fromArrays, py::arg("imu"), py::arg("gnss"), py::arg("truth"),
        py::arg("tested_imu"), py::arg("odometer"), py::arg("config"));
}

}  // namespace graftnav::python

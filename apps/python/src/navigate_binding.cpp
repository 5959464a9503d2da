// navigate(): the run config built with the GIL, the run without it, the result as arrays.
#include <pybind11/stl.h>

#include "arrays.h"
#include "bindings.h"
#include "navigate.h"
#include "run_options.h"

namespace graftnav::python {
namespace {

py::dict navigate(const std::shared_ptr<PyCase>& c, const std::string& estimator,
                  const std::string& imu, const std::string& run_config, const py::object& options,
                  double output_rate_hz) {
  if (!(output_rate_hz >= 0.0)) throw OptionError("output_rate_hz must be > 0 (None: every epoch)");
  NavigateRequest request;
  request.estimator = estimator;
  request.imu = imu.empty() ? c->defaultImu() : imu;
  std::vector<std::string> config_warnings;
  request.rc =
      runConfigFor(c->hasFolder() ? c->inputs().dir : "", run_config, options, &config_warnings);
  NavigateOutcome out;
  {
    py::gil_scoped_release release;
    out = navigateCase(*c, request);
  }
  const std::vector<std::size_t> rows = decimatedRows(out.solution.states, output_rate_hz);
  py::dict d;
  d["estimator"] = estimator;
  d["imu"] = request.imu;
  d["solution"] = solutionToArray(out.solution, rows);
  d["imu_errors"] = imuErrorsToArray(out.solution, rows);
  d["statistics_json"] =
      out.evaluated ? py::object(py::str(out.statistics_json)) : py::object(py::none());
  d["reference"] = out.reference;
  d["gnss"] = py::dict(py::arg("used") = out.solution.gnss_used,
                       py::arg("rejected") = out.solution.gnss_rejected,
                       py::arg("withheld") = out.solution.gnss_withheld);
  std::vector<std::pair<double, double>> windows;
  for (const auto& w : out.outages) windows.emplace_back(w.start_s, w.end_s);
  d["outage_windows_s"] = windows;
  d["notes"] = out.notes;
  config_warnings.insert(config_warnings.end(), out.warnings.begin(), out.warnings.end());
  d["warnings"] = config_warnings;
  return d;
}

}  // namespace

void bindNavigate(py::module_& m) {
  m.def("navigate", &navigate, py::arg("case"), py::arg("estimator"), py::arg("imu"),
        py::arg("run_config"), py::arg("options"), py::arg("output_rate_hz"));
}

}  // namespace graftnav::python

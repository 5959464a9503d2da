// evaluate(): evaluation.json's content and each realization's statistics.
#include <pybind11/stl.h>

#include "arrays.h"
#include "bindings.h"
#include "evaluate.h"
#include "graftnav/nav/units.h"
#include "run_options.h"

namespace graftnav::python {
namespace {

// One row per realization: horizontal_m, vertical_m, roll_deg, pitch_deg, heading_deg.
Array drawsToArray(const std::vector<DriftStats>& draws) {
  Array a({static_cast<py::ssize_t>(draws.size()), py::ssize_t{5}});
  auto r = a.mutable_unchecked<2>();
  for (std::size_t k = 0; k < draws.size(); ++k) {
    const DriftStats& d = draws[k];
    r(k, 0) = d.horizontal_m;
    r(k, 1) = d.vertical_m;
    r(k, 2) = d.roll_rad * units::kRadToDeg;
    r(k, 3) = d.pitch_rad * units::kRadToDeg;
    r(k, 4) = d.heading_rad * units::kRadToDeg;
  }
  return a;
}

py::dict evaluate(const std::shared_ptr<PyCase>& c, const std::string& estimator,
                  const py::object& realizations, std::uint64_t seed, const std::string& run_config,
                  const py::object& options, int jobs) {
  EvaluateRequest request;
  request.estimator = estimator;
  if (!realizations.is_none()) request.realizations = realizations.cast<int>();
  request.seed = seed;
  request.jobs = jobs;
  std::vector<std::string> warnings;
  request.rc = runConfigFor(c->hasFolder() ? c->inputs().dir : "", run_config, options, &warnings,
                            "graftnav.evaluate");
  EvaluateOutcome out;
  {
    py::gil_scoped_release release;
    out = evaluateCase(*c, request);
  }
  py::dict draws;
  for (const auto& s : out.report.solutions)
    if (!s.draws.empty()) draws[py::str(s.label)] = drawsToArray(s.draws);
  warnings.insert(warnings.end(), out.warnings.begin(), out.warnings.end());
  py::dict d;
  d["evaluation_json"] = out.evaluation_json;
  d["draws"] = draws;
  d["warnings"] = warnings;
  return d;
}

}  // namespace

void bindEvaluate(py::module_& m) {
  m.attr("DRAW_COLUMNS") = std::vector<std::string>{"horizontal_m", "vertical_m", "roll_deg",
                                                    "pitch_deg", "heading_deg"};
  m.def("evaluate", &evaluate, py::arg("case"), py::arg("estimator"), py::arg("realizations"),
        py::arg("seed"), py::arg("run_config"), py::arg("options"), py::arg("jobs"));
}

}  // namespace graftnav::python

// diagnose(): the mismatch finder on a case folder, as `graftnav diagnose` runs it without
// --estimator (diagnosisInputsOf of core/mismatch): the simulation of the tested IMU (SG#2 from
// the lab data, else the reference plus the tested IMU's static bias) against its real field
// recording. The report is diagnosis.json's
// content. Runs without the GIL.
#include <pybind11/stl.h>

#include "bindings.h"
#include "graftnav/io/file_errors.h"
#include "graftnav/mismatch/diagnose_config.h"
#include "graftnav/mismatch/diagnosis_case.h"
#include "graftnav/mismatch/diagnosis.h"
#include "graftnav/mismatch/diagnosis_report.h"
#include "py_case.h"
#include "run_options.h"

namespace graftnav::python {
namespace {

struct DiagnoseOutcome {
  std::string json;
  std::vector<std::string> warnings;
};

DiagnoseOutcome diagnoseCase(const PyCase& pc, const RunConfig& rc,
                             const DiagnoseOptions& options) {
  if (!pc.hasFolder())
    throw std::invalid_argument("diagnose needs the case's folder (lab data, truth): load it");
  if (!pc.hasImu("tested"))
    throw MissingFileError(
        pc.inputs().paths().testedImu(),
        pc.inputs().paths().testedImu() + ": diagnose needs the tested IMU's field recording");
  DiagnoseOutcome out;
  std::vector<std::string> notes;
  CaseInputs c;  // what the finder reads of the case: its folder and case.yaml
  c.dir = pc.inputs().dir;
  c.config = pc.inputs().config;
  ImuSelection ref = pc.imu("ref"), tested = pc.imu("tested");  // moved into the finder
  DiagnosisInputs in =
      diagnosisInputsOf(c, rc, &ref, &tested, {}, &notes, [&out](const std::string& line) {
        if (line.rfind("warning: ", 0) == 0) out.warnings.push_back(line.substr(9));
      });
  DiagnosisResult res = diagnose(std::move(in), options);
  res.notes.insert(res.notes.end(), notes.begin(), notes.end());
  out.json = diagnosisJson(res);
  return out;
}

py::dict diagnosePy(const std::shared_ptr<PyCase>& c, const std::string& diagnose_config,
                    const std::string& run_config, const py::object& options) {
  std::vector<std::string> warnings;
  const RunConfig rc =
      runConfigFor(c->inputs().dir, run_config, options, &warnings, "graftnav.diagnose");
  DiagnoseOptions opt;
  if (!diagnose_config.empty()) {
    try {
      opt = loadDiagnoseConfig(diagnose_config, &warnings);
    } catch (const MissingFileError&) {
      throw;
    } catch (const std::exception& e) {
      throw OptionError(e.what());
    }
  }
  DiagnoseOutcome out;
  {
    py::gil_scoped_release release;
    out = diagnoseCase(*c, rc, opt);
  }
  warnings.insert(warnings.end(), out.warnings.begin(), out.warnings.end());
  py::dict d;
  d["diagnosis_json"] = out.json;
  d["warnings"] = warnings;
  return d;
}

}  // namespace

void bindDiagnose(py::module_& m) {
  m.def("diagnose", &diagnosePy, py::arg("case"), py::arg("diagnose_config"), py::arg("run_config"),
        py::arg("options"));
}

}  // namespace graftnav::python

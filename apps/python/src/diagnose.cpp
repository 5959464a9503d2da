// diagnose(): the mismatch finder on a case folder, as `graftnav diagnose` runs it without
// --estimator: the simulation of the tested IMU (SG#2 from the lab data, else the reference plus
// the tested IMU's static bias) against its real field recording. The report is diagnosis.json's
// content. Runs without the GIL.
#include <pybind11/stl.h>

#include "bindings.h"
#include "graftnav/calibration/lab_data.h"
#include "graftnav/case/input_checks.h"
#include "graftnav/io/file_errors.h"
#include "graftnav/io/imu_io.h"
#include "graftnav/io/nav_io.h"
#include "graftnav/mismatch/diagnose_config.h"
#include "graftnav/mismatch/diagnosis.h"
#include "graftnav/mismatch/diagnosis_report.h"
#include "graftnav/mismatch/diagnosis_setup.h"
#include "py_case.h"
#include "run_options.h"

namespace graftnav::python {
namespace {

struct DiagnoseOutcome {
  std::string json;
  std::vector<std::string> warnings;
};

// The finder's inputs: records, plausible ranges, the simulation and its priors.
DiagnosisInputs finderInputs(const PyCase& pc, const RunConfig& rc, std::vector<std::string>* notes,
                             std::vector<std::string>* warnings) {
  const CaseInputs& c = pc.inputs();
  const CaseConfig& cfg = c.config;
  DiagnosisInputs in;
  in.case_name = cfg.name;
  in.reference = pc.imu("ref").imu;
  in.real = pc.imu("tested").imu;
  in.initial_state = cfg.initial_state;
  if (cfg.tested_imu) in.tested_plausible_ranges = cfg.tested_imu->plausible_ranges;
  if (in.tested_plausible_ranges) in.tested_plausible_ranges->validate();
  if (CasePaths::exists(c.paths().labStatic())) {
    PerSensor<double> ref_scale_std;
    if (cfg.reference_imu) {
      ref_scale_std[Sensor::gyro] = cfg.reference_imu->gyro_scale_std;
      ref_scale_std[Sensor::accel] = cfg.reference_imu->accel_scale_std;
    }
    const std::string dir = c.dir;
    LabData lab = loadLabData(dir);
    if (lab.has_static) {
      const auto w = checkLabStaticRecord(lab.staticRecordSeconds(), lab.static_file, 0.0);
      warnings->insert(warnings->end(), w.begin(), w.end());
    }
    simulateFromLab(lab, rc.grafting.start_offset_s, ref_scale_std, &in,
                    [dir] { return loadLabData(dir); });
  } else {
    simulateWithoutLab(&in, notes, warnings);
  }
  const std::string truth = c.paths().truthNav();
  in.reference_is_simulated = CasePaths::exists(truth);
  if (in.reference_is_simulated) in.read_attitude = [truth] { return readNav(truth); };
  return in;
}

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
  DiagnosisResult res = diagnose(finderInputs(pc, rc, &notes, &out.warnings), options);
  res.notes.insert(res.notes.end(), notes.begin(), notes.end());
  out.json = diagnosisJson(res);
  return out;
}

py::dict diagnosePy(const std::shared_ptr<PyCase>& c, const std::string& diagnose_config,
                    const std::string& run_config, const py::object& options) {
  std::vector<std::string> warnings;
  const RunConfig rc = runConfigFor(c->inputs().dir, run_config, options, &warnings);
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

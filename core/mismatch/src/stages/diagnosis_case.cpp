#include "graftnav/mismatch/diagnosis_case.h"

#include <stdexcept>
#include <string>
#include <utility>

#include "graftnav/calibration/lab_data.h"
#include "graftnav/case/file_streams.h"
#include "graftnav/case/input_checks.h"
#include "graftnav/io/imu_recording.h"
#include "graftnav/io/imu_profile_io.h"
#include "graftnav/io/nav_io.h"
#include "graftnav/mismatch/diagnosis_setup.h"

namespace graftnav {
namespace {

// The tested IMU's file, read once into a spool that each of the finder's passes reads back.
ImuRecording testedRecording(const ImuSelection& tested, const DiagnosisLog& log) {
  ReadReport report;
  ImuRecording rec;
  try {
    rec = spooledRecording(imuFileStream(tested.path, tested.read_options, &report));
  } catch (const std::invalid_argument&) {
    throw std::runtime_error("IMU file '" + tested.path + "' holds no sample");
  }
  if (const std::string summary = report.summary(); !summary.empty()) log("warning: " + summary);
  return rec;
}

}  // namespace

DiagnosisInputs diagnosisInputsOf(CaseInputs& c, const RunConfig& rc, ImuSelection* ref_imu,
                                  ImuSelection* tested, const DiagnosisCaseOptions& o,
                                  std::vector<std::string>* notes, const DiagnosisLog& log) {
  const CaseConfig& cfg = c.config;
  DiagnosisInputs in;
  in.case_name = cfg.name;
  in.reference = std::move(ref_imu->imu);
  if (!tested->imu.empty()) {
    in.real = std::move(tested->imu);
  } else {
    in.real_recording = testedRecording(*tested, log);
  }
  in.initial_state = cfg.initial_state;
  // The ranges a claimed value must lie in: the tested profile's (its class, or its grade's).
  if (!o.tested_profile.empty()) {
    std::vector<std::string> profile_warnings;
    in.tested_plausible_ranges =
        loadImuProfile(o.tested_profile, &profile_warnings).plausible_ranges;
    for (const auto& w : profile_warnings) log("warning: " + w);
  } else if (cfg.tested_imu) {
    in.tested_plausible_ranges = cfg.tested_imu->plausible_ranges;
  }
  if (in.tested_plausible_ranges) in.tested_plausible_ranges->validate();
  if (CasePaths::exists(c.paths().labStatic())) {
    log("diagnose: lab data found: simulation = SG#2 from the lab calibration");
    PerSensor<double> ref_scale_std;
    if (cfg.reference_imu) {
      ref_scale_std[Sensor::gyro] = cfg.reference_imu->gyro_scale_std;
      ref_scale_std[Sensor::accel] = cfg.reference_imu->accel_scale_std;
    }
    const std::string case_dir = c.dir;
    LabData lab = loadLabData(case_dir);
    if (lab.has_static) checkLabStaticRecord(lab.staticRecordSeconds(), lab.static_file, 0.0);
    simulateFromLab(
        std::move(lab), rc.grafting.start_offset_s, ref_scale_std, &in,
        [case_dir] { return loadLabData(case_dir); }, true);
  } else {
    std::vector<std::string> warnings;
    if (in.real_recording) {  // the static-bias simulation reads the whole tested record
      in.real = collectRecording(*in.real_recording);
      in.real_recording.reset();
    }
    simulateWithoutLab(&in, notes, &warnings);
    for (const auto& w : warnings) log("warning: " + w);
  }
  // A case with a truth trajectory is simulated: its reference IMU may lack navigation physics.
  // The truth is as long as the records: the finder reads it when it needs the attitude, after
  // it has binned them; the navigation level reads it here (its SOL_REF), after the simulation.
  const std::string truth = c.paths().truthNav();
  in.reference_is_simulated = CasePaths::exists(truth);
  if (!o.navigation_level) {
    if (in.reference_is_simulated) in.read_attitude = [truth] { return readNav(truth); };
    return in;
  }
  const std::size_t warned = c.warnings.size();
  loadCaseReference(&c, true);
  for (std::size_t k = warned; k < c.warnings.size(); ++k) log("warning: " + c.warnings[k]);
  // The case holds it for the navigation level anyway: the finder takes a copy only while it
  // builds the regressors.
  if (in.reference_is_simulated) in.read_attitude = [&c] { return c.reference; };
  return in;
}

}  // namespace graftnav

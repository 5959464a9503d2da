#include "evaluate.h"

#include <utility>

#include "graftnav/calibration/lab_calibration.h"
#include "graftnav/calibration/lab_data.h"
#include "graftnav/case/input_checks.h"
#include "graftnav/case/problem.h"
#include "graftnav/case/reference_solution.h"
#include "graftnav/case/sg_case_evaluation.h"
#include "graftnav/estimators/estimator_table.h"
#include "graftnav/io/imu_io.h"
#include "graftnav/sg/evaluate_pipeline.h"
#include "graftnav/sg/graft_case.h"
#include "graftnav/sg/sg_report_files.h"

namespace graftnav::python {
namespace {

double imuBegin(const ImuSeries& imu) { return imu.front().t_s - imu.front().dt_s; }

// The checks `graftnav evaluate` runs before it starts (graftnav/case/input_checks.h).
std::vector<std::string> checkInputs(const CaseInputs& c, const ImuSelection& ref,
                                     const OutageScheduleConfig& oc) {
  const CaseConfig& cfg = c.config;
  requireTestedNoise(c);
  std::vector<std::string> w = checkGnssCoverage(c.gnss, c.paths().gnssPos(), ref.imu, false);
  const double t0 = imuBegin(ref.imu), t1 = ref.imu.back().t_s;
  const std::vector<TimeWindow> windows = buildOutageWindows(oc, t0, t1);
  requireOutagesInsideData(oc, windows, t0, t1);
  const auto add = [&w](const std::vector<std::string>& more) {
    w.insert(w.end(), more.begin(), more.end());
  };
  add(checkReferenceCoverage(c.reference, c.reference_name, ref.imu, windows));
  const std::string static_path = c.paths().labStatic();
  if (CasePaths::exists(static_path)) {
    ImuReadOptions ro;  // the span and the range checks; loadLabData applies its own rules
    ro.nominal_rate_hz = cfg.testedImuRateHz();
    ro.policy = ImuReadPolicy::real();
    const ImuSeries st = readImu(static_path, ro);
    add(checkLabStaticRecord(st.back().t_s - imuBegin(st), static_path, outageSpacing(windows)));
  }
  return w;
}

}  // namespace

EvaluateOutcome evaluateCase(const PyCase& pc, const EvaluateRequest& r) {
  if (!pc.hasFolder())
    throw std::invalid_argument(
        "evaluate needs the case's lab data (lab/): load the case from its folder");
  estimatorTable().find(r.estimator);
  const CaseInputs& c = pc.inputs();
  const RunConfig& rc = r.rc;
  const SgEvaluationOptions po = sgPipelineOptions(rc, r.realizations, {}, r.seed, r.jobs);
  po.validate();

  EvaluateOutcome out;
  const ImuSelection& ref = pc.imu("ref");
  out.warnings = checkInputs(c, ref, rc.outages);
  const LabCalibrationReport lab = calibrateLab(loadLabData(c.dir));
  SgEvaluationInputs in = sgPipelineInputs(c.dir, c, rc.outages, lab);
  in.reference_imu = ref.imu;
  const ImuSelection* real = nullptr;
  if (pc.hasImu("tested")) {
    real = &pc.imu("tested");
    in.has_real = true;
    in.real_imu_file = real->path;
  }
  const SgEvaluationPipeline pipeline(po, makeGraftPlan(lab, true), std::move(in));
  ReferenceSolution sol_ref = resolveReferenceSolution(
      c, [&ref] { return ref; }, rc, estimatorTable());
  out.report =
      pipeline.run({std::move(sol_ref.states), sol_ref.description},
                   heldCaseNavigator(c, rc, real, estimatorTable(), r.estimator), r.estimator);
  out.report.case_name = c.config.name;
  out.report.tested_grade = c.config.tested_imu->grade;
  out.report.csv_rate_hz = rc.evaluation.csv_rate_hz;
  out.evaluation_json = evaluationJson(out.report).dump();
  return out;
}

}  // namespace graftnav::python

#include "evaluate.h"

#include <utility>

#include "graftnav/calibration/lab_calibration.h"
#include "graftnav/calibration/lab_data.h"
#include "graftnav/case/input_checks.h"
#include "graftnav/case/problem.h"
#include "graftnav/case/reference_solution.h"
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
  if (!cfg.tested_imu || !cfg.tested_imu_noise_given)
    throw std::runtime_error(
        c.paths().caseYaml() +
        ": tested_imu needs its noise parameters (arw_deg_rt_h, vrw_m_s_rt_h, "
        "gyro_bias_instability_deg_h, accel_bias_instability_mg) to be navigated");
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

// The case's navigator: makeProblem with the tested IMU's profile, then the chosen estimator.
SgNavigator caseNavigator(const CaseInputs& c, const RunConfig& rc, const ImuSelection* real,
                          const std::string& estimator) {
  return [&c, &rc, real, estimator](std::optional<ImuSeries> grafted,
                                    const OutageScheduleConfig& schedule) {
    SgNavigation nav;
    EstimationProblem pr;
    if (grafted) {
      const ImuSelection sel = graftedSelection(std::move(*grafted), *c.config.tested_imu);
      grafted.reset();
      pr = makeProblem(c, sel, rc, schedule, &nav.notes);
    } else {
      pr = makeProblem(c, *real, rc, schedule, &nav.notes);
    }
    nav.solution = estimatorTable().run(estimator, pr, rc);
    nav.outages = pr.outages;
    return nav;
  };
}

}  // namespace

EvaluateOutcome evaluateCase(const PyCase& pc, const EvaluateRequest& r) {
  if (!pc.hasFolder())
    throw std::invalid_argument(
        "evaluate needs the case's lab data (lab/): load the case from its folder");
  estimatorTable().find(r.estimator);
  const CaseInputs& c = pc.inputs();
  const RunConfig& rc = r.rc;
  SgEvaluationOptions po;
  po.realizations = r.realizations.value_or(rc.grafting.realizations);
  po.outage_shifts = rc.grafting.outage_shifts;
  po.seed = r.seed;
  po.start_offset_s = rc.grafting.start_offset_s;
  po.jobs = r.jobs;
  po.evaluation = rc.evaluation.options;
  po.validate();

  EvaluateOutcome out;
  const ImuSelection& ref = pc.imu("ref");
  out.warnings = checkInputs(c, ref, rc.outages);
  const LabCalibrationReport lab = calibrateLab(loadLabData(c.dir));
  SgEvaluationInputs in;
  in.case_name = c.dir;
  for (const auto& n : lab.notes) in.notes.push_back("calibration: " + n);
  in.reference_imu = ref.imu;
  in.tested_profile = *c.config.tested_imu;
  if (c.config.reference_imu && c.config.reference_imu_noise_given)
    in.reference_noise_profile = *c.config.reference_imu;
  in.outages = rc.outages;
  const ImuSelection* real = nullptr;
  if (pc.hasImu("tested")) {
    real = &pc.imu("tested");
    in.has_real = true;
    in.real_imu_file = real->path;
  }
  const SgEvaluationPipeline pipeline(po, makeGraftPlan(lab, true), std::move(in));
  ReferenceSolution sol_ref = resolveReferenceSolution(
      c, [&ref] { return ref; }, rc, estimatorTable());
  out.report = pipeline.run({std::move(sol_ref.states), sol_ref.description},
                            caseNavigator(c, rc, real, r.estimator), r.estimator);
  out.report.case_name = c.config.name;
  out.report.tested_grade = c.config.tested_imu->grade;
  out.report.csv_rate_hz = rc.evaluation.csv_rate_hz;
  out.evaluation_json = evaluationJson(out.report).dump();
  return out;
}

}  // namespace graftnav::python

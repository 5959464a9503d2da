#include "sg_evaluate.h"

#include <fmt/core.h>
#include <fmt/format.h>

#include <filesystem>
#include <optional>
#include <stdexcept>
#include <utility>

#include "graftnav/case/case_inputs.h"
#include "graftnav/case/input_checks.h"
#include "graftnav/case/outage_overrides.h"
#include "graftnav/case/problem.h"
#include "graftnav/case/reference_solution.h"
#include "graftnav/estimators/estimator_table.h"
#include "graftnav/calibration/calibration_io.h"
#include "graftnav/calibration/lab_calibration.h"
#include "graftnav/calibration/lab_data.h"
#include "graftnav/io/imu_io.h"
#include "graftnav/sg/evaluate_pipeline.h"
#include "graftnav/sg/sg_report_files.h"
#include "script_locator.h"

namespace graftnav::app {
namespace fs = std::filesystem;

namespace {

OutageOverrides outageOverrides(const SgEvaluateOptions& o) {
  return {o.outage_length_s, o.outage_period_s, o.outage_start_s};
}

double imuBegin(const ImuSeries& imu) { return imu.front().t_s - imu.front().dt_s; }

SgEvaluationOptions pipelineOptions(const SgEvaluateOptions& o, const RunConfig& rc) {
  SgEvaluationOptions p;
  p.realizations = o.realizations.value_or(rc.grafting.realizations);
  p.outage_shifts = o.outage_shifts.value_or(rc.grafting.outage_shifts);
  p.seed = o.seed;
  p.start_offset_s = rc.grafting.start_offset_s;
  p.jobs = o.jobs;
  p.evaluation = rc.evaluation.options;
  return p;
}

SolutionReference solutionReference(const SgEvaluateOptions& o, const CaseInputs& c,
                                    const ImuSelection& ref, const RunConfig& rc, const LogFn& log,
                                    const std::string& tag) {
  ReferenceSolutionOptions ro;
  ro.use_case_reference = o.sol_ref == "auto";
  if (!ro.use_case_reference || c.reference.empty())
    log(fmt::format("[{}] smoothing SOL_REF (rts) from the reference IMU and all GNSS", tag));
  ReferenceSolution r = resolveReferenceSolution(
      c, [&ref] { return ref; }, rc, estimatorTable(), ro);
  return {std::move(r.states), r.description};
}

// The case's navigator: makeProblem with the tested IMU's profile, then the chosen estimator.
SgNavigator caseNavigator(const CaseInputs& c, const RunConfig& rc,
                          const std::optional<ImuSelection>& real, const std::string& estimator) {
  return [&c, &rc, &real, estimator](std::optional<ImuSeries> grafted,
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

void requireTestedNoise(const CaseInputs& c) {
  const CaseConfig& cfg = c.config;
  if (!cfg.tested_imu || !cfg.tested_imu_noise_given) {
    throw std::runtime_error(
        c.paths().caseYaml() +
        ": tested_imu needs its noise parameters (arw_deg_rt_h, vrw_m_s_rt_h, "
        "gyro_bias_instability_deg_h, accel_bias_instability_mg) to be navigated");
  }
}

// The pipeline's inputs from the case: the lab calibration's graft plan and the reference IMU.
SgEvaluationInputs pipelineInputs(const SgEvaluateOptions& o, const CaseInputs& c,
                                  const ImuSelection& ref, const OutageScheduleConfig& oc,
                                  const LabCalibrationReport& lab) {
  SgEvaluationInputs in;
  in.case_name = o.case_dir;
  for (const auto& n : lab.notes) in.notes.push_back("calibration: " + n);
  in.reference_imu = ref.imu;
  in.tested_profile = *c.config.tested_imu;
  if (c.config.reference_imu && c.config.reference_imu_noise_given)
    in.reference_noise_profile = *c.config.reference_imu;
  in.outages = oc;
  return in;
}

}  // namespace

std::vector<std::string> checkEvaluationInputs(const SgEvaluateOptions& o) {
  std::vector<std::string> w;
  const auto add = [&](std::vector<std::string> more) {
    w.insert(w.end(), more.begin(), more.end());
  };
  if (!estimatorTable().contains(o.estimator))
    throw std::runtime_error("--estimator '" + o.estimator +
                             "': unknown (known: " + estimatorTable().namesText() + ")");
  outageOverrides(o).validate();
  const CaseInputs c = loadCaseInputs(o.case_dir);
  RunConfig rc;
  if (!o.run_config.empty()) rc = loadRunConfig(o.run_config, nullptr);
  const OutageScheduleConfig oc = outageOverrides(o).appliedTo(rc.outages);
  const ImuSelection ref = selectImu(c, "ref");
  if (CasePaths::exists(c.paths().testedImu()))
    selectImu(c, "tested");  // range checks of the tested file
  add(checkGnssCoverage(c.gnss, c.paths().gnssPos(), ref.imu, false));
  const double t0 = imuBegin(ref.imu), t1 = ref.imu.back().t_s;
  std::vector<TimeWindow> windows;
  try {
    windows = buildOutageWindows(oc, t0, t1);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(std::string("outage schedule: ") + e.what());
  }
  requireOutagesInsideData(oc, windows, t0, t1);
  add(checkReferenceCoverage(c.reference, c.reference_name, ref.imu, windows));
  const std::string static_path = c.paths().labStatic();
  if (CasePaths::exists(static_path)) {
    ImuReadOptions ro;
    ro.nominal_rate_hz = c.config.testedImuRateHz();
    ro.policy = ImuReadPolicy::
        real();  // only the span and the range checks; loadLabData applies its own rules
    const ImuSeries st = readImu(static_path, ro);
    add(checkLabStaticRecord(st.back().t_s - imuBegin(st), static_path, outageSpacing(windows)));
  }
  return w;
}

void writeSgOutputs(const std::string& out_dir, const SgEvaluationReport& rep, bool plots,
                    const LogFn& log) {
  writeSgEvaluationFiles(out_dir, rep);
  if (plots) {
    const std::string w = runPythonScript("plot_sg.py", {out_dir});
    if (!w.empty()) log("warning: " + w);
  }
}

SgEvaluationReport runSgEvaluation(const SgEvaluateOptions& o, const LogFn& log_in) {
  const LogFn log = log_in ? log_in : [](const std::string&) {};
  for (const auto& w : checkEvaluationInputs(o)) log("warning: " + w);  // before any output
  const std::string tag = fs::path(o.case_dir).filename().string();
  const CaseInputs c = loadCaseInputs(o.case_dir);
  for (const auto& w : c.warnings) log("warning: " + w);
  requireTestedNoise(c);
  std::vector<std::string> cw;
  RunConfig rc;
  if (!o.run_config.empty()) rc = loadRunConfig(o.run_config, &cw);
  for (const auto& w : cw) log("warning: " + w);
  const ImuSelection ref = selectImu(c, "ref");
  const SgEvaluationOptions po = pipelineOptions(o, rc);
  po.validate();
  log(fmt::format("[{}] calibrating the tested IMU from lab/", tag));
  const LabCalibrationReport lab = calibrateLab(loadLabData(o.case_dir));
  SgEvaluationInputs in = pipelineInputs(o, c, ref, outageOverrides(o).appliedTo(rc.outages), lab);
  std::optional<ImuSelection> real;
  if (CasePaths::exists(c.paths().testedImu())) {
    real = selectImu(c, "tested");
    in.has_real = true;
    in.real_imu_file = real->path;
  }
  const SgEvaluationPipeline pipeline(po, makeGraftPlan(lab, o.use_cross_axis), std::move(in));
  const SolutionReference sol_ref = solutionReference(o, c, ref, rc, log, tag);

  // Only now are files written.
  fs::create_directories(o.out_dir);
  writeCalibrationYaml((fs::path(o.out_dir) / "calibration.yaml").string(), lab.result);
  for (SgStrategy g : po.strategies) {
    if (o.write_grafted_imu)
      writeImu((fs::path(o.out_dir) / (std::string("IMU_") + sgLabel(g) + ".txt")).string(),
               pipeline.graft(g, 0));
  }
  SgEvaluationReport rep =
      pipeline.run(sol_ref, caseNavigator(c, rc, real, o.estimator), o.estimator, log);
  for (auto& s : rep.solutions)
    if (s.label != "REAL")
      s.imu_file = (fs::path(o.out_dir) / ("IMU_" + s.label + ".txt")).string();
  rep.case_name = c.config.name;
  rep.tested_grade = c.config.tested_imu->grade;
  rep.csv_rate_hz = rc.evaluation.csv_rate_hz;
  writeSgOutputs(o.out_dir, rep, o.plots, log);
  return rep;
}

}  // namespace graftnav::app

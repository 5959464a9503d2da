#include "sg_evaluate.h"

#include <fmt/core.h>

#include <algorithm>
#include <filesystem>
#include <future>
#include <stdexcept>
#include <thread>

#include "case_loader.h"
#include "estimators.h"
#include "input_checks.h"
#include "graftnav/calibration/calibration_io.h"
#include "graftnav/calibration/lab_calibration.h"
#include "graftnav/calibration/lab_data.h"
#include "graftnav/sg/graft_case.h"
#include "graftnav/io/imu_io.h"
#include "graftnav/nav/units.h"
#include "report_io.h"
#include "script_locator.h"

namespace graftnav::app {
namespace fs = std::filesystem;

namespace {

struct Job {
  std::string label;
  ImuSelection imu;
};

}  // namespace

SgEvaluationReport runSgEvaluation(const SgEvaluateOptions& o, const LogFn& log_in) {
  const LogFn log = log_in ? log_in : [](const std::string&) {};
  for (const auto& w : checkEvaluationInputs(o)) log("warning: " + w);  // before any output
  fs::create_directories(o.out_dir);
  const std::string tag = fs::path(o.case_dir).filename().string();

  CaseInputs c = loadCaseInputs(o.case_dir);
  for (const auto& w : c.warnings) log("warning: " + w);
  const CaseConfig& cfg = c.config;
  if (!cfg.tested_imu || !cfg.tested_imu_noise_given) {
    throw std::runtime_error(c.paths().caseYaml() +
                             ": tested_imu needs its noise parameters (arw_deg_rt_h, vrw_m_s_rt_h, "
                             "gyro_bias_instability_deg_h, accel_bias_instability_mg) to be navigated");
  }
  RunConfig rc;
  std::vector<std::string> cw;
  if (!o.config_path.empty()) rc = loadRunConfig(o.config_path, &cw);
  for (const auto& w : cw) log("warning: " + w);
  OutageScheduleConfig oc = rc.outages;
  if (o.outage_length_s) oc.length_s = *o.outage_length_s;
  if (o.outage_period_s) oc.period_s = *o.outage_period_s;
  if (o.outage_start_s) oc.start_s = *o.outage_start_s;

  SgEvaluationReport rep;
  rep.case_name = cfg.name;
  rep.estimator = o.estimator;
  rep.tested_grade = cfg.tested_imu->grade;

  // 1. Lab calibration and the basic error signal.
  log(fmt::format("[{}] calibrating the tested IMU from lab/", tag));
  const LabData lab = loadLabData(o.case_dir);
  const LabCalibrationReport labrep = calibrateLab(lab);
  for (const auto& n : labrep.notes) rep.notes.push_back("calibration: " + n);
  writeCalibrationYaml((fs::path(o.out_dir) / "calibration.yaml").string(), labrep.result);

  // 2. Grafting.
  const ImuSelection ref = selectImu(c, "ref");
  // A rate that disagrees with case.yaml is rejected by the strict reader (file, line, interval).
  GraftCaseOptions go;
  go.graft.seed = o.seed;
  go.graft.start_offset_s = rc.grafting.start_offset_s;
  go.use_cross_axis = o.use_cross_axis;
  log(fmt::format("[{}] grafting SG#1 and SG#2 onto {} reference samples", tag, ref.imu.size()));
  GraftedCase g = graftCase(ref.imu, labrep, go);
  rep.notes.push_back(fmt::format(
      "basic error signal: lab static record {:.1f} s, extended by mirrored tiling over {} record "
      "lengths, field start at {:.2f} s of the tiled record (seed {})",
      g.static_record_s, g.tiles, g.start_offset_s, o.seed));
  if (cfg.reference_imu && cfg.reference_imu_noise_given) {
    const Eigen::Vector2d f = referenceResidualFraction(*cfg.reference_imu, *cfg.tested_imu);
    rep.notes.push_back(fmt::format(
        "the reference IMU's own white noise, grafted along, is {:.2f} % (gyro) and {:.2f} % (accel) "
        "of the tested IMU's",
        100.0 * f[0], 100.0 * f[1]));
  }
  std::vector<Job> jobs;
  auto grafted = [&](const std::string& label, ImuSeries&& imu) {
    Job j;
    j.label = label;
    j.imu.imu = std::move(imu);
    j.imu.profile = *cfg.tested_imu;
    j.imu.profile_given = true;
    j.imu.path = (fs::path(o.out_dir) / ("IMU_" + label + ".txt")).string();
    j.imu.label = label;
    if (o.write_grafted_imu) writeImu(j.imu.path, j.imu.imu);
    jobs.push_back(std::move(j));
  };
  grafted("SG1", std::move(g.sg1));
  grafted("SG2", std::move(g.sg2));
  if (CasePaths::exists(c.paths().testedImu())) {
    jobs.push_back({"REAL", selectImu(c, "tested")});
  } else {
    rep.notes.push_back("no field/tested_imu.txt: ERR_REAL and DIFF are not available");
  }

  // 3. SOL_REF.
  NavSeries sol_ref;
  if (o.sol_ref == "auto" && !c.reference.empty()) {
    sol_ref = c.reference;
    rep.reference = c.reference_is_truth ? "truth (" + c.reference_name + ")"
                                         : "external reference solution (" + c.reference_name + ")";
  } else {
    if (!ref.profile_given) {
      throw std::runtime_error(c.paths().caseYaml() + ": reference_imu needs noise parameters to smooth SOL_REF");
    }
    log(fmt::format("[{}] smoothing SOL_REF (rts) from the reference IMU and all GNSS", tag));
    std::vector<std::string> n;
    const EstimationProblem pr = makeProblem(c, ref, rc, std::nullopt, &n);
    sol_ref = runEstimator("rts", pr, rc).states;
    rep.reference = "RTS-smoothed reference IMU with all GNSS (SOL_REF of the seed)";
  }

  // 4. Navigate every IMU with the same outage schedule.
  std::vector<EstimationProblem> problems;
  for (const auto& j : jobs) {
    std::vector<std::string> n;
    problems.push_back(makeProblem(c, j.imu, rc, oc, &n));
    if (&j == &jobs.front())
      for (const auto& s : n) rep.notes.push_back(s);
  }
  rep.outages = problems.front().outages;
  rep.outage_length_s = rep.outages.empty() ? 0.0 : rep.outages.front().length_s();
  if (rep.outages.empty()) rep.notes.push_back("no outage fits in the data with this schedule: ERR is NaN");
  const int n_jobs = static_cast<int>(jobs.size());
  const int parallel = std::max(1, std::min(n_jobs, o.jobs > 0 ? o.jobs : static_cast<int>(std::thread::hardware_concurrency())));
  log(fmt::format("[{}] navigating {} with {} ({} outages of {:.0f} s, {} in parallel)", tag,
                  n_jobs == 3 ? "SG1, SG2, REAL" : "SG1, SG2", o.estimator, rep.outages.size(),
                  rep.outage_length_s, parallel));
  std::vector<NavSolution> sols(jobs.size());
  for (int start = 0; start < n_jobs; start += parallel) {
    std::vector<std::future<NavSolution>> fut;
    for (int k = start; k < std::min(n_jobs, start + parallel); ++k) {
      fut.push_back(std::async(std::launch::async,
                               [&, k]() { return runEstimator(o.estimator, problems[k], rc); }));
    }
    for (int k = start; k < std::min(n_jobs, start + parallel); ++k) sols[k] = fut[k - start].get();
  }

  // 5. Errors against SOL_REF, reports, plots.
  for (int k = 0; k < n_jobs; ++k) {
    SgSolutionErrors e;
    e.label = jobs[k].label;
    e.imu_file = jobs[k].imu.path;
    e.evaluation = evaluateSolution(sols[k], sol_ref, rep.outages, rc.evaluation.options);
    writeErrorsCsv((fs::path(o.out_dir) / ("errors_" + e.label + ".csv")).string(), e.evaluation,
                   1.0 / rc.evaluation.csv_rate_hz);
    rep.solutions.push_back(std::move(e));
  }
  const fs::path out(o.out_dir);
  writeEvaluationJson((out / "evaluation.json").string(), rep);
  writeTablesMarkdown((out / "tables.md").string(), rep);
  writeEvaluationCsv((out / "evaluation.csv").string(), rep);
  writePerOutageCsv((out / "outage_drift.csv").string(), rep);
  if (o.plots) {
    const std::string w = runPythonScript("plot_sg.py", {o.out_dir});
    if (!w.empty()) log("warning: " + w);
  }
  return rep;
}

}  // namespace graftnav::app

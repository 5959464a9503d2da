#include "graftnav/case/sg_case_evaluation.h"

#include <fmt/core.h>
#include <fmt/format.h>

#include <algorithm>
#include <filesystem>
#include <memory>
#include <optional>
#include <stdexcept>
#include <utility>

#include "graftnav/calibration/calibration_io.h"
#include "graftnav/calibration/lab_data.h"
#include "graftnav/case/file_streams.h"
#include "graftnav/case/input_checks.h"
#include "graftnav/case/outage_overrides.h"
#include "graftnav/case/problem.h"
#include "graftnav/case/reference_solution.h"
#include "graftnav/eval/errors_csv.h"
#include "graftnav/io/imu_io.h"
#include "graftnav/io/imu_recording.h"
#include "graftnav/io/nav_io.h"

namespace graftnav {
namespace fs = std::filesystem;

namespace {

OutageOverrides outageOverrides(const SgCaseEvaluationOptions& o) {
  return {o.outage_length_s, o.outage_period_s, o.outage_start_s};
}

double imuBegin(const ImuSeries& imu) { return imu.front().t_s - imu.front().dt_s; }

// Whether the evaluation streams (nothing held that grows with the recording): the estimator and
// the smoother of a smoothed SOL_REF have streamed forms, and no problem needs the samples before
// its run (an alignment from the data reads them).
bool evaluationStreams(const SgCaseEvaluationOptions& o, const RunConfig& rc,
                       const EstimatorRegistry& estimators) {
  return estimators.canStream(o.estimator) && estimators.canStream("rts") &&
         rc.alignment.mode == AlignmentMode::kGiven;
}

// An IMU file read once in blocks: its errors (range, time order, intervals) stop the run as
// readImu's would. Returns its first and last samples.
ImuSeries scanImuSpan(const std::string& path, const ImuReadOptions& options) {
  ImuBlockReader reader(path, options);
  ImuSeries block, span;
  while (reader.next(&block)) {
    if (span.empty()) span = {block.front(), block.back()};
    span.back() = block.back();
  }
  return span;
}

// The case's reference file read once (its errors stop the run here), checked for coverage of
// the outages from counts.
std::vector<std::string> checkStreamedReference(const CaseInputs& c, const ImuSeries& imu_span,
                                                const std::vector<TimeWindow>& windows) {
  const CaseReferenceFile f = caseReferenceFile(c, false);
  if (f.path.empty()) return {};
  NavStreamReader reader(f.path, f.policy);
  ReferenceCoverage coverage(windows);
  NavState state;
  while (reader.next(&state)) coverage.add(state.t_s);
  return coverage.check(f.path, imu_span);
}

// What one evaluation runs with, handed to each of its steps.
struct Run {
  const SgCaseEvaluationOptions& o;
  const RunConfig& rc;
  const EstimatorRegistry& estimators;
  SgLogFn log;
  std::string tag;  // the case folder's name, in the log
};

SolutionReference solutionReference(const Run& run, const CaseInputs& c, const ImuSelection& ref) {
  ReferenceSolutionOptions ro;
  ro.use_case_reference = !run.o.always_smooth_sol_ref;
  if (!ro.use_case_reference || c.reference.empty())
    run.log(
        fmt::format("[{}] smoothing SOL_REF (rts) from the reference IMU and all GNSS", run.tag));
  ReferenceSolution r = resolveReferenceSolution(
      c, [&ref] { return ref; }, run.rc, run.estimators, ro);
  return {std::move(r.states), r.description};
}

}  // namespace

std::vector<std::string> checkSgCaseInputs(const SgCaseEvaluationOptions& o,
                                           const EstimatorRegistry& estimators) {
  std::vector<std::string> w;
  const auto add = [&](std::vector<std::string> more) {
    w.insert(w.end(), more.begin(), more.end());
  };
  if (!estimators.contains(o.estimator))
    throw std::runtime_error("estimator '" + o.estimator +
                             "': unknown (known: " + estimators.namesText() + ")");
  outageOverrides(o).validate();
  CaseLoadOptions lo;
  lo.load_reference = false;  // read as a stream below
  const CaseInputs c = loadCaseInputs(o.case_dir, lo);
  RunConfig rc;
  if (!o.run_config.empty()) rc = loadRunConfig(o.run_config, nullptr);
  requireTimeRangeUnset(rc.time_range, o.run_config, "graftnav evaluate");
  const OutageScheduleConfig oc = outageOverrides(o).appliedTo(rc.outages);
  ImuSelection ref = selectImu(c, "ref", "", false, false);
  ref.imu = scanImuSpan(ref.path, ref.read_options);
  if (CasePaths::exists(c.paths().testedImu())) {  // range checks of the tested file
    const ImuSelection tested = selectImu(c, "tested", "", false, false);
    scanImuSpan(tested.path, tested.read_options);
  }
  add(checkGnssCoverage(c.gnss, c.paths().gnssPos(), ref.imu, false));
  const double t0 = imuBegin(ref.imu), t1 = ref.imu.back().t_s;
  std::vector<TimeWindow> windows;
  try {
    windows = buildOutageWindows(oc, t0, t1);
  } catch (const std::invalid_argument& e) {
    throw std::runtime_error(std::string("outage schedule: ") + e.what());
  }
  requireOutagesInsideData(oc, windows, t0, t1);
  add(checkStreamedReference(c, ref.imu, windows));
  const std::string static_path = c.paths().labStatic();
  if (CasePaths::exists(static_path)) {
    ImuReadOptions ro;
    ro.nominal_rate_hz = c.config.testedImuRateHz();
    ro.policy = ImuReadPolicy::
        real();  // only the span and the range checks; loadLabData applies its own rules
    const ImuSeries st = scanImuSpan(static_path, ro);
    add(checkLabStaticRecord(st.back().t_s - imuBegin(st), static_path, outageSpacing(windows)));
  }
  return w;
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

SgEvaluationOptions sgPipelineOptions(const RunConfig& rc, std::optional<int> realizations,
                                      std::optional<int> outage_shifts, std::uint64_t seed,
                                      int jobs) {
  SgEvaluationOptions p;
  p.realizations = realizations.value_or(rc.grafting.realizations);
  p.outage_shifts = outage_shifts.value_or(rc.grafting.outage_shifts);
  p.seed = seed;
  p.start_offset_s = rc.grafting.start_offset_s;
  p.jobs = jobs;
  p.evaluation = rc.evaluation.options;
  return p;
}

SgEvaluationInputs sgPipelineInputs(const std::string& case_name, const CaseInputs& c,
                                    const OutageScheduleConfig& outages,
                                    const LabCalibrationReport& lab) {
  SgEvaluationInputs in;
  in.case_name = case_name;
  for (const auto& n : lab.notes) in.notes.push_back("calibration: " + n);
  in.tested_profile = *c.config.tested_imu;
  if (c.config.reference_imu && c.config.reference_imu_noise_given)
    in.reference_noise_profile = *c.config.reference_imu;
  in.outages = outages;
  return in;
}

SgNavigator heldCaseNavigator(const CaseInputs& c, const RunConfig& rc, const ImuSelection* real,
                              const EstimatorRegistry& estimators, const std::string& estimator) {
  return [&c, &rc, real, &estimators, estimator](std::optional<ImuSeries> grafted,
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
    nav.solution = estimators.run(estimator, pr, rc);
    nav.outages = pr.outages;
    return nav;
  };
}

namespace {

// Hands each epoch of a streamed estimator to the evaluation against SOL_REF.
class EpochForwardSink final : public SolutionSink {
 public:
  explicit EpochForwardSink(SgEpochFn epochs) : epochs_(std::move(epochs)) {}
  void add(const NavState& state, const PvaSigma* sigma, const ImuErrorEstimate&) override {
    epochs_(state, sigma);
  }

 private:
  SgEpochFn epochs_;
};

// The case's streamed navigator: makeProblem from the recording's span with the tested IMU's
// profile (REAL: the tested IMU's selection), then the estimator's streamed form over the
// recording, each epoch handed to the evaluation.
SgStreamNavigator streamedCaseNavigator(const CaseInputs& c, const RunConfig& rc,
                                        const std::optional<ImuSelection>& real,
                                        const EstimatorRegistry& estimators,
                                        const std::string& estimator) {
  return [&c, &rc, &real, &estimators, estimator](
             const SgImu& imu, const OutageScheduleConfig& schedule, const SgStartFn& start) {
    SgNavigation nav;
    ImuSelection sel =
        imu.strategy ? graftedSelection(imu.imu.span(), *c.config.tested_imu) : *real;
    sel.imu = imu.imu.span();
    EstimationProblem pr = makeProblem(c, sel, rc, schedule, &nav.notes);
    pr.imu = {};
    // One epoch per sample, unless the run config decimates (then the rate is left unknown).
    const double span_s = imu.imu.last.t_s - imu.imu.first.t_s;
    const double rate_hz = rc.ekf.output_decimation == 1 && imu.imu.samples > 1 && span_s > 0.0
                               ? static_cast<double>(imu.imu.samples - 1) / span_s
                               : 0.0;
    EpochForwardSink sink(start(pr.outages, rate_hz));
    const NavSolution book = estimators.runStreaming(estimator, pr, imu.imu.pass, rc, sink);
    nav.solution.copyBookkeeping(book);
    nav.outages = pr.outages;
    return nav;
  };
}

// The case's IMU files as spooled recordings (parsed once, read back by every navigation), and
// the head of its reference that makeProblem reads.
struct StreamedCase {
  ImuSelection ref;  // its span
  std::optional<ImuSelection> real;
  ImuRecording ref_recording;
  std::optional<ImuRecording> real_recording;
  CaseReferenceFile reference_file;
};

StreamedCase streamCase(CaseInputs* c) {
  StreamedCase s;
  s.ref = selectImu(*c, "ref", "", false, false);
  s.ref_recording = spooledRecording(imuFileStream(s.ref.path, s.ref.read_options));
  s.ref.imu = s.ref_recording.span();
  double t_head = s.ref_recording.beginTime_s();
  if (CasePaths::exists(c->paths().testedImu())) {
    s.real = selectImu(*c, "tested", "", false, false);
    s.real_recording = spooledRecording(imuFileStream(s.real->path, s.real->read_options));
    s.real->imu = s.real_recording->span();
    t_head = std::max(t_head, s.real_recording->beginTime_s());
  }
  s.reference_file = caseReferenceFile(*c, false);
  if (!s.reference_file.path.empty()) {
    c->reference = readReferenceHead(s.reference_file, t_head);
    c->reference_name = s.reference_file.path;
    c->reference_is_truth = s.reference_file.is_truth;
  }
  return s;
}

SolutionReference streamedSolutionReference(const Run& run, const CaseInputs& c,
                                            const StreamedCase& s) {
  ReferenceSolutionOptions ro;
  ro.use_case_reference = !run.o.always_smooth_sol_ref;
  if (!ro.use_case_reference || s.reference_file.path.empty())
    run.log(
        fmt::format("[{}] smoothing SOL_REF (rts) from the reference IMU and all GNSS", run.tag));
  const StreamedReferenceSolution r = streamReferenceSolution(
      c, s.reference_file, s.ref, s.ref_recording.pass, run.rc, run.estimators, ro);
  SolutionReference out;
  out.open = r.open;
  out.rate_hz = r.rate_hz;
  out.description = r.description;
  return out;
}

void writeGraftedImu(const std::string& path, const ImuRecording& grafted) {
  ImuWriter writer(path);
  grafted.pass([&writer](const ImuSeries& block) {
    for (const ImuSample& s : block) writer.add(s);
  });
  writer.commit();
}

// The pipeline with everything streamed: the IMU files spooled, SOL_REF spooled (or smoothed as
// a stream into a spool), each realization grafted block by block, every solution evaluated as
// it is written, the representative errors_<LABEL>.csv written as they come.
SgEvaluationReport runStreamed(const Run& run, CaseInputs* c, const SgEvaluationOptions& po,
                               const GraftPlan& plan, SgEvaluationInputs in) {
  const SgCaseEvaluationOptions& o = run.o;
  const StreamedCase s = streamCase(c);
  in.reference_recording = s.ref_recording;
  in.real_recording = s.real_recording;
  if (s.real) {
    in.has_real = true;
    in.real_imu_file = s.real->path;
  }
  const SgEvaluationPipeline pipeline(po, plan, std::move(in));
  const SolutionReference sol_ref = streamedSolutionReference(run, *c, s);
  for (SgStrategy g : po.strategies) {
    if (o.write_grafted_imu)
      writeGraftedImu((fs::path(o.out_dir) / (std::string("IMU_") + sgLabel(g) + ".txt")).string(),
                      pipeline.graftedRecording(g, 0));
  }
  SgRunHooks hooks;
  hooks.log = run.log;
  const double csv_interval_s = 1.0 / run.rc.evaluation.csv_rate_hz;
  const std::string out_dir = o.out_dir;
  hooks.epoch_sink = [out_dir, csv_interval_s](const std::string& label) {
    return std::make_unique<ErrorsCsvWriter>(
        (fs::path(out_dir) / ("errors_" + label + ".csv")).string(), csv_interval_s);
  };
  return pipeline.run(sol_ref,
                      streamedCaseNavigator(*c, run.rc, s.real, run.estimators, o.estimator),
                      o.estimator, hooks);
}

// The pipeline with the case's series held (an estimator without a streamed form, or an
// alignment from the data).
SgEvaluationReport runHeld(const Run& run, const CaseInputs& c, const SgEvaluationOptions& po,
                           const GraftPlan& plan, SgEvaluationInputs in) {
  const SgCaseEvaluationOptions& o = run.o;
  const ImuSelection ref = selectImu(c, "ref");
  in.reference_imu = ref.imu;
  std::optional<ImuSelection> real;
  if (CasePaths::exists(c.paths().testedImu())) {
    real = selectImu(c, "tested");
    in.has_real = true;
    in.real_imu_file = real->path;
  }
  const SgEvaluationPipeline pipeline(po, plan, std::move(in));
  const SolutionReference sol_ref = solutionReference(run, c, ref);
  for (SgStrategy g : po.strategies) {
    if (o.write_grafted_imu)
      writeImu((fs::path(o.out_dir) / (std::string("IMU_") + sgLabel(g) + ".txt")).string(),
               pipeline.graft(g, 0));
  }
  return pipeline.run(
      sol_ref, heldCaseNavigator(c, run.rc, real ? &*real : nullptr, run.estimators, o.estimator),
      o.estimator, run.log);
}

}  // namespace

SgCaseEvaluation runSgCaseEvaluation(const SgCaseEvaluationOptions& o,
                                     const EstimatorRegistry& estimators, const SgLogFn& log_in) {
  const SgLogFn log = log_in ? log_in : [](const std::string&) {};
  for (const auto& w : checkSgCaseInputs(o, estimators)) log("warning: " + w);  // before output
  std::vector<std::string> cw;
  RunConfig rc;
  if (!o.run_config.empty()) rc = loadRunConfig(o.run_config, &cw);
  const Run run{o, rc, estimators, log, fs::path(o.case_dir).filename().string()};
  const bool streams = evaluationStreams(o, rc, estimators);
  CaseLoadOptions lo;
  lo.load_reference = !streams;
  CaseInputs c = loadCaseInputs(o.case_dir, lo);
  for (const auto& w : c.warnings) log("warning: " + w);
  for (const auto& w : cw) log("warning: " + w);
  requireTestedNoise(c);
  const SgEvaluationOptions po =
      sgPipelineOptions(rc, o.realizations, o.outage_shifts, o.seed, o.jobs);
  po.validate();
  log(fmt::format("[{}] calibrating the tested IMU from lab/", run.tag));
  LabCalibrationReport lab = calibrateLab(loadLabData(o.case_dir));
  const GraftPlan plan = makeGraftPlan(lab, o.use_cross_axis);
  lab.basic.error = ImuSeries();  // the plan holds the basic error signal
  SgEvaluationInputs in =
      sgPipelineInputs(o.case_dir, c, outageOverrides(o).appliedTo(rc.outages), lab);

  // From here on files are written.
  fs::create_directories(o.out_dir);
  writeCalibrationYaml((fs::path(o.out_dir) / "calibration.yaml").string(), lab.result);
  SgCaseEvaluation out;
  out.report = streams ? runStreamed(run, &c, po, plan, std::move(in))
                       : runHeld(run, c, po, plan, std::move(in));
  out.errors_csv_written = streams;
  for (auto& s : out.report.solutions)
    if (s.label != "REAL")
      s.imu_file = (fs::path(o.out_dir) / ("IMU_" + s.label + ".txt")).string();
  out.report.case_name = c.config.name;
  out.report.tested_grade = c.config.tested_imu->grade;
  out.report.csv_rate_hz = rc.evaluation.csv_rate_hz;
  return out;
}

}  // namespace graftnav

#include "graftnav/navigate/compare_run.h"

#include <algorithm>
#include <chrono>
#include <memory>
#include <stdexcept>
#include <utility>

#include "graftnav/case/file_streams.h"
#include "graftnav/case/input_checks.h"
#include "graftnav/case/problem.h"
#include "graftnav/eval/solution_spool.h"
#include "graftnav/eval/streamed_evaluation.h"
#include "graftnav/io/nav_io.h"
#include "graftnav/io/provenance.h"
#include "graftnav/eval/spooled_comparison.h"
#include "graftnav/navigate/streamed_imu_file.h"
#include "graftnav/navigate/streamed_problem.h"

namespace graftnav {
namespace {

const char kNoEarth[] = "-noearth";

// One estimator of compare: its registry entry, and whether Earth rotation is switched off.
struct CompareEstimator {
  std::string name;
  const EstimatorEntry* entry = nullptr;
  bool no_earth = false;
};

// A registry name, or "<name>-noearth" for an estimator whose Earth rotation is optional
// (EstimatorEntry::earth_rotation_optional: the factor graphs).
CompareEstimator compareEstimator(const std::string& name, const EstimatorRegistry& registry) {
  CompareEstimator e{name, nullptr, false};
  const std::string suffix = kNoEarth;
  std::string base = name;
  if (!registry.contains(name) && name.size() > suffix.size() &&
      name.compare(name.size() - suffix.size(), suffix.size(), suffix) == 0) {
    base = name.substr(0, name.size() - suffix.size());
    e.no_earth = registry.contains(base) && registry.find(base).earth_rotation_optional;
    if (!e.no_earth) base = name;
  }
  if (!registry.contains(base))
    throw std::runtime_error("--estimator: unknown estimator '" + name +
                             "' (known: " + compareEstimatorNamesText(registry) + ")");
  e.entry = &registry.find(base);
  return e;
}

// The reference read once (its errors stop the run, its coverage is checked from counts); each
// estimator's evaluation reads it again as a stream.
void scanReference(const CompareInputs& in, const RunMessages& messages) {
  NavStreamReader reader(in.reference.path, in.reference.policy);
  ReferenceCoverage coverage(in.p.outages);
  NavState state;
  while (reader.next(&state)) coverage.add(state.t_s);
  if (!in.reference.is_truth && !reader.report().summary().empty())
    messages.warning(reader.report().summary());
  for (const auto& w : coverage.check(in.reference.path, in.p.imu)) messages.warning(w);
}

// The IMU: held and cut to the time range with the GNSS, or scanned once for its errors and the
// span the range keeps when every run streams it (the GNSS held and cut as navigate cuts it).
void selectCompareImu(const CompareRequest& q, const RunMessages& messages, CompareInputs* in,
                      std::vector<std::string>* notes) {
  in->imu = selectImu(in->c, q.imu, q.profile_path, q.lenient, !in->stream);
  if (in->stream) {
    const ImuFileScan scan = scanImuFile(&in->imu, in->time_range);
    in->imu.imu = scan.span;
    in->imu_samples = scan.kept;
    if (!in->time_range.empty())
      notes->push_back(keepHeldGnssInRange(in->time_range, scan, &in->c.gnss));
  } else {
    restrictToTimeRange(in->time_range, &in->c, &in->imu, notes);
    in->imu_samples = static_cast<long>(in->imu.imu.size());
  }
  if (!in->imu.read_summary.empty()) messages.warning(in->imu.read_summary);
  if (!in->imu.profile_given) {
    throw std::runtime_error("no noise parameters for IMU '" + q.imu +
                             "' in case.yaml: pass --profile FILE");
  }
}

// Streams the epochs of a run into its spool and its evaluation.
class CompareSink final : public SolutionSink {
 public:
  CompareSink(SolutionSpool* spool, StreamedEvaluation* evaluation)
      : spool_(spool), evaluation_(evaluation) {}
  void add(const NavState& state, const PvaSigma* sigma, const ImuErrorEstimate&) override {
    spool_->add(state, sigma);
    evaluation_->add(state, sigma);
  }

 private:
  SolutionSpool* spool_;
  StreamedEvaluation* evaluation_;
};

// One estimator: streamed (or in memory) into its spool, evaluated against the reference as it
// comes. `grid`: the first row's 1 Hz series (null for the first row).
CompareRow runOne(const CompareEstimator& e, const CompareInputs& in,
                  const EstimatorRegistry& registry, const std::vector<EpochError>* grid,
                  SolutionSpool* spool) {
  RunConfig cfg = in.cfg;
  if (e.no_earth) cfg.fgo.earth_rotation = false;
  CompareRow r;
  r.name = e.name;
  StreamedEvaluation ev(navFileSource(in.reference.path, in.reference.policy)(), in.p.outages,
                        EvaluationOptions{}, e.name, ExpectedRates{},
                        [&]() { return std::make_unique<CompareSeriesSink>(grid, &r.series); });
  const auto t0 = std::chrono::steady_clock::now();
  NavSolution book;
  if (in.stream) {
    CompareSink sink(spool, &ev);
    book = registry.runStreaming(e.entry->name, in.p, imuRangeStream(in.imu, in.time_range), cfg,
                                 sink);
  } else {
    book = registry.run(e.entry->name, in.p, cfg);
    const bool has_sigma = book.sigma.size() == book.states.size();
    for (std::size_t k = 0; k < book.states.size(); ++k) {
      spool->add(book.states[k], has_sigma ? &book.sigma[k] : nullptr);
      ev.add(book.states[k], has_sigma ? &book.sigma[k] : nullptr);
    }
  }
  spool->finish();
  checkGnssUsed(book.gnss_used, false);  // throws before any file is written
  r.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  r.eval = ev.finish();
  ev.commitEpochs();
  r.gnss_rejected = book.gnss_rejected;
  return r;
}

// a against b inside the outages; the cross-check takes the filter-smoother form when one of the
// two smooths the other's filter (the registry's EstimatorEntry::smooths).
ComparePair comparePair(const CompareEstimator& a, const SolutionSpool& sa,
                        const CompareEstimator& b, const SolutionSpool& sb,
                        const std::vector<TimeWindow>& outages) {
  const Evaluation e = evaluatePair(sa, sb, outages);
  ComparePair q{a.name, b.name, e.outage_rms, e.outage_max_rms, {}};
  const auto smooths = [](const CompareEstimator& s, const CompareEstimator& f) {
    return !s.no_earth && !f.no_earth && !s.entry->smooths.empty() &&
           s.entry->smooths == f.entry->name;
  };
  if (smooths(b, a)) {
    q.cross = crossCheck(sa, sb, outages, DifferenceCovariance::kFilterSmoother);
  } else if (smooths(a, b)) {
    q.cross = crossCheck(sb, sa, outages, DifferenceCovariance::kFilterSmoother);
  } else {
    q.cross = crossCheck(sa, sb, outages, DifferenceCovariance::kIndependent);
  }
  return q;
}

}  // namespace

std::string compareEstimatorNamesText(const EstimatorRegistry& registry) {
  std::string text = registry.namesText();
  for (const EstimatorEntry& e : registry.entries())
    if (e.earth_rotation_optional) text += ", " + e.name + kNoEarth;
  return text;
}

CompareInputs loadCompareInputs(const CompareRequest& q, const EstimatorRegistry& registry,
                                const RunMessages& messages) {
  if (q.estimators.empty()) throw std::invalid_argument("compare: --estimator is empty");
  bool all_stream = true;
  for (const auto& n : q.estimators)
    all_stream = all_stream && compareEstimator(n, registry).entry->stream != nullptr;
  CompareInputs in;
  if (!q.run_config.empty()) {
    std::vector<std::string> warnings;
    in.cfg = loadRunConfig(q.run_config, &warnings);
    recordConfigFile(q.run_config);
    for (const auto& w : warnings) messages.warning(w);
  }
  in.time_range = mergeTimeRange(in.cfg.time_range, q.time_range);
  // makeProblem sees the samples the alignment reads (streamed_problem.h).
  in.stream = all_stream;
  CaseLoadOptions lo;
  lo.lenient = q.lenient;
  lo.load_reference = false;
  in.c = loadCaseInputs(q.case_dir, lo);
  in.reference = caseReferenceFile(in.c, q.lenient);
  in.c.reference_name = in.reference.path;
  in.c.reference_is_truth = in.reference.is_truth;
  for (const auto& w : in.c.warnings) messages.warning(w);
  if (in.reference.path.empty())
    throw std::runtime_error(q.case_dir + ": compare needs truth.nav or a reference");
  in.schedule = q.outage.appliedTo(in.cfg.outages);
  in.schedule.enabled = in.schedule.enabled && !q.no_outages;
  std::vector<std::string> notes;
  selectCompareImu(q, messages, &in, &notes);
  const ImuSeries& imu = in.imu.imu;
  for (const auto& w : checkGnssCoverage(in.c.gnss, in.c.paths().gnssPos(), imu, false))
    messages.warning(w);
  // makeProblem reads the reference's first epochs only (the week, the initial state).
  in.c.reference = readReferenceHead(in.reference, imu.front().t_s - imu.front().dt_s);
  in.p = in.stream ? makeStreamedProblem(in.c, in.imu, in.cfg, in.schedule, in.time_range, &notes)
                   : makeProblem(in.c, in.imu, in.cfg, in.schedule, &notes);
  in.c.reference = NavSeries();
  for (const auto& n : notes) messages.note(n);
  const EstimationProblem& p = in.p;
  requireOutagesInsideData(in.schedule, p.outages, p.imu.front().t_s - p.imu.front().dt_s,
                           p.imu.back().t_s);
  scanReference(in, messages);
  if (in.stream) {  // the checks above needed only the span; each run reads the file in blocks
    in.p.imu = ImuSeries();
    in.imu.imu = ImuSeries();
  }
  return in;
}

CompareReport runCompare(const CompareRequest& q, const CompareInputs& in,
                         const EstimatorRegistry& registry,
                         const std::function<void(const CompareRow&)>& on_row) {
  CompareReport report;
  report.case_dir = q.case_dir;
  report.imu = q.imu;
  report.imu_profile_name = in.p.imu_profile.name;
  report.reference_name = in.c.reference_name;
  report.schedule = in.schedule;
  report.outages = in.p.outages;
  std::vector<CompareEstimator> estimators;
  for (const auto& n : q.estimators) estimators.push_back(compareEstimator(n, registry));
  std::vector<std::unique_ptr<SolutionSpool>> spools;
  report.rows.reserve(estimators.size());
  for (const CompareEstimator& e : estimators) {
    const std::vector<EpochError>* grid = report.rows.empty() ? nullptr : &report.rows[0].series;
    spools.push_back(std::make_unique<SolutionSpool>(q.spool_dir));
    report.rows.push_back(runOne(e, in, registry, grid, spools.back().get()));
    if (on_row) on_row(report.rows.back());
  }
  for (std::size_t i = 0; i < estimators.size(); ++i)
    for (std::size_t j = i + 1; j < estimators.size(); ++j)
      report.pairs.push_back(
          comparePair(estimators[i], *spools[i], estimators[j], *spools[j], in.p.outages));
  return report;
}

}  // namespace graftnav

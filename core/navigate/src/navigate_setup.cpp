#include "graftnav/navigate/navigate_setup.h"

#include <optional>
#include <stdexcept>
#include <utility>

#include "graftnav/case/file_streams.h"
#include "graftnav/case/input_checks.h"
#include "graftnav/case/problem.h"
#include "graftnav/io/gnss_io.h"
#include "graftnav/io/imu_io.h"
#include "graftnav/io/nav_io.h"
#include "graftnav/io/provenance.h"
#include "graftnav/navigate/streamed_imu_file.h"
#include "graftnav/navigate/streamed_problem.h"

namespace graftnav {
namespace {

// Prints the warnings and keeps them in the run's notes (run_info.json).
void warnAll(const std::vector<std::string>& warnings, const RunMessages& messages,
             std::vector<std::string>* notes) {
  for (const auto& w : warnings) {
    messages.warning(w);
    notes->push_back(w);
  }
}

// Whether the run streams the IMU (read in blocks, the per-epoch files written as they go): when
// the estimator has a streamed form. makeProblem sees the samples its alignment reads
// (streamed_problem.h); a time range is kept as the files are read (streamed_imu_file.h).
bool streamable(const EstimatorRegistry& registry, const std::string& estimator) {
  return registry.canStream(estimator);
}

// The note of a streamed run's time range, where restrictToTimeRange would have put it, once the
// GNSS epochs are counted.
void noteTimeRange(long gnss_kept, long gnss_total, NavigateSetup* s) {
  if (!s->stream || s->time_range.empty()) return;
  const auto at = s->notes.begin() + static_cast<std::ptrdiff_t>(s->time_range_note_at);
  s->notes.insert(at, timeRangeNote(s->imu_scan.span, s->imu_scan.kept, s->imu_scan.total,
                                    gnss_kept, gnss_total));
}

// The case's GNSS read once epoch by epoch before anything is written, as scanImuFile reads
// the IMU: its errors stop the run here, its warnings are given, the coverage check gets the
// counts. Memory stays flat; the run reads the files again through *stream. Returns the first
// epoch, which stands in for the series in makeProblem (it asks only whether there is GNSS).
GnssFix scanStreamedGnss(const NavigateRequest& q, const RunMessages& messages, NavigateSetup* s,
                         GnssOpenFn* stream) {
  const CasePaths paths = s->c.paths();
  if (!CasePaths::exists(paths.gnssPos()))
    throw std::runtime_error("GNSS file '" + paths.gnssPos() + "' not found");
  const std::string ft = CasePaths::exists(paths.gnssFixType()) ? paths.gnssFixType() : "";
  const GnssReadPolicy policy = q.lenient ? GnssReadPolicy::real() : GnssReadPolicy{};
  GnssStreamReader reader(paths.gnssPos(), ft, policy);
  GnssCoverage coverage;
  coverage.imu_t0_s = s->imu.imu.front().t_s - s->imu.imu.front().dt_s;
  coverage.imu_t1_s = s->imu.imu.back().t_s;
  GnssFix fix, first;
  long total = 0;
  while (reader.next(&fix)) {
    ++total;
    if (!s->time_range.keepsGnssEpoch(fix.t_s)) continue;
    if (coverage.total == 0) first = fix;
    coverage.add(fix.t_s);
  }
  for (const auto& r : reader.reports())
    if (!r.summary().empty()) messages.warning(r.summary());
  warnAll(checkGnssCoverage(coverage, paths.gnssPos(), false), messages, &s->notes);
  s->gnss_count = coverage.total;
  noteTimeRange(coverage.total, total, s);
  *stream = gnssRangeStream(gnssFileStream(paths.gnssPos(), ft, policy), s->time_range);
  return first;
}

// The IMU and its profile, read in memory and cut to the time range, or scanned for a streamed
// run.
void selectNavigateImu(const NavigateRequest& q, const EstimatorRegistry& registry,
                       const RunMessages& messages, NavigateSetup* s) {
  if (!q.profile_path.empty()) recordConfigFile(q.profile_path);
  s->stream = streamable(registry, s->estimator);
  s->imu = selectImu(s->c, q.imu, q.profile_path, q.lenient, !s->stream);
  if (s->stream) {
    s->imu_scan = scanImuFile(&s->imu, s->time_range);
    s->imu.imu = s->imu_scan.span;
    s->time_range_note_at = s->notes.size();
    // The solution has an epoch per IMU sample (with a decimation the rate is left unknown: both
    // epoch sets are evaluated until the run ends).
    const long count = s->imu_scan.kept;
    const double span_s = s->imu.imu.back().t_s - s->imu.imu.front().t_s;
    if (count > 1 && span_s > 0.0 && s->rc.ekf.output_decimation == 1)
      s->expected_rates.solution_hz = static_cast<double>(count - 1) / span_s;
  } else {
    restrictToTimeRange(s->time_range, &s->c, &s->imu, &s->notes);
  }
  if (!s->imu.read_summary.empty()) warnAll({s->imu.read_summary}, messages, &s->notes);
  if (s->uses_gnss && !s->imu.profile_given) {
    throw std::runtime_error("no noise parameters for IMU '" + q.imu +
                             "' in case.yaml: pass --profile FILE (configs/imu/*.yaml)");
  }
}

// A streamed run's reference read once before anything is written, as scanImuFile reads the
// IMU: its errors stop the run here, its repairs are given, the coverage of the outages is
// checked from counts, and its rate chooses the evaluation epochs (kAuto) before the run.
void scanStreamedReference(const RunMessages& messages, NavigateSetup* s) {
  const CaseReferenceFile& f = s->streamed_reference;
  NavStreamReader reader(f.path, f.policy);
  ReferenceCoverage coverage(s->pr.outages);
  NavState state;
  while (reader.next(&state)) coverage.add(state.t_s);
  if (!f.is_truth && !reader.report().summary().empty())
    messages.warning(reader.report().summary());
  warnAll(coverage.check(f.path, s->pr.imu), messages, &s->notes);
  s->expected_rates.reference_hz = coverage.rateHz();
}

// The case (without the series a streamed run reads later) and the run config's warnings.
void loadCase(const NavigateRequest& q, const EstimatorRegistry& registry,
              const RunMessages& messages, NavigateSetup* s) {
  std::vector<std::string> config_warnings;
  if (!q.run_config.empty()) s->rc = loadRunConfig(q.run_config, &config_warnings);
  s->time_range = mergeTimeRange(s->rc.time_range, q.time_range);
  const bool stream = streamable(registry, s->estimator);
  // Unless the run config selects GNSS epochs (selectGnss re-sorts and spaces the whole series)
  // or an in-motion alignment reads them.
  s->stream_gnss =
      s->uses_gnss && stream && !s->rc.gnss.given && s->rc.alignment.mode != AlignmentMode::kMotion;
  CaseLoadOptions lo;
  lo.load_gnss = s->uses_gnss && !s->stream_gnss;
  lo.lenient = q.lenient;
  // A streamed run reads its reference as it evaluates (scanStreamedReference), never whole.
  lo.load_reference = !stream;
  s->c = loadCaseInputs(q.case_dir, lo);
  if (stream) {
    s->streamed_reference = caseReferenceFile(s->c, q.lenient);
    s->c.reference_name = s->streamed_reference.path;
    s->c.reference_is_truth = s->streamed_reference.is_truth;
  }
  recordConfigFile(s->c.paths().caseYaml());
  std::vector<std::string> warnings = s->c.warnings;
  warnings.insert(warnings.end(), config_warnings.begin(), config_warnings.end());
  if (!q.run_config.empty()) {
    recordConfigFile(q.run_config);
    s->notes.push_back("run config: " + q.run_config);
    if (q.run_config_from_case) messages.note("using the case's run config " + q.run_config);
  }
  for (const auto& w : warnings) messages.warning(w);
}

// A streamed run's GNSS held (a gnss: section selects epochs, or none is read): the epochs the
// time range keeps, as restrictToTimeRange keeps them.
void keepGnssInRange(NavigateSetup* s) {
  if (!s->stream || s->time_range.empty()) return;
  const auto at = s->notes.begin() + static_cast<std::ptrdiff_t>(s->time_range_note_at);
  s->notes.insert(at, keepHeldGnssInRange(s->time_range, s->imu_scan, &s->c.gnss));
}

// The notes of makeProblem a user should see (alignment, lever arm, GNSS selection, time range,
// odometer).
void noteProblem(const std::vector<std::string>& notes, const RunMessages& messages) {
  for (const auto& n : notes)
    if (n.find("alignment") != std::string::npos || n.find("lever") != std::string::npos ||
        n.find("GNSS selection") != std::string::npos ||
        n.find("time range") != std::string::npos || n.find("odometer") != std::string::npos)
      messages.note(n);
}

}  // namespace

NavigateSetup prepareNavigate(const NavigateRequest& q, const EstimatorRegistry& registry,
                              const RunMessages& messages) {
  q.outage.validate();
  if (!registry.contains(q.estimator))
    throw std::runtime_error("--estimator '" + q.estimator + "': unknown estimator");
  NavigateSetup s;
  s.estimator = q.estimator;
  s.uses_gnss = registry.find(q.estimator).uses_gnss;
  loadCase(q, registry, messages, &s);  // the run config first: whether the GNSS is held
  s.rc.ekf.output_decimation = q.decimate;
  if (!s.uses_gnss) s.rc.alignment.mode = AlignmentMode::kGiven;

  selectNavigateImu(q, registry, messages, &s);
  GnssOpenFn gnss_stream;
  if (s.stream_gnss) {
    s.c.gnss = {scanStreamedGnss(q, messages, &s, &gnss_stream)};
  } else {
    keepGnssInRange(&s);
  }
  if (!s.stream_gnss && s.uses_gnss) {
    warnAll(checkGnssCoverage(s.c.gnss, s.c.paths().gnssPos(), s.imu.imu, false), messages,
            &s.notes);
  }

  // Outages: config section, overridden by the command line; none for a free-inertial run.
  s.oc = q.outage.appliedTo(s.rc.outages);
  std::optional<OutageScheduleConfig> outages;
  if ((s.rc.outages_given || q.outage.any()) && s.uses_gnss) outages = s.oc;
  if (!s.streamed_reference.path.empty())  // what makeProblem reads of the reference
    s.c.reference =
        readReferenceHead(s.streamed_reference, s.imu.imu.front().t_s - s.imu.imu.front().dt_s);
  s.pr = s.stream ? makeStreamedProblem(s.c, s.imu, s.rc, outages, s.time_range, &s.notes)
                  : makeProblem(s.c, s.imu, s.rc, outages, &s.notes);
  if (!s.streamed_reference.path.empty()) s.c.reference = NavSeries();
  if (s.stream_gnss) {  // makeProblem saw the first epoch only; the run reads the files
    s.pr.gnss = GnssSeries();
    s.c.gnss = GnssSeries();
    s.pr.gnss_stream = gnss_stream;
  } else {
    s.gnss_count = static_cast<long>(s.pr.gnss.size());
    if (s.stream) s.c.gnss = GnssSeries();  // a streamed run holds the problem's fixes only
  }
  noteProblem(s.notes, messages);
  if (outages) {
    const double t0 = s.pr.imu.front().t_s - s.pr.imu.front().dt_s;
    requireOutagesInsideData(*outages, s.pr.outages, t0, s.pr.imu.back().t_s);
  }
  if (!s.streamed_reference.path.empty()) {
    scanStreamedReference(messages, &s);
  } else {
    warnAll(checkReferenceCoverage(s.c.reference, s.c.reference_name, s.pr.imu, s.pr.outages),
            messages, &s.notes);
  }
  if (s.stream) {  // the checks above needed only the span; the run reads the file in blocks
    s.pr.imu = ImuSeries();
    s.imu.imu = ImuSeries();
  }
  return s;
}

}  // namespace graftnav

#include "graftnav/navigate/real_setup.h"

#include <fmt/core.h>

#include <cmath>
#include <memory>
#include <stdexcept>

#include "graftnav/case/file_streams.h"
#include "graftnav/case/input_checks.h"
#include "graftnav/case/problem.h"
#include "graftnav/eval/gnss_selection.h"
#include "graftnav/io/gnss_io.h"
#include "graftnav/io/imu_io.h"
#include "graftnav/io/nav_io.h"
#include "graftnav/io/provenance.h"
#include "graftnav/nav/rotation.h"
#include "graftnav/navigate/streamed_imu_file.h"
#include "graftnav/navigate/streamed_problem.h"

namespace graftnav {
namespace {

// Each line of `text` as a note after `prefix`.
void noteLines(const std::string& prefix, const std::string& text, const RunMessages& messages) {
  std::size_t a = 0;
  while (a < text.size()) {
    std::size_t b = text.find('\n', a);
    if (b == std::string::npos) b = text.size();
    messages.note(prefix + text.substr(a, b - a));
    a = b + 1;
  }
}

// The fixes of a GNSS pass after t_s: startAtInitialState's cut of a held series, as the file is
// read.
class GnssAfter final : public GnssSource {
 public:
  GnssAfter(std::unique_ptr<GnssSource> fixes, double t_s) : fixes_(std::move(fixes)), t_s_(t_s) {}
  bool next(GnssFix* fix) override {
    while (fixes_->next(fix)) {
      if (started_ || fix->t_s > t_s_) {
        started_ = true;
        return true;
      }
    }
    return false;
  }

 private:
  std::unique_ptr<GnssSource> fixes_;
  double t_s_;
  bool started_ = false;
};

// The case's GNSS file, when the run reads it as it goes.
struct GnssFile {
  std::string pos_path, fixtype_path;
  explicit GnssFile(const CaseInputs& c) {
    const CasePaths paths = c.paths();
    if (!CasePaths::exists(paths.gnssPos()))
      throw std::runtime_error("GNSS file '" + paths.gnssPos() + "' not found");
    pos_path = paths.gnssPos();
    if (CasePaths::exists(paths.gnssFixType())) fixtype_path = paths.gnssFixType();
  }
  // The fixes the range keeps.
  GnssOpenFn stream(const TimeRangeConfig& range) const {
    return gnssRangeStream(gnssFileStream(pos_path, fixtype_path, GnssReadPolicy::real()), range);
  }
};

// Every estimator has a streamed form, no in-motion alignment (it may read the whole IMU) and no
// latency study needs the series. A static alignment reads only its window (alignmentPrefix,
// streamed_imu_file.h).
bool streamable(const RealRequest& q, const EstimatorRegistry& registry) {
  if (q.latency_study) return false;
  for (const auto& name : q.estimators)
    if (!registry.contains(name) || !registry.canStream(name)) return false;
  return true;
}

// The note on the heading of a data alignment against case.yaml's (a warning beyond 5 degrees).
void noteAlignedHeading(const CaseInputs& c, const RunConfig& rc, const EstimationProblem& pr,
                        const RunMessages& messages) {
  if (rc.alignment.mode != AlignmentMode::kStatic || !c.config.initial_state) return;
  const double yaw_case = eulerFromQuat(c.config.initial_state->q_nb).z() * kRadToDeg;
  const double yaw_used = eulerFromQuat(pr.initial.q_nb).z() * kRadToDeg;
  const double d = std::remainder(yaw_used - yaw_case, 360.0);
  messages.note(fmt::format(
      "  {}: {} alignment from the data: yaw {:.1f} deg at t={:.3f} (case.yaml initial_state: "
      "{:.1f} deg at t={:.3f}; difference {:.1f} deg{})",
      std::abs(d) > 5.0 ? "WARNING" : "note", alignmentModeName(rc.alignment.mode), yaw_used,
      pr.initial.t_s, yaw_case, c.config.initial_state->t_s, d,
      std::abs(d) > 5.0 ? ": the case's initial heading is NOT used" : ""));
}

// The reference solution read once: its errors stop the run here, its repairs are given, and its
// epoch count and rate are known before any estimator runs.
void scanRealReference(const RunMessages& messages, RealInputs* in) {
  NavStreamReader reader(in->reference.path, in->reference.policy);
  ReferenceCoverage coverage(in->pr.outages);
  NavState state;
  while (reader.next(&state)) coverage.add(state.t_s);
  in->reference_epochs = coverage.count();
  in->expected_rates.reference_hz = coverage.rateHz();
  messages.note(fmt::format("  reference {}: {} epochs, read as each estimator runs",
                            in->reference.path, in->reference_epochs));
  if (!in->reference.is_truth && !reader.report().summary().empty())
    noteLines("  reader/case: ", reader.report().summary(), messages);
}

// Whether each run reads the GNSS file: a streamed run without a gnss: section (which selects
// epochs over the whole series) and without an in-motion alignment (which reads the fixes).
bool streamsGnss(const RealInputs& in) {
  return in.stream && !in.rc.gnss.given && in.rc.alignment.mode != AlignmentMode::kMotion;
}

// What a streamed run holds of the problem: the IMU's span is dropped (each run reads the file
// from imu_start_s), and without a gnss: section so are the GNSS fixes (each run reads the file).
void releaseStreamedSeries(const RunMessages& messages, RealInputs* in) {
  EstimationProblem& pr = in->pr;
  const double t_init = pr.initial.t_s;
  // startAtInitialState's rule on the samples (when some sample starts at or after t_init).
  const auto starts_before = [&](const ImuSample& s) { return s.t_s - s.dt_s < t_init - 1e-6; };
  if (starts_before(pr.imu.front()) && !starts_before(pr.imu.back())) {
    in->imu_start_s = t_init - 1e-6;
    messages.note(
        fmt::format("  note: IMU samples before the initial state epoch t={:.3f} are "
                    "skipped as the file is read (used only by the alignment)",
                    t_init));
  }
  pr.imu = ImuSeries();
  in->imu.imu = ImuSeries();
  if (!streamsGnss(*in)) return;
  const GnssOpenFn file = GnssFile(in->c).stream(in->time_range);
  pr.gnss_stream = [file, t_init]() -> std::unique_ptr<GnssSource> {
    return std::make_unique<GnssAfter>(file(), t_init + 1e-6);
  };
  pr.gnss = GnssSeries();
  in->c.gnss = GnssSeries();
}

// The check points of gnss.checkpoint_fix_types among `fixes` and how many lie inside the
// outages; a streamed run keeps only those.
void selectCheckpoints(const GnssSeries& fixes, RealInputs* in) {
  const GnssSeries all =
      gnssOfFixTypes(fixes, in->rc.gnss.checkpoint_fix_types, in->rc.gnss.selection);
  in->checkpoint_epochs = static_cast<long>(all.size());
  for (const auto& f : all) {
    bool inside = false;
    for (const auto& w : in->pr.outages) {
      in->checkpoints_in_outages += w.contains(f.t_s) ? 1 : 0;
      inside = inside || w.contains(f.t_s);
    }
    if (!in->stream || inside) in->checkpoints.push_back(f);
  }
}

// Without a gnss: section the check points are every fix (no selection but the time order), so
// those inside the outages are the check points of the fixes inside the outages: the file is
// read once for them (and its errors and repairs), never held whole.
void selectStreamedCheckpoints(const RunMessages& messages, RealInputs* in) {
  const GnssFile file(in->c);
  GnssStreamReader reader(file.pos_path, file.fixtype_path, GnssReadPolicy::real());
  GnssSeries inside;
  GnssFix fix;
  long count = 0, total = 0;
  while (reader.next(&fix)) {
    ++total;
    if (!in->time_range.keepsGnssEpoch(fix.t_s)) continue;
    ++count;
    for (const auto& w : in->pr.outages)
      if (w.contains(fix.t_s)) {
        inside.push_back(fix);
        break;
      }
  }
  for (const auto& r : reader.reports())
    if (!r.summary().empty()) noteLines("  reader/case: ", r.summary(), messages);
  if (!in->time_range.empty()) {
    const ImuFileScan& scan = in->imu_scan;
    messages.note("  note: " + timeRangeNote(scan.span, scan.kept, scan.total, count, total));
  }
  selectCheckpoints(inside, in);
  in->checkpoint_epochs = count;
  messages.note(
      fmt::format("  GNSS {}: {} epochs, read as each estimator runs", file.pos_path, count));
}

// The first fix of the GNSS file the range keeps: what makeProblem reads of a GNSS series it does
// not select.
GnssSeries firstGnssFix(const CaseInputs& c, const TimeRangeConfig& range) {
  const auto pass = GnssFile(c).stream(range)();
  GnssFix fix;
  return pass->next(&fix) ? GnssSeries{fix} : GnssSeries{};
}

// makeRealProblem; imu_held false: `imu` is the first and last samples of a file each run reads,
// makeProblem sees the samples its alignment reads (streamed_problem.h), and startAtInitialState
// cuts only the GNSS (the samples are skipped as they are read). `range`: what the streamed
// problem reads of the file (a held series is cut before).
EstimationProblem realProblem(const CaseInputs& c, const ImuSelection& imu, const RunConfig& rc,
                              const std::optional<OutageScheduleConfig>& outages, bool imu_held,
                              const TimeRangeConfig& range, const RunMessages& messages,
                              std::vector<std::string>* notes_out) {
  std::vector<std::string> notes;
  EstimationProblem pr = imu_held ? makeProblem(c, imu, rc, outages, &notes)
                                  : makeStreamedProblem(c, imu, rc, outages, range, &notes);
  ImuSeries span;
  if (!imu_held) std::swap(span, pr.imu);
  startAtInitialState(&pr, &notes);
  if (!imu_held) std::swap(span, pr.imu);
  for (const auto& n : notes) messages.note("  note: " + n);
  noteAlignedHeading(c, rc, pr, messages);
  if (notes_out) notes_out->insert(notes_out->end(), notes.begin(), notes.end());
  return pr;
}

}  // namespace

CaseInputs loadRealCase(const std::string& dir, CaseLoadOptions lo, const RunMessages& messages) {
  lo.lenient = true;
  CaseInputs c = loadCaseInputs(dir, lo);
  if (!lo.load_reference) {
    const CaseReferenceFile f = caseReferenceFile(c, true);
    c.reference_name = f.path;
    c.reference_is_truth = f.is_truth;
  }
  const std::string reference =
      c.reference_name.empty() ? "none"
      : lo.load_reference      ? fmt::format("{} ({} epochs)", c.reference_name, c.reference.size())
                               : c.reference_name + " (read as a stream)";
  messages.note(fmt::format(
      "read {} (real read policies): GNSS {}, reference {}", dir,
      lo.load_gnss ? fmt::format("{} epochs", c.gnss.size()) : "read as a stream", reference));
  if (c.warnings.empty()) messages.note("  readers: no repair and no warning");
  for (const auto& w : c.warnings) noteLines("  reader/case: ", w, messages);
  return c;
}

ImuSelection selectRealImu(const CaseInputs& c, const std::string& which,
                           const std::string& profile, bool read_samples,
                           const RunMessages& messages, const TimeRangeConfig& range,
                           ImuFileScan* scan_out) {
  ImuSelection s = selectImu(c, which, profile, true, read_samples);
  ImuFileScan scan;
  scan.total = scan.kept = static_cast<long>(s.imu.size());
  if (!read_samples) {
    scan = scanImuFile(&s, range);
    s.imu = scan.span;
  }
  if (scan_out) *scan_out = scan;
  messages.note(
      fmt::format("IMU '{}' {}: {} samples, profile '{}'", which, s.path, scan.total, s.label));
  if (s.read_summary.empty()) {
    messages.note("  reader: no repair and no warning");
  } else {
    noteLines("  reader: ", s.read_summary, messages);
  }
  return s;
}

EstimationProblem makeRealProblem(const CaseInputs& c, const ImuSelection& imu, const RunConfig& rc,
                                  const std::optional<OutageScheduleConfig>& outages,
                                  const RunMessages& messages,
                                  std::vector<std::string>* notes_out) {
  return realProblem(c, imu, rc, outages, true, {}, messages, notes_out);
}

namespace {

// A latency study reads the fixes and the reference solution beyond the range (its track, its
// shifted time tags): it refuses a range, from the run config or from the request.
void refuseRangeInLatencyStudy(const RealRequest& q, const RunConfig& rc) {
  const std::string command = "graftnav real --latency-scan/--latency-grid";
  requireTimeRangeUnset(rc.time_range, q.run_config, command);
  if (!q.time_range.empty())
    throw std::runtime_error("--start/--end are not applied by " + command +
                             ": the latency study reads the GNSS and the reference beyond them");
}

// The series the range keeps: the held IMU and GNSS cut by restrictToTimeRange, or, streamed,
// the held GNSS cut as the scan of the IMU file kept its samples (a GNSS file read by each run
// is cut as it is read).
void keepRange(bool stream_gnss, const RunMessages& messages, RealInputs* in) {
  if (in->time_range.empty()) return;
  std::vector<std::string> notes;
  if (!in->stream) {
    restrictToTimeRange(in->time_range, &in->c, &in->imu, &notes);
  } else if (!stream_gnss) {
    notes.push_back(keepHeldGnssInRange(in->time_range, in->imu_scan, &in->c.gnss));
  }
  for (const auto& n : notes) messages.note("  note: " + n);
}

}  // namespace

RealInputs loadRealInputs(const RealRequest& q, const EstimatorRegistry& registry,
                          const RunMessages& messages) {
  RealInputs in;
  std::vector<std::string> warnings;
  in.rc = loadRunConfig(q.run_config, &warnings);
  in.time_range = mergeTimeRange(in.rc.time_range, q.time_range);
  if (q.latency_study) refuseRangeInLatencyStudy(q, in.rc);
  recordConfigFile(q.run_config);
  for (const auto& w : warnings) messages.warning(w);
  if (!in.rc.outages_given)
    throw std::runtime_error(q.run_config + ": an outages: section is required");
  in.stream = streamable(q, registry);
  // A streamed run reads the reference as it evaluates, and without a gnss: section the GNSS as
  // it navigates, unless an in-motion alignment reads it.
  const bool stream_gnss = streamsGnss(in);
  CaseLoadOptions lo;
  lo.load_reference = !in.stream;
  lo.load_gnss = !stream_gnss;
  in.c = loadRealCase(q.case_dir, lo, messages);
  in.imu =
      selectRealImu(in.c, q.imu, q.profile_path, !in.stream, messages, in.time_range, &in.imu_scan);
  if (!in.imu.profile_given)
    throw std::runtime_error("no noise parameters for the IMU: pass --profile");
  keepRange(stream_gnss, messages, &in);
  const ImuSample first = in.imu.imu.front();
  in.t_first_s = first.t_s - first.dt_s;
  if (in.stream) {  // makeProblem reads the reference's first epochs only
    in.reference = caseReferenceFile(in.c, true);
    if (!in.reference.path.empty()) in.c.reference = readReferenceHead(in.reference, in.t_first_s);
  }
  // Of a GNSS series it does not select, makeProblem reads whether there is one and (a static
  // alignment without an initial state) the first fix's position.
  if (stream_gnss) in.c.gnss = firstGnssFix(in.c, in.time_range);
  in.pr =
      realProblem(in.c, in.imu, in.rc, in.rc.outages, !in.stream, in.time_range, messages, nullptr);
  if (stream_gnss) {
    selectStreamedCheckpoints(messages, &in);
  } else {
    selectCheckpoints(in.c.gnss, &in);
  }
  if (!in.stream) return in;
  in.c.reference = NavSeries();
  if (!in.reference.path.empty()) scanRealReference(messages, &in);
  const double span_s = in.imu.imu.back().t_s - first.t_s;
  const long samples = in.imu_scan.kept;
  if (samples > 1 && span_s > 0.0 && in.rc.ekf.output_decimation == 1)
    in.expected_rates.solution_hz = static_cast<double>(samples - 1) / span_s;
  releaseStreamedSeries(messages, &in);
  if (std::isfinite(in.imu_start_s))
    in.expected_rates.solution_hz = 0.0;  // fewer samples navigated
  return in;
}

}  // namespace graftnav

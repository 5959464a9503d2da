#include "case_loader.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <stdexcept>

#include "graftnav/io/gnss_io.h"
#include "graftnav/eval/gnss_selection.h"
#include "graftnav/io/imu_io.h"
#include "graftnav/io/imu_profile_io.h"
#include "graftnav/nav/nav_interp.h"
#include "graftnav/io/nav_io.h"
#include "graftnav/nav/rotation.h"
#include "graftnav/filters/alignment.h"

namespace graftnav::app {

CaseInputs loadCaseInputs(const std::string& case_dir, const CaseLoadOptions& o) {
  if (!std::filesystem::is_directory(case_dir)) {
    throw std::runtime_error("case directory '" + case_dir + "' does not exist");
  }
  CaseInputs c;
  c.dir = case_dir;
  const CasePaths paths(case_dir);
  if (!CasePaths::exists(paths.caseYaml())) {
    throw std::runtime_error("'" + case_dir + "' is not a case directory: no case.yaml");
  }
  c.config = loadCaseConfig(paths.caseYaml(), &c.warnings);
  if (o.load_gnss) {
    if (!CasePaths::exists(paths.gnssPos())) {
      throw std::runtime_error("GNSS file '" + paths.gnssPos() + "' not found");
    }
    const std::string ft = CasePaths::exists(paths.gnssFixType()) ? paths.gnssFixType() : "";
    std::vector<ReadReport> reports;
    c.gnss = readGnss(paths.gnssPos(), ft, o.lenient ? GnssReadPolicy::real() : GnssReadPolicy{},
                      &reports);
    for (const auto& r : reports)
      if (!r.summary().empty()) c.warnings.push_back(r.summary());
  }
  if (o.load_reference) loadCaseReference(&c, o.lenient);
  return c;
}

void loadCaseReference(CaseInputs* c, bool lenient) {
  const CasePaths paths = c->paths();
  if (CasePaths::exists(paths.truthNav())) {
    c->reference = readNav(paths.truthNav());
    c->reference_name = paths.truthNav();
    c->reference_is_truth = true;
  } else if (auto ref = paths.referenceSolution(c->config); ref && CasePaths::exists(*ref)) {
    ReadReport rep;
    c->reference = readNav(*ref, lenient ? NavReadPolicy::real() : NavReadPolicy{}, &rep);
    if (!rep.summary().empty()) c->warnings.push_back(rep.summary());
    c->reference_name = *ref;
  }
}

ImuSelection selectImu(const CaseInputs& c, const std::string& which,
                       const std::string& profile_file, bool lenient, bool read_samples) {
  const CasePaths paths = c.paths();
  const CaseConfig& cfg = c.config;
  ImuSelection s;
  double rate_hz = cfg.testedImuRateHz();
  std::optional<ImuProfile> profile = cfg.tested_imu;
  s.profile_given = cfg.tested_imu_noise_given;
  if (which == "ref") {
    s.path = paths.refImu();
    rate_hz = cfg.imu_rate_hz;
    profile = cfg.reference_imu;
    s.profile_given = cfg.reference_imu_noise_given;
  } else if (which == "tested") {
    s.path = paths.testedImu();
  } else {
    s.path = which;
  }
  if (!profile_file.empty()) {
    std::vector<std::string> pw;
    profile = loadImuProfile(profile_file, &pw);
    s.profile_given = true;
  }
  if (profile) s.profile = *profile;
  if (!CasePaths::exists(s.path)) throw std::runtime_error("IMU file '" + s.path + "' not found");
  ImuReadOptions& ro = s.read_options;
  ro.nominal_rate_hz = rate_hz;
  if (lenient) ro.policy = ImuReadPolicy::real();
  if (read_samples) {
    ReadReport rep;
    s.imu = readImu(s.path, ro, &rep);
    s.read_summary = rep.summary();
    if (s.imu.empty()) throw std::runtime_error("IMU file '" + s.path + "' holds no sample");
  }
  s.label = profile && !profile->name.empty() ? profile->name : which;
  return s;
}

void restrictToTimeRange(const TimeRangeConfig& range, CaseInputs* c, ImuSelection* imu,
                         std::vector<std::string>* notes) {
  if (range.empty()) return;
  const double t0 = range.start_s.value_or(-1e300), t1 = range.end_s.value_or(1e300);
  ImuSeries kept;
  for (const auto& s : imu->imu)
    if (s.t_s - s.dt_s >= t0 - 1e-6 && s.t_s <= t1) kept.push_back(s);
  if (kept.empty()) {
    throw std::runtime_error(
        fmt::format("time range [{}, {}] holds no sample of '{}' ({:.3f} .. {:.3f})", t0, t1,
                    imu->path, imu->imu.front().t_s, imu->imu.back().t_s));
  }
  GnssSeries gnss;
  for (const auto& f : c->gnss)
    if (f.t_s >= t0 && f.t_s <= t1) gnss.push_back(f);
  notes->push_back(
      fmt::format("time range {:.3f} .. {:.3f}: {} of {} IMU samples, {} of {} GNSS epochs",
                  kept.front().t_s - kept.front().dt_s, kept.back().t_s, kept.size(),
                  imu->imu.size(), gnss.size(), c->gnss.size()));
  imu->imu = std::move(kept);
  c->gnss = std::move(gnss);
}

namespace {

// Static alignment over the first static_alignment_s of the IMU record; the heading from
// case.yaml when the gyros cannot find it.
void alignStaticInto(EstimationProblem& pr, const CaseConfig& cfg, const RunConfig& rc,
                     double t_first, int week, bool from_truth, std::vector<std::string>* notes) {
  Geodetic pos = pr.initial.pos;
  if (!cfg.initial_state && !from_truth) {
    if (pr.gnss.empty())
      throw std::runtime_error("static alignment needs a position (initial_state or GNSS)");
    pos = pr.gnss.front().pos;
  }
  const StaticAlignment al =
      alignStatic(pr.imu, t_first, rc.alignment.static_duration_s, pos, pr.imu_profile);
  NavState s;
  s.t_s = t_first + rc.alignment.static_duration_s;
  s.pos = pos;
  s.gnss_week = week;
  Eigen::Vector3d e = al.euler_rad;
  if (!al.heading_valid) {
    notes->push_back(al.note);
    if (!cfg.initial_state) throw std::runtime_error(al.note + "; use ekf.alignment: motion");
    e.z() = eulerFromQuat(cfg.initial_state->q_nb).z();
    notes->push_back("heading taken from case.yaml initial_state");
  }
  s.q_nb = quatFromEuler(e);
  pr.initial = s;
  pr.initial_sigma << 1.0, 1.0, 1.0, 0.05, 0.05, 0.05, std::max(al.level_std_rad, 1e-4),
      std::max(al.level_std_rad, 1e-4),
      al.heading_valid ? std::max(al.heading_std_rad, 1e-3) : 0.05;
  notes->push_back(fmt::format("static alignment: roll {:.4f} pitch {:.4f} yaw {:.4f} deg",
                               e.x() * kRadToDeg, e.y() * kRadToDeg, e.z() * kRadToDeg));
}

// In-motion alignment from the GNSS epochs precise enough; warns when the heading found is far
// from case.yaml's.
void alignInMotionInto(EstimationProblem& pr, const CaseConfig& cfg, const RunConfig& rc, int week,
                       std::vector<std::string>* notes) {
  GnssSeries precise;
  for (const auto& f : pr.gnss)
    if (std::max(f.std_ned_m.x(), f.std_ned_m.y()) <= rc.alignment.motion_max_std_m)
      precise.push_back(f);
  if (precise.size() < pr.gnss.size()) {
    notes->push_back(
        fmt::format("in-motion alignment from the {} of {} GNSS epochs with horizontal std <= {} m",
                    precise.size(), pr.gnss.size(), rc.alignment.motion_max_std_m));
  }
  const auto st = alignInMotion(pr.imu, precise, pr.lever_arm_b_m, rc.alignment.motion);
  if (!st) throw std::runtime_error("in-motion alignment: no GNSS epoch reaches the minimum speed");
  pr.initial = *st;
  pr.initial.gnss_week = week;
  pr.initial_sigma << 0.5, 0.5, 0.5, 0.3, 0.3, 0.3, 1.0 * kDegToRad, 1.0 * kDegToRad,
      3.0 * kDegToRad;
  notes->push_back(fmt::format("in-motion alignment at t={:.3f}", st->t_s));
  if (cfg.initial_state) {
    const double yaw_case = eulerFromQuat(cfg.initial_state->q_nb).z() * kRadToDeg;
    const double yaw = eulerFromQuat(st->q_nb).z() * kRadToDeg;
    const double d = std::remainder(yaw - yaw_case, 360.0);
    if (std::abs(d) > 5.0) {
      notes->push_back(fmt::format(
          "WARNING: in-motion alignment yaw {:.1f} deg at t={:.3f} differs by {:.1f} deg from case.yaml "
          "initial_state ({:.1f} deg at t={:.3f}): the case's initial heading is NOT used",
          yaw, st->t_s, d, yaw_case, cfg.initial_state->t_s));
    }
  }
}

}  // namespace

EstimationProblem makeProblem(const CaseInputs& c, const ImuSelection& sel, const RunConfig& rc,
                              const std::optional<OutageScheduleConfig>& outages,
                              std::vector<std::string>* notes) {
  std::vector<std::string> local;
  if (!notes) notes = &local;
  const CaseConfig& cfg = c.config;
  EstimationProblem pr;
  pr.imu = sel.imu;
  pr.imu_profile = sel.profile;
  pr.gnss = c.gnss;
  if (rc.gnss.given && !c.gnss.empty()) {
    const GnssSelection gnss_sel = selectGnss(c.gnss, rc.gnss.selection);
    pr.gnss = gnss_sel.kept;
    notes->push_back(gnss_sel.counts.summary());
    if (pr.gnss.empty())
      throw std::runtime_error("GNSS selection of the run config rejected every epoch of '" +
                               c.dir + "'");
  }
  if (cfg.lever_arm_m) {
    pr.lever_arm_b_m = *cfg.lever_arm_m;
  } else if (!c.gnss.empty()) {
    notes->push_back("case.yaml has no lever_arm_m: a zero lever arm is used");
  }

  const double t_first = pr.imu.front().t_s - pr.imu.front().dt_s;
  const int week = cfg.gnss_week.value_or(c.reference.empty() ? 0 : c.reference.front().gnss_week);
  std::optional<NavState> from_truth;
  if (c.reference_is_truth)
    from_truth = interpolateNav(c.reference, std::max(t_first, c.reference.front().t_s), 1e-3);
  if (from_truth) {
    pr.initial = *from_truth;
    notes->push_back(fmt::format("initial state from truth.nav at t={:.3f}", pr.initial.t_s));
  } else if (cfg.initial_state) {
    pr.initial = *cfg.initial_state;
    notes->push_back("initial state from case.yaml initial_state");
  } else if (rc.alignment.mode == "given") {
    throw std::runtime_error("no initial state for '" + c.dir +
                             "': neither field/truth.nav nor case.yaml initial_state (set "
                             "ekf.alignment: static|motion)");
  }
  pr.initial.gnss_week = week;

  if (rc.alignment.mode == "static") {
    alignStaticInto(pr, cfg, rc, t_first, week, from_truth.has_value(), notes);
  } else if (rc.alignment.mode == "motion") {
    alignInMotionInto(pr, cfg, rc, week, notes);
  }
  // The schedule counts from the first IMU epoch, also when the filter starts later (alignment).
  if (outages) pr.outages = buildOutageWindows(*outages, t_first, pr.imu.back().t_s);
  return pr;
}

ImuSelection graftedSelection(ImuSeries imu, const ImuProfile& tested_profile,
                              const ImuReadOptions& read_options) {
  ImuSelection sel;
  sel.imu = std::move(imu);
  sel.profile = tested_profile;
  sel.profile_given = true;
  sel.read_options = read_options;
  return sel;
}

}  // namespace graftnav::app

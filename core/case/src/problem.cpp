#include "graftnav/case/problem.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <utility>

#include "graftnav/estimation/alignment.h"
#include "graftnav/eval/gnss_selection.h"
#include "graftnav/io/odometer_io.h"
#include "graftnav/nav/nav_interp.h"
#include "graftnav/nav/rotation.h"

namespace graftnav {

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

// The run config's odometer and NHC; with the odometer on, the case's field/odometer.txt as a
// stream, read once here so that a bad line stops the run before any output, and a warning
// listing the parts of the IMU span it does not cover.
void addVehicleAiding(const CaseInputs& c, const RunConfig& rc, EstimationProblem* pr,
                      std::vector<std::string>* notes) {
  pr->aiding = rc.aiding.options;
  if (!pr->aiding.any()) return;
  const double rate_hz = pr->aiding.rateHz();
  notes->push_back(fmt::format("vehicle aiding: odometer {}, NHC {}, {:g} Hz",
                               pr->aiding.odometer.enabled ? "on" : "off",
                               pr->aiding.nhc.enabled ? "on" : "off", rate_hz));
  if (!pr->aiding.odometer.enabled) return;
  const std::string path = c.paths().odometer();
  if (!CasePaths::exists(path))
    throw std::runtime_error("odometer.enabled is true in the run config but the case '" + c.dir +
                             "' has no field/odometer.txt");
  pr->odometer_stream = odometerFileStream(path, rc.aiding.odometer_read);
  const double t0 = pr->imu.front().t_s - pr->imu.front().dt_s, t1 = pr->imu.back().t_s;
  const auto pass = pr->odometer_stream();
  const std::string w = odometerCoverageWarning(
      path, odometerUncoveredSpans(*pass, t0, t1, pr->aiding.odometer.max_gap_s), t0, t1);
  if (!w.empty()) notes->push_back(w);
}

}  // namespace

EstimationProblem makeProblem(const CaseInputs& c, ImuSelection sel, const RunConfig& rc,
                              const std::optional<OutageScheduleConfig>& outages,
                              std::vector<std::string>* notes) {
  std::vector<std::string> local;
  if (!notes) notes = &local;
  const CaseConfig& cfg = c.config;
  EstimationProblem pr;
  pr.imu = std::move(sel.imu);
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
  } else if (rc.alignment.mode == AlignmentMode::kGiven) {
    throw std::runtime_error("no initial state for '" + c.dir +
                             "': neither field/truth.nav nor case.yaml initial_state (set "
                             "ekf.alignment: static|motion)");
  }
  pr.initial.gnss_week = week;

  if (rc.alignment.mode == AlignmentMode::kStatic) {
    alignStaticInto(pr, cfg, rc, t_first, week, from_truth.has_value(), notes);
  } else if (rc.alignment.mode == AlignmentMode::kMotion) {
    alignInMotionInto(pr, cfg, rc, week, notes);
  }
  // The schedule counts from the first IMU epoch, also when the filter starts later (alignment).
  if (outages) pr.outages = buildOutageWindows(*outages, t_first, pr.imu.back().t_s);
  addVehicleAiding(c, rc, &pr, notes);
  return pr;
}

void startAtInitialState(EstimationProblem* pr, std::vector<std::string>* notes) {
  const double t_init = pr->initial.t_s;
  std::size_t k0 = 0;
  while (k0 < pr->imu.size() && pr->imu[k0].t_s - pr->imu[k0].dt_s < t_init - 1e-6) ++k0;
  if (k0 > 0 && k0 < pr->imu.size()) {
    pr->imu.erase(pr->imu.begin(), pr->imu.begin() + static_cast<std::ptrdiff_t>(k0));
    notes->push_back(
        fmt::format("IMU series starts at the initial state epoch t={:.3f} ({} earlier samples "
                    "used only by the alignment)",
                    t_init, k0));
  }
  // GNSS epochs before the start are not navigation inputs (the EKF skips them; the graph would
  // anchor nodes where no IMU data connects them).
  const auto first_gnss = std::find_if(pr->gnss.begin(), pr->gnss.end(),
                                       [&](const GnssFix& f) { return f.t_s > t_init + 1e-6; });
  if (first_gnss != pr->gnss.begin()) {
    notes->push_back(fmt::format("{} GNSS epochs before the initial state epoch not used",
                                 std::distance(pr->gnss.begin(), first_gnss)));
    pr->gnss.erase(pr->gnss.begin(), first_gnss);
  }
}

}  // namespace graftnav

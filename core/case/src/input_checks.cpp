#include "graftnav/case/input_checks.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

namespace graftnav {

namespace {

double imuBegin(const ImuSeries& imu) { return imu.front().t_s - imu.front().dt_s; }

}  // namespace

void InputCheckOptions::validate() const {
  if (min_gnss_epochs < 1)
    throw std::invalid_argument(
        fmt::format("InputCheckOptions.min_gnss_epochs must be >= 1, got {}", min_gnss_epochs));
  if (!(lab_static_floor_s > 0.0) || !std::isfinite(lab_static_floor_s))
    throw std::invalid_argument(fmt::format(
        "InputCheckOptions.lab_static_floor_s must be > 0, got {}", lab_static_floor_s));
}

void requireOutagesInsideData(const OutageScheduleConfig& c, const std::vector<TimeWindow>& windows,
                              double t_begin_s, double t_end_s) {
  if (!c.enabled || !windows.empty()) return;
  const double span = t_end_s - t_begin_s;
  if (!c.explicit_windows.empty())
    throw std::runtime_error(fmt::format(
        "outages.windows: no window lies inside the data [{:.3f}, {:.3f}] s", t_begin_s, t_end_s));
  throw std::runtime_error(fmt::format(
      "outage start {:g} s + length {:g} s (+ end margin {:g} s) lies beyond the data, which last {:.1f} s: "
      "no outage fits (check --outage-start / --outage-length or outages: in the config)",
      c.start_s, c.length_s, c.end_margin_s, span));
}

void GnssCoverage::add(double t_s) {
  if (total++ == 0) first_t_s = t_s;
  last_t_s = t_s;
  if (t_s >= imu_t0_s && t_s <= imu_t1_s) ++inside;
}

std::vector<std::string> checkGnssCoverage(const GnssSeries& gnss, const std::string& gnss_path,
                                           const ImuSeries& imu, bool free_inertial,
                                           const InputCheckOptions& o) {
  if (imu.empty()) throw std::runtime_error("checkGnssCoverage: no IMU samples");
  GnssCoverage c;
  c.imu_t0_s = imuBegin(imu);
  c.imu_t1_s = imu.back().t_s;
  for (const GnssFix& f : gnss) c.add(f.t_s);
  return checkGnssCoverage(c, gnss_path, free_inertial, o);
}

std::vector<std::string> checkGnssCoverage(const GnssCoverage& c, const std::string& gnss_path,
                                           bool free_inertial, const InputCheckOptions& o) {
  o.validate();
  if (c.inside >= o.min_gnss_epochs) return {};
  std::string what =
      fmt::format("{}: {} of {} GNSS epochs lie inside the IMU span [{:.3f}, {:.3f}] s", gnss_path,
                  c.inside, c.total, c.imu_t0_s, c.imu_t1_s);
  if (c.total > 0) what += fmt::format(" (GNSS span [{:.3f}, {:.3f}] s)", c.first_t_s, c.last_t_s);
  what += fmt::format("; at least {} are needed for GNSS/INS", o.min_gnss_epochs);
  if (!free_inertial)
    throw std::runtime_error(
        what + ": the run would be free-inertial (pass --free-inertial if that is meant)");
  return {what + "; running FREE-INERTIAL as asked"};
}

std::vector<std::string> checkGnssUsed(int gnss_used, bool free_inertial,
                                       const InputCheckOptions& o) {
  o.validate();
  if (free_inertial || gnss_used >= o.min_gnss_epochs) return {};
  throw std::runtime_error(fmt::format(
      "the estimator used {} GNSS epochs (at least {} needed; the rest were gated out or withheld): the "
      "solution is close to free-inertial; no result written",
      gnss_used, o.min_gnss_epochs));
}

std::vector<std::string> checkReferenceCoverage(const NavSeries& ref, const std::string& path,
                                                const ImuSeries& imu,
                                                const std::vector<TimeWindow>& outages) {
  if (ref.empty() || imu.empty()) return {};
  const double r0 = ref.front().t_s, r1 = ref.back().t_s;
  for (const TimeWindow& w : outages) {
    const bool any = std::any_of(ref.begin(), ref.end(), [&](const NavState& s) {
      return s.t_s >= w.start_s && s.t_s <= w.end_s;
    });
    if (!any)
      throw std::runtime_error(fmt::format(
          "{}: no reference epoch inside the outage [{:.3f}, {:.3f}] s (reference span [{:.3f}, {:.3f}] s): its "
          "outage errors cannot be computed",
          path, w.start_s, w.end_s, r0, r1));
  }
  const double t0 = imuBegin(imu), t1 = imu.back().t_s;
  const double covered = std::max(0.0, std::min(t1, r1) - std::max(t0, r0));
  if (covered < 0.99 * (t1 - t0))
    return {fmt::format(
        "{} covers {:.1f} s of the {:.1f} s IMU span ([{:.3f}, {:.3f}] s vs [{:.3f}, {:.3f}] s): "
        "errors are evaluated only where it exists",
        path, covered, t1 - t0, r0, r1, t0, t1)};
  return {};
}

double outageSpacing(const std::vector<TimeWindow>& windows) {
  if (windows.empty()) return 0.0;
  double spacing = windows.size() == 1 ? windows.front().length_s() : 0.0;
  for (std::size_t i = 1; i < windows.size(); ++i)
    spacing = std::max(spacing, windows[i].start_s - windows[i - 1].start_s);
  return spacing;
}

std::vector<std::string> checkLabStaticRecord(double record_s, const std::string& path,
                                              double outage_spacing_s, const InputCheckOptions& o) {
  o.validate();
  if (!(record_s >= o.lab_static_floor_s))
    throw std::runtime_error(fmt::format(
        "{}: the lab static record lasts {:.2f} s, below the {:g} s floor for grafting (a shorter record repeats "
        "inside one outage)",
        path, record_s, o.lab_static_floor_s));
  if (record_s < outage_spacing_s)
    return {fmt::format(
        "{}: the lab static record lasts {:.1f} s, shorter than the outage spacing of {:.1f} s: "
        "consecutive outages graft overlapping stretches of the same noise (record at least the "
        "outage period recommended)",
        path, record_s, outage_spacing_s)};
  return {};
}

}  // namespace graftnav

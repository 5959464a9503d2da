#include "input_checks.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "case_loader.h"
#include "estimators.h"
#include "graftnav/io/imu_io.h"
#include "run_config.h"
#include "sg_evaluate.h"

namespace graftnav::app {

namespace {

void requirePositive(const std::optional<double>& v, const char* flag) {
  if (v && !(std::isfinite(*v) && *v > 0.0))
    throw std::runtime_error(fmt::format("{} {}: must be a positive number of seconds", flag, *v));
}

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

void validateOutageOptions(const std::optional<double>& length_s,
                           const std::optional<double>& period_s,
                           const std::optional<double>& start_s) {
  requirePositive(length_s, "--outage-length");
  requirePositive(period_s, "--outage-period");
  if (start_s && !(std::isfinite(*start_s) && *start_s >= 0.0))
    throw std::runtime_error(
        fmt::format("--outage-start {}: must be >= 0 s (seconds after the data start)", *start_s));
  if (length_s && period_s && *period_s < *length_s)
    throw std::runtime_error(
        fmt::format("--outage-period {} is shorter than --outage-length {}: outages would overlap",
                    *period_s, *length_s));
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

std::vector<std::string> checkEvaluationInputs(const SgEvaluateOptions& o) {
  std::vector<std::string> w;
  const auto add = [&](std::vector<std::string> more) {
    w.insert(w.end(), more.begin(), more.end());
  };
  const std::vector<std::string> names = estimatorNames();
  if (std::find(names.begin(), names.end(), o.estimator) == names.end()) {
    std::string known;
    for (const auto& n : names) known += (known.empty() ? "" : ", ") + n;
    throw std::runtime_error("--estimator '" + o.estimator + "': unknown (known: " + known + ")");
  }
  validateOutageOptions(o.outage_length_s, o.outage_period_s, o.outage_start_s);
  const CaseInputs c = loadCaseInputs(o.case_dir);
  RunConfig rc;
  if (!o.config_path.empty()) rc = loadRunConfig(o.config_path, nullptr);
  OutageScheduleConfig oc = rc.outages;
  if (o.outage_length_s) oc.length_s = *o.outage_length_s;
  if (o.outage_period_s) oc.period_s = *o.outage_period_s;
  if (o.outage_start_s) oc.start_s = *o.outage_start_s;
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

}  // namespace graftnav::app

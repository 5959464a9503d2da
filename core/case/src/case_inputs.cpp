#include "graftnav/case/case_inputs.h"

#include <fmt/core.h>

#include <filesystem>
#include <stdexcept>

#include "graftnav/io/gnss_io.h"
#include "graftnav/io/imu_io.h"
#include "graftnav/io/imu_profile_io.h"
#include "graftnav/io/nav_io.h"
#include "graftnav/io/file_errors.h"

namespace graftnav {

CaseInputs loadCaseInputs(const std::string& case_dir, const CaseLoadOptions& o) {
  if (!std::filesystem::is_directory(case_dir)) {
    throw MissingFileError(case_dir, "case directory '" + case_dir + "' does not exist");
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
      throw MissingFileError(paths.gnssPos(), "GNSS file '" + paths.gnssPos() + "' not found");
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

CaseReferenceFile caseReferenceFile(const CaseInputs& c, bool lenient) {
  const CasePaths paths = c.paths();
  CaseReferenceFile f;
  if (CasePaths::exists(paths.truthNav())) {
    f.path = paths.truthNav();
    f.is_truth = true;
  } else if (auto ref = paths.referenceSolution(c.config); ref && CasePaths::exists(*ref)) {
    f.path = *ref;
    if (lenient) f.policy = NavReadPolicy::real();
  }
  return f;
}

NavSeries readReferenceHead(const CaseReferenceFile& f, double t_s) {
  NavStreamReader reader(f.path, f.policy);
  NavSeries head;
  NavState s;
  int after = 0;
  while (after < 2 && reader.next(&s)) {
    // An epoch at or before t_s replaces the previous one unless that is the first.
    const bool replaces = s.t_s <= t_s && head.size() >= 2;
    if (replaces) {
      head.back() = s;
    } else {
      head.push_back(s);
    }
    if (s.t_s > t_s) ++after;
  }
  return head;
}

void loadCaseReference(CaseInputs* c, bool lenient) {
  const CaseReferenceFile f = caseReferenceFile(*c, lenient);
  if (f.path.empty()) return;
  ReadReport rep;
  c->reference = readNav(f.path, f.policy, &rep);
  if (!f.is_truth && !rep.summary().empty()) c->warnings.push_back(rep.summary());
  c->reference_name = f.path;
  c->reference_is_truth = f.is_truth;
}

std::string defaultImuOf(const CasePaths& paths) {
  const bool only_tested =
      !CasePaths::exists(paths.refImu()) && CasePaths::exists(paths.testedImu());
  return only_tested ? "tested" : "ref";
}

std::string chooseImu(const std::string& requested, const CasePaths& paths, std::string* note) {
  if (!requested.empty()) return requested;
  const std::string which = defaultImuOf(paths);
  if (note && which != "ref")
    *note = "IMU: '" + which + "' (" + paths.testedImu() +
            "), the only IMU of the case (no field/ref_imu.txt); --imu chooses another";
  return which;
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
  if (!CasePaths::exists(s.path))
    throw MissingFileError(s.path, "IMU file '" + s.path + "' not found");
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
  ImuSeries kept;
  for (const auto& s : imu->imu)
    if (range.keepsImuSample(s.t_s, s.dt_s)) kept.push_back(s);
  if (kept.empty())
    throw timeRangeWithoutSamples(range, imu->path, imu->imu.front(), imu->imu.back());
  GnssSeries gnss;
  for (const auto& f : c->gnss)
    if (range.keepsGnssEpoch(f.t_s)) gnss.push_back(f);
  notes->push_back(timeRangeNote({kept.front(), kept.back()}, static_cast<long>(kept.size()),
                                 static_cast<long>(imu->imu.size()), static_cast<long>(gnss.size()),
                                 static_cast<long>(c->gnss.size())));
  imu->imu = std::move(kept);
  c->gnss = std::move(gnss);
}

std::runtime_error timeRangeWithoutSamples(const TimeRangeConfig& range, const std::string& path,
                                           const ImuSample& first, const ImuSample& last) {
  return std::runtime_error(
      fmt::format("time range [{}, {}] holds no sample of '{}' ({:.3f} .. {:.3f})", range.startS(),
                  range.endS(), path, first.t_s, last.t_s));
}

std::string timeRangeNote(const ImuSeries& kept_span, long imu_kept, long imu_total, long gnss_kept,
                          long gnss_total) {
  return fmt::format("time range {:.3f} .. {:.3f}: {} of {} IMU samples, {} of {} GNSS epochs",
                     kept_span.front().t_s - kept_span.front().dt_s, kept_span.back().t_s, imu_kept,
                     imu_total, gnss_kept, gnss_total);
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

}  // namespace graftnav

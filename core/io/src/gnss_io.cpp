#include "graftnav/io/gnss_io.h"

#include <fmt/format.h>

#include <cmath>
#include <iterator>
#include <stdexcept>

#include "graftnav/io/atomic_file.h"
#include "graftnav/nav/units.h"

namespace graftnav {

GnssReadPolicy GnssReadPolicy::real() {
  GnssReadPolicy p;
  p.duplicate_stamp = ReadRule::kRepair;
  p.backwards_stamp = ReadRule::kRepair;
  p.off_whole_second = ReadRule::kWarn;
  p.zero_std = ReadRule::kRepair;
  p.unmatched_fix_type = ReadRule::kWarn;
  return p;
}

void GnssReadPolicy::validate() const {
  requireRule(duplicate_stamp, {ReadRule::kError, ReadRule::kRepair},
              "GnssReadPolicy.duplicate_stamp");
  requireRule(backwards_stamp, {ReadRule::kError, ReadRule::kRepair},
              "GnssReadPolicy.backwards_stamp");
  requireRule(off_whole_second, {ReadRule::kError, ReadRule::kWarn},
              "GnssReadPolicy.off_whole_second");
  requireRule(zero_std, {ReadRule::kError, ReadRule::kRepair}, "GnssReadPolicy.zero_std");
  requireRule(unmatched_fix_type, {ReadRule::kError, ReadRule::kWarn},
              "GnssReadPolicy.unmatched_fix_type");
  if (!(whole_second_tolerance_s > 0.0 && whole_second_tolerance_s < 0.5))
    throw std::invalid_argument(
        "GnssReadPolicy.whole_second_tolerance_s must be in (0, 0.5), got " +
        std::to_string(whole_second_tolerance_s));
  if (!(std_floor_m > 0.0) || !std::isfinite(std_floor_m))
    throw std::invalid_argument("GnssReadPolicy.std_floor_m must be > 0, got " +
                                std::to_string(std_floor_m));
  if (!(match_tolerance_s >= 0.0) || !std::isfinite(match_tolerance_s))
    throw std::invalid_argument("GnssReadPolicy.match_tolerance_s must be >= 0, got " +
                                std::to_string(match_tolerance_s));
}

namespace {
const char* const kPosColumns[] = {"time",      "latitude", "longitude", "height",
                                   "std_north", "std_east", "std_up"};
const char* const kFixTypeColumns[] = {"time", "fix_type", "num_sv"};

void checkOffWholeSecond(const TextTableReader& r, double t_s, const GnssReadPolicy& policy,
                         ReadReport& report) {
  const double off = std::fabs(t_s - std::round(t_s));
  if (off <= policy.whole_second_tolerance_s) return;
  const std::string what = "epoch " + std::string(r.token(0)) + " is " +
                           fmt::format("{:.3f}", off) + " s off a whole second";
  if (policy.off_whole_second == ReadRule::kError) r.fail(what);
  report.note(ReadCondition::kOffWholeSecond, r.lineNumber(), what);
}

void beginReport(ReadReport& report, const std::string& path) {
  report = ReadReport{};
  report.path = path;
}
}  // namespace

GnssSeries readGnssPos(const std::string& path, const GnssReadPolicy& policy,
                       ReadReport* report_out) {
  policy.validate();
  ReadReport local_report;
  ReadReport& report = report_out ? *report_out : local_report;
  beginReport(report, path);
  TextTableReader reader(path);
  GnssSeries fixes;
  fixes.reserve(reader.physicalLineCount());
  TimeOrderGuard order(policy.duplicate_stamp, policy.backwards_stamp);
  while (reader.next()) {
    ++report.data_lines;
    reader.requireColumns(7, 7, "GNSS .pos");
    reader.requireFinite(kPosColumns);
    const double* v = reader.values();
    if (std::fabs(v[1]) > 90.0)
      reader.fail("latitude " + std::string(reader.token(1)) + " deg is outside [-90, 90]");
    if (std::fabs(v[2]) > 360.0)
      reader.fail("longitude " + std::string(reader.token(2)) + " deg is outside [-360, 360]");
    if (!order.accept(reader, v[0], 0, report)) continue;
    checkOffWholeSecond(reader, v[0], policy, report);
    GnssFix f;
    f.t_s = v[0];
    f.pos = Geodetic{v[1] * units::kDegToRad, v[2] * units::kDegToRad, v[3]};
    for (int i = 0; i < 3; ++i) {
      double s = v[4 + i];
      if (s < 0.0)
        reader.fail(std::string(kPosColumns[4 + i]) + " " + std::string(reader.token(4 + i)) +
                    " m is negative");
      if (s == 0.0) {
        const std::string what =
            std::string(kPosColumns[4 + i]) + " is " + quoteForMessage(reader.token(4 + i));
        if (policy.zero_std == ReadRule::kError)
          reader.fail(what + ": a zero standard deviation is not usable");
        report.note(
            ReadCondition::kZeroStd, reader.lineNumber(),
            what + ": replaced by the floor " + fmt::format("{:g}", policy.std_floor_m) + " m");
        s = policy.std_floor_m;
      }
      f.std_ned_m[i] = s;
    }
    fixes.push_back(f);
  }
  if (fixes.empty()) throw std::runtime_error(path + ": no GNSS epochs in the file");
  report.records_kept = static_cast<int>(fixes.size());
  return fixes;
}

std::vector<GnssFixTypeRecord> readGnssFixTypes(const std::string& path,
                                                const GnssReadPolicy& policy,
                                                ReadReport* report_out) {
  policy.validate();
  ReadReport local_report;
  ReadReport& report = report_out ? *report_out : local_report;
  beginReport(report, path);
  TextTableReader reader(path);
  std::vector<GnssFixTypeRecord> records;
  records.reserve(reader.physicalLineCount());
  TimeOrderGuard order(policy.duplicate_stamp, policy.backwards_stamp);
  while (reader.next()) {
    ++report.data_lines;
    reader.requireColumns(3, 3, "GNSS fix type");
    reader.requireFinite(kFixTypeColumns);
    GnssFixTypeRecord rec;
    rec.t_s = reader.value(0);
    rec.fix_type = reader.integerValue(1, "fix_type");
    rec.num_sv = reader.integerValue(2, "num_sv");
    rec.line = reader.lineNumber();
    if (rec.fix_type < 0) reader.fail("fix_type " + std::string(reader.token(1)) + " is negative");
    if (rec.num_sv < 0) reader.fail("num_sv " + std::string(reader.token(2)) + " is negative");
    if (!order.accept(reader, rec.t_s, 0, report)) continue;
    records.push_back(rec);
  }
  if (records.empty()) throw std::runtime_error(path + ": no epochs in the fix type file");
  report.records_kept = static_cast<int>(records.size());
  return records;
}

void mergeGnssFixTypes(GnssSeries& fixes, const std::vector<GnssFixTypeRecord>& records,
                       const std::string& fixtype_path, const GnssReadPolicy& policy,
                       ReadReport* report_out) {
  policy.validate();
  ReadReport local_report;
  ReadReport& report = report_out ? *report_out : local_report;
  if (report.path.empty()) report.path = fixtype_path;
  const double tol = policy.match_tolerance_s;
  auto unmatched = [&](int line, const std::string& what) {
    if (policy.unmatched_fix_type == ReadRule::kError)
      throw std::runtime_error(
          fixtype_path + (line > 0 ? ":" + std::to_string(line) : std::string()) + ": " + what);
    report.note(ReadCondition::kUnmatchedEpoch, line, what);
  };
  // Both sequences are strictly increasing: one merge pass.
  std::size_t i = 0;  // fixes
  std::size_t j = 0;  // records
  while (i < fixes.size() || j < records.size()) {
    if (j >= records.size()) {
      unmatched(0, "GNSS epoch " + fmt::format("{:.6f}", fixes[i].t_s) +
                       " (.pos) has no fix type record");
      ++i;
    } else if (i >= fixes.size() || records[j].t_s < fixes[i].t_s - tol) {
      unmatched(records[j].line,
                "fix type epoch " + fmt::format("{:.6f}", records[j].t_s) + " has no .pos epoch");
      ++j;
    } else if (records[j].t_s > fixes[i].t_s + tol) {
      unmatched(0, "GNSS epoch " + fmt::format("{:.6f}", fixes[i].t_s) +
                       " (.pos) has no fix type record");
      ++i;
    } else {
      fixes[i].fix_type = records[j].fix_type;
      fixes[i].num_sv = records[j].num_sv;
      ++i;
      ++j;
    }
  }
}

GnssSeries readGnss(const std::string& pos_path, const std::string& fixtype_path,
                    const GnssReadPolicy& policy, std::vector<ReadReport>* reports) {
  ReadReport pos_report;
  GnssSeries fixes = readGnssPos(pos_path, policy, &pos_report);
  if (reports) reports->push_back(pos_report);
  if (!fixtype_path.empty()) {
    ReadReport ft_report;
    const auto records = readGnssFixTypes(fixtype_path, policy, &ft_report);
    mergeGnssFixTypes(fixes, records, fixtype_path, policy, &ft_report);
    if (reports) reports->push_back(ft_report);
  }
  return fixes;
}

namespace {
void checkIncreasing(const std::string& path, const GnssSeries& fixes, const char* who) {
  for (std::size_t k = 0; k < fixes.size(); ++k) {
    const GnssFix& f = fixes[k];
    if (!std::isfinite(f.t_s) || !std::isfinite(f.pos.lat_rad) || !std::isfinite(f.pos.lon_rad) ||
        !std::isfinite(f.pos.h_m) || !f.std_ned_m.allFinite())
      throw std::invalid_argument(path + ": " + who + ": epoch " + std::to_string(k) +
                                  " has a non-finite value");
    if (k > 0 && !(f.t_s > fixes[k - 1].t_s))
      throw std::invalid_argument(path + ": " + who + ": epoch " + std::to_string(k) + " time " +
                                  fmt::format("{:.6f}", f.t_s) + " is not after previous " +
                                  fmt::format("{:.6f}", fixes[k - 1].t_s));
  }
  if (fixes.empty()) throw std::invalid_argument(path + ": " + who + ": no epochs");
}
}  // namespace

void writeGnssPos(const std::string& path, const GnssSeries& fixes) {
  checkIncreasing(path, fixes, "writeGnssPos");
  fmt::memory_buffer buf;
  for (const GnssFix& f : fixes) {
    fmt::format_to(std::back_inserter(buf), "{:.6f} {:.10f} {:.10f} {:.4f} {:.4f} {:.4f} {:.4f}\n",
                   f.t_s, f.pos.lat_rad * units::kRadToDeg, f.pos.lon_rad * units::kRadToDeg,
                   f.pos.h_m, f.std_ned_m.x(), f.std_ned_m.y(), f.std_ned_m.z());
  }
  writeFileAtomically(path, std::string_view(buf.data(), buf.size()));
}

void writeGnssFixTypes(const std::string& path, const GnssSeries& fixes) {
  checkIncreasing(path, fixes, "writeGnssFixTypes");
  fmt::memory_buffer buf;
  for (const GnssFix& f : fixes)
    fmt::format_to(std::back_inserter(buf), "{:.6f} {} {}\n", f.t_s, f.fix_type, f.num_sv);
  writeFileAtomically(path, std::string_view(buf.data(), buf.size()));
}

}  // namespace graftnav

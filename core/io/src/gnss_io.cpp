#include "graftnav/io/gnss_io.h"

#include <fmt/format.h>

#include <cmath>
#include <functional>
#include <optional>
#include <utility>
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

namespace {

// The current line of a .pos reader as a fix into *fix; false when the time-order rule drops it.
bool parsePosLine(TextTableReader& reader, const GnssReadPolicy& policy, TimeOrderGuard& order,
                  ReadReport& report, GnssFix* fix) {
  ++report.data_lines;
  reader.requireColumns(7, 7, "GNSS .pos");
  reader.requireFinite(kPosColumns);
  const double* v = reader.values();
  if (std::fabs(v[1]) > 90.0)
    reader.fail("latitude " + std::string(reader.token(1)) + " deg is outside [-90, 90]");
  if (std::fabs(v[2]) > 360.0)
    reader.fail("longitude " + std::string(reader.token(2)) + " deg is outside [-360, 360]");
  if (!order.accept(reader, v[0], 0, report)) return false;
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
  *fix = f;
  return true;
}

// The current line of a fix-type reader as a record; false when the time-order rule drops it.
bool parseFixTypeLine(TextTableReader& reader, TimeOrderGuard& order, ReadReport& report,
                      GnssFixTypeRecord* rec) {
  ++report.data_lines;
  reader.requireColumns(3, 3, "GNSS fix type");
  reader.requireFinite(kFixTypeColumns);
  rec->t_s = reader.value(0);
  rec->fix_type = reader.integerValue(1, "fix_type");
  rec->num_sv = reader.integerValue(2, "num_sv");
  rec->line = reader.lineNumber();
  if (rec->fix_type < 0) reader.fail("fix_type " + std::string(reader.token(1)) + " is negative");
  if (rec->num_sv < 0) reader.fail("num_sv " + std::string(reader.token(2)) + " is negative");
  return order.accept(reader, rec->t_s, 0, report);
}

// Fixes (in time order) matched with fix-type records (in time order) in one merge pass: each
// fix takes the record within policy.match_tolerance_s; unmatched fixes and records follow
// policy.unmatched_fix_type.
class FixTypeMatcher {
 public:
  using NextRecord = std::function<bool(GnssFixTypeRecord*)>;
  FixTypeMatcher(const std::string& path, const GnssReadPolicy& policy, ReadReport& report,
                 NextRecord next)
      : path_(path), policy_(policy), report_(report), next_(std::move(next)) {}
  void match(GnssFix& fix) {
    const double tol = policy_.match_tolerance_s;
    while (peek() && rec_.t_s < fix.t_s - tol) {
      unmatched(rec_.line,
                "fix type epoch " + fmt::format("{:.6f}", rec_.t_s) + " has no .pos epoch");
      has_ = false;
    }
    if (peek() && rec_.t_s <= fix.t_s + tol) {
      fix.fix_type = rec_.fix_type;
      fix.num_sv = rec_.num_sv;
      has_ = false;
    } else {
      unmatched(0,
                "GNSS epoch " + fmt::format("{:.6f}", fix.t_s) + " (.pos) has no fix type record");
    }
  }
  // The records after the last fix.
  void finish() {
    for (; peek(); has_ = false)
      unmatched(rec_.line,
                "fix type epoch " + fmt::format("{:.6f}", rec_.t_s) + " has no .pos epoch");
  }

 private:
  bool peek() {
    if (!has_ && !ended_) {
      has_ = next_(&rec_);
      ended_ = !has_;
    }
    return has_;
  }
  void unmatched(int line, const std::string& what) {
    if (policy_.unmatched_fix_type == ReadRule::kError)
      throw std::runtime_error(path_ + (line > 0 ? ":" + std::to_string(line) : std::string()) +
                               ": " + what);
    report_.note(ReadCondition::kUnmatchedEpoch, line, what);
  }

  const std::string& path_;
  const GnssReadPolicy& policy_;
  ReadReport& report_;
  NextRecord next_;
  GnssFixTypeRecord rec_;
  bool has_ = false, ended_ = false;
};

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
  GnssFix f;
  while (reader.next()) {
    if (parsePosLine(reader, policy, order, report, &f)) fixes.push_back(f);
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
  GnssFixTypeRecord rec;
  while (reader.next()) {
    if (parseFixTypeLine(reader, order, report, &rec)) records.push_back(rec);
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
  std::size_t j = 0;
  FixTypeMatcher matcher(fixtype_path, policy, report, [&](GnssFixTypeRecord* rec) {
    if (j >= records.size()) return false;
    *rec = records[j++];
    return true;
  });
  for (GnssFix& f : fixes) matcher.match(f);
  matcher.finish();
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

// The readers, order guards, reports and fix-type matcher of one pass.
struct GnssStreamReader::State {
  State(const std::string& pos_path, const std::string& ft_path, const GnssReadPolicy& p,
        std::size_t chunk_bytes)
      : policy(p),
        pos(TextTableReader::streaming(pos_path, chunk_bytes)),
        pos_order(p.duplicate_stamp, p.backwards_stamp),
        fixtype_order(p.duplicate_stamp, p.backwards_stamp),
        fixtype_path(ft_path) {
    beginReport(pos_report, pos_path);
    if (fixtype_path.empty()) return;
    beginReport(fixtype_report, fixtype_path);
    fixtype.emplace(TextTableReader::streaming(fixtype_path, chunk_bytes));
    matcher.emplace(fixtype_path, policy, fixtype_report,
                    [this](GnssFixTypeRecord* rec) { return nextRecord(rec); });
  }
  bool nextRecord(GnssFixTypeRecord* rec) {
    while (fixtype->next()) {
      if (parseFixTypeLine(*fixtype, fixtype_order, fixtype_report, rec)) {
        ++fixtype_report.records_kept;
        return true;
      }
    }
    if (fixtype_report.records_kept == 0)
      throw std::runtime_error(fixtype_path + ": no epochs in the fix type file");
    return false;
  }

  const GnssReadPolicy policy;
  TextTableReader pos;
  TimeOrderGuard pos_order, fixtype_order;
  const std::string fixtype_path;
  std::optional<TextTableReader> fixtype;
  ReadReport pos_report, fixtype_report;
  std::optional<FixTypeMatcher> matcher;
  bool ended = false;
};

GnssStreamReader::GnssStreamReader(const std::string& pos_path, const std::string& fixtype_path,
                                   const GnssReadPolicy& policy, std::size_t chunk_bytes) {
  policy.validate();
  state_ = std::make_unique<State>(pos_path, fixtype_path, policy, chunk_bytes);
}

GnssStreamReader::~GnssStreamReader() = default;

bool GnssStreamReader::next(GnssFix* fix) {
  State& st = *state_;
  if (st.ended) return false;
  while (st.pos.next()) {
    if (!parsePosLine(st.pos, st.policy, st.pos_order, st.pos_report, fix)) continue;
    ++st.pos_report.records_kept;
    if (st.matcher) st.matcher->match(*fix);
    return true;
  }
  st.ended = true;
  if (st.pos_report.records_kept == 0)
    throw std::runtime_error(st.pos_report.path + ": no GNSS epochs in the file");
  if (st.matcher) st.matcher->finish();
  return false;
}

std::vector<ReadReport> GnssStreamReader::reports() const {
  std::vector<ReadReport> r{state_->pos_report};
  if (state_->matcher) r.push_back(state_->fixtype_report);
  return r;
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

#include "graftnav/io/imu_io.h"

#include <fmt/format.h>

#include <algorithm>
#include <charconv>
#include <cstdio>
#include <memory>
#include <cmath>
#include <iterator>
#include <stdexcept>
#include <vector>

#include "graftnav/io/atomic_file.h"
#include "graftnav/nav/units.h"
#include "graftnav/io/file_errors.h"

namespace graftnav {

ImuReadPolicy ImuReadPolicy::real() {
  ImuReadPolicy p;
  p.uneven_interval = ReadRule::kWarn;
  p.gap = ReadRule::kWarn;
  p.duplicate_stamp = ReadRule::kRepair;
  p.backwards_stamp = ReadRule::kRepair;
  return p;
}

void ImuReadPolicy::validate() const {
  requireRule(uneven_interval, {ReadRule::kError, ReadRule::kWarn},
              "ImuReadPolicy.uneven_interval");
  requireRule(gap, {ReadRule::kError, ReadRule::kWarn}, "ImuReadPolicy.gap");
  requireRule(duplicate_stamp, {ReadRule::kError, ReadRule::kRepair},
              "ImuReadPolicy.duplicate_stamp");
  requireRule(backwards_stamp, {ReadRule::kError, ReadRule::kRepair},
              "ImuReadPolicy.backwards_stamp");
  if (!(uneven_tolerance > 0.0) || !std::isfinite(uneven_tolerance))
    throw std::invalid_argument("ImuReadPolicy.uneven_tolerance must be > 0, got " +
                                std::to_string(uneven_tolerance));
  if (!(gap_factor > 1.0) || !std::isfinite(gap_factor))
    throw std::invalid_argument("ImuReadPolicy.gap_factor must be > 1, got " +
                                std::to_string(gap_factor));
  if (!(max_gyro_rate_deg_s > 0.0) || !std::isfinite(max_gyro_rate_deg_s))
    throw std::invalid_argument("ImuReadPolicy.max_gyro_rate_deg_s must be > 0, got " +
                                std::to_string(max_gyro_rate_deg_s));
  if (!(max_accel_g > 0.0) || !std::isfinite(max_accel_g))
    throw std::invalid_argument("ImuReadPolicy.max_accel_g must be > 0, got " +
                                std::to_string(max_accel_g));
}

namespace {
const char* const kImuColumns[] = {"time",   "dtheta_x", "dtheta_y", "dtheta_z",
                                   "dvel_x", "dvel_y",   "dvel_z",   "temperature"};

std::string fmtDt(double dt_s, double nominal_s) {
  return fmt::format("dt {:.6f} s = {:.3f} x nominal {:.6f} s", dt_s, dt_s / nominal_s, nominal_s);
}

// Parses the reader's current line into *s. Returns false when the time-order rules drop it.
bool parseImuLine(TextTableReader& reader, int& first_column_count, TimeOrderGuard& order,
                  ReadReport& report, ImuSample* s) {
  ++report.data_lines;
  reader.requireColumns(7, 8, "IMU");
  if (first_column_count == 0) first_column_count = reader.columnCount();
  if (reader.columnCount() != first_column_count)
    reader.fail("IMU line has " + std::to_string(reader.columnCount()) +
                " columns but line 1 of the data has " + std::to_string(first_column_count) +
                " (temperature column must be all or none)");
  reader.requireFinite(kImuColumns);
  const double* v = reader.values();
  if (!order.accept(reader, v[0], 0, report)) return false;
  *s = ImuSample{};
  s->t_s = v[0];
  s->dtheta_rad = Eigen::Vector3d(v[1], v[2], v[3]);
  s->dvel_m_s = Eigen::Vector3d(v[4], v[5], v[6]);
  if (reader.columnCount() == 8) s->temperature_degC = v[7];
  return true;
}

// The gap and uneven-interval rules for the interval dt ending at `line` (after time t_prev_s).
void checkInterval(const std::string& path, int line, double dt, double t_prev_s, double nominal_s,
                   const ImuReadPolicy& policy, ReadReport& report) {
  if (dt > policy.gap_factor * nominal_s) {
    const std::string what =
        "gap: " + fmtDt(dt, nominal_s) + " after time " + fmt::format("{:.6f}", t_prev_s);
    if (policy.gap == ReadRule::kError)
      throw std::runtime_error(path + ":" + std::to_string(line) + ": " + what);
    report.note(ReadCondition::kGap, line, what);
  } else if (std::fabs(dt - nominal_s) > policy.uneven_tolerance * nominal_s) {
    const std::string what = "uneven interval: " + fmtDt(dt, nominal_s) + " (tolerance " +
                             fmt::format("{:g}", 100.0 * policy.uneven_tolerance) + " %)";
    if (policy.uneven_interval == ReadRule::kError)
      throw std::runtime_error(path + ":" + std::to_string(line) + ": " + what);
    report.note(ReadCondition::kUnevenInterval, line, what);
  }
}

void validateReadOptions(const std::string& path, const ImuReadOptions& options) {
  options.policy.validate();
  if (!(options.nominal_rate_hz >= 0.0) || !std::isfinite(options.nominal_rate_hz))
    throw std::invalid_argument(path + ": ImuReadOptions.nominal_rate_hz must be >= 0, got " +
                                std::to_string(options.nominal_rate_hz));
}

// Physical range of one sample's increments (ImuReadPolicy.max_*) over dt_s (at least the nominal
// interval): an error naming path:line, column, value. Shared by readImu and ImuBlockReader.
void checkImuRange(const std::string& path, int line, const ImuSample& s, double nominal_s,
                   const ImuReadPolicy& policy) {
  const double max_rate_rad_s = policy.max_gyro_rate_deg_s * units::kDegToRad;
  const double max_accel_m_s2 = policy.max_accel_g * units::kStandardGravity_m_s2;
  const double dt = std::max(s.dt_s, nominal_s);
  for (int a = 0; a < 3; ++a) {
    const double w = s.dtheta_rad[a], v = s.dvel_m_s[a];
    if (std::fabs(w) > max_rate_rad_s * dt)
      throw std::runtime_error(fmt::format(
          "{}:{}: {} {:g} rad over {:g} s is {:.4g} deg/s, beyond the physical limit {:g} deg/s "
          "(corrupted or mis-scaled value)",
          path, line, kImuColumns[1 + a], w, dt, std::fabs(w) / dt / units::kDegToRad,
          policy.max_gyro_rate_deg_s));
    if (std::fabs(v) > max_accel_m_s2 * dt)
      throw std::runtime_error(fmt::format(
          "{}:{}: {} {:g} m/s over {:g} s is {:.4g} g, beyond the physical limit {:g} g "
          "(corrupted or mis-scaled value)",
          path, line, kImuColumns[4 + a], v, dt, std::fabs(v) / dt / units::kStandardGravity_m_s2,
          policy.max_accel_g));
  }
}
}  // namespace

ImuSeries readImu(const std::string& path, const ImuReadOptions& options, ReadReport* report_out) {
  const ImuReadPolicy& policy = options.policy;
  validateReadOptions(path, options);
  ReadReport local_report;
  ReadReport& report = report_out ? *report_out : local_report;
  report = ReadReport{};
  report.path = path;

  // Streamed: the file's text is not held next to the series.
  const std::size_t max_lines = countPhysicalLines(path);
  TextTableReader reader = TextTableReader::streaming(path);
  ImuSeries imu;
  std::vector<int> lines;  // line number of each kept sample, for messages of the interval checks
  imu.reserve(max_lines);
  lines.reserve(max_lines);
  TimeOrderGuard order(policy.duplicate_stamp, policy.backwards_stamp);
  int first_column_count = 0;
  ImuSample s;
  while (reader.next()) {
    if (!parseImuLine(reader, first_column_count, order, report, &s)) continue;
    imu.push_back(s);
    lines.push_back(reader.lineNumber());
  }
  if (imu.empty()) throw std::runtime_error(path + ": no IMU samples in the file");
  if (imu.size() < 2 && options.nominal_rate_hz <= 0.0)
    throw std::runtime_error(path +
                             ": a single IMU sample and no nominal rate: its interval is unknown");

  for (std::size_t k = 1; k < imu.size(); ++k) imu[k].dt_s = imu[k].t_s - imu[k - 1].t_s;
  double nominal_s;
  if (options.nominal_rate_hz > 0.0) {
    nominal_s = 1.0 / options.nominal_rate_hz;
  } else {
    std::vector<double> dts;
    dts.reserve(imu.size() - 1);
    for (std::size_t k = 1; k < imu.size(); ++k) dts.push_back(imu[k].dt_s);
    std::nth_element(dts.begin(), dts.begin() + dts.size() / 2, dts.end());
    nominal_s = dts[dts.size() / 2];
  }
  imu[0].dt_s = options.nominal_rate_hz > 0.0 ? nominal_s : imu[1].dt_s;

  for (std::size_t k = 0; k < imu.size(); ++k)
    checkImuRange(path, lines[k], imu[k], nominal_s, policy);
  // Interval checks (times already strictly increase).
  for (std::size_t k = 1; k < imu.size(); ++k)
    checkInterval(path, lines[k], imu[k].dt_s, imu[k - 1].t_s, nominal_s, policy, report);
  report.records_kept = static_cast<int>(imu.size());
  return imu;
}

ImuBlockReader::ImuBlockReader(const std::string& path, const ImuReadOptions& options,
                               std::size_t block_samples)
    : options_(options),
      block_samples_(std::max<std::size_t>(block_samples, 1)),
      reader_(TextTableReader::streaming(path)),
      order_(options.policy.duplicate_stamp, options.policy.backwards_stamp) {
  validateReadOptions(path, options);
  if (!(options.nominal_rate_hz > 0.0))
    throw std::invalid_argument(
        path +
        ": ImuBlockReader needs ImuReadOptions.nominal_rate_hz > 0 (the first "
        "interval and the interval checks cannot wait for the whole file)");
  nominal_s_ = 1.0 / options.nominal_rate_hz;
  report_.path = path;
}

bool ImuBlockReader::next(ImuSeries* block) {
  block->clear();
  ImuSample s;
  while (block->size() < block_samples_ && reader_.next()) {
    if (!parseImuLine(reader_, first_column_count_, order_, report_, &s)) continue;
    const bool first = report_.records_kept == 0;
    s.dt_s = first ? nominal_s_ : s.t_s - t_prev_s_;
    checkImuRange(reader_.path(), reader_.lineNumber(), s, nominal_s_, options_.policy);
    if (!first)
      checkInterval(reader_.path(), reader_.lineNumber(), s.dt_s, t_prev_s_, nominal_s_,
                    options_.policy, report_);
    t_prev_s_ = s.t_s;
    ++report_.records_kept;
    block->push_back(s);
  }
  if (block->empty() && report_.records_kept == 0)
    throw std::runtime_error(reader_.path() + ": no IMU samples in the file");
  return !block->empty();
}

double readLastImuTime(const std::string& path) {
  constexpr long kTailBytes = 64 * 1024;
  std::unique_ptr<std::FILE, int (*)(std::FILE*)> f(std::fopen(path.c_str(), "rb"), &std::fclose);
  if (!f) throw MissingFileError(path, path + ": cannot open file (missing or unreadable)");
  if (std::fseek(f.get(), 0, SEEK_END) != 0) throw std::runtime_error(path + ": cannot seek");
  const long size = std::ftell(f.get());
  const long start = std::max(0L, size - kTailBytes);
  std::string tail(static_cast<std::size_t>(size - start), '\0');
  if (std::fseek(f.get(), start, SEEK_SET) != 0 ||
      std::fread(tail.data(), 1, tail.size(), f.get()) != tail.size())
    throw std::runtime_error(path + ": read error in the last " + std::to_string(kTailBytes) +
                             " bytes");
  std::size_t pos = 0;
  if (start > 0)
    pos = tail.find('\n') == std::string::npos ? tail.size() : tail.find('\n') + 1;  // partial line
  bool found = false;
  double t_max = 0.0;
  while (pos < tail.size()) {
    std::size_t end = tail.find('\n', pos);
    if (end == std::string::npos) end = tail.size();
    const char* p = tail.data() + pos;
    const char* e = tail.data() + end;
    while (p < e && (*p == ' ' || *p == '\t')) ++p;
    double t = 0.0;
    if (p < e && *p != '#' && std::from_chars(p, e, t).ec == std::errc() && std::isfinite(t)) {
      t_max = found ? std::max(t_max, t) : t;
      found = true;
    }
    pos = end + 1;
  }
  if (!found)
    throw std::runtime_error(path + ": no IMU data line in the last " + std::to_string(kTailBytes) +
                             " bytes");
  return t_max;
}

void writeImu(const std::string& path, const ImuSeries& imu) {
  if (imu.empty()) throw std::invalid_argument(path + ": writeImu: no samples");
  ImuWriter writer(path);
  for (const ImuSample& s : imu) writer.add(s);
  writer.commit();
}

ImuWriter::ImuWriter(const std::string& path) : file_(std::make_unique<AtomicFile>(path)) {
  buffer_.reserve((1u << 20) + 256);
}

ImuWriter::~ImuWriter() = default;

void ImuWriter::add(const ImuSample& s) {
  const std::string& path = file_->path();
  const std::size_t k = count_;
  if (k == 0) with_temperature_ = s.hasTemperature();
  if (s.hasTemperature() != with_temperature_)
    throw std::invalid_argument(path + ": writeImu: sample " + std::to_string(k) +
                                " differs from sample 0 in having a temperature (all or none)");
  if (!std::isfinite(s.t_s) || !s.dtheta_rad.allFinite() || !s.dvel_m_s.allFinite() ||
      (with_temperature_ && !std::isfinite(s.temperature_degC)))
    throw std::invalid_argument(path + ": writeImu: sample " + std::to_string(k) +
                                " has a non-finite value");
  if (k > 0 && !(s.t_s > prev_.t_s))
    throw std::invalid_argument(path + ": writeImu: sample " + std::to_string(k) + " time " +
                                fmt::format("{:.9f}", s.t_s) + " is not after previous " +
                                fmt::format("{:.9f}", prev_.t_s));
  const auto& a = s.dtheta_rad;
  const auto& v = s.dvel_m_s;
  fmt::format_to(std::back_inserter(buffer_),
                 "{:.9f} {:.16e} {:.16e} {:.16e} {:.16e} {:.16e} {:.16e}", s.t_s, a.x(), a.y(),
                 a.z(), v.x(), v.y(), v.z());
  if (with_temperature_) fmt::format_to(std::back_inserter(buffer_), " {:.4f}", s.temperature_degC);
  buffer_.push_back('\n');
  prev_ = s;
  ++count_;
  if (buffer_.size() > (1u << 20)) {
    file_->write(buffer_);
    buffer_.clear();
  }
}

void ImuWriter::commit() {
  if (count_ == 0) throw std::invalid_argument(file_->path() + ": writeImu: no samples");
  file_->write(buffer_);
  buffer_.clear();
  file_->commit();
}

}  // namespace graftnav

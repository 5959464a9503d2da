#pragma once
// IMU text files (dataset.md): `t dtheta_x dtheta_y dtheta_z dvel_x dvel_y dvel_z [temp_degC]`,
// t = GNSS seconds of week at the END of the interval, increments in rad and m/s, body FRD.
//
// Strict by default: a malformed line, a wrong column count, NaN/inf, a time not after the
// previous one, an uneven interval or a gap is a std::runtime_error "path:line: ...". For real
// recordings, ImuReadPolicy::real() turns the conditions into counted warnings or repairs that are
// listed in a ReadReport (see docs/io.md).

#include <memory>
#include <string>

#include "graftnav/io/text_table.h"
#include "graftnav/nav/types.h"

namespace graftnav {

struct ImuReadPolicy {
  // |dt - nominal| > uneven_tolerance * nominal (and not a gap): kError or kWarn (kept as is;
  // dt_s is the actual interval).
  ReadRule uneven_interval = ReadRule::kError;
  double uneven_tolerance = 0.05;
  // dt > gap_factor * nominal: kError or kWarn (kept; the sample after the gap carries dt_s = gap,
  // its increments are whatever the file says; nothing is interpolated).
  ReadRule gap = ReadRule::kError;
  double gap_factor = 1.5;
  // Time equal to the previous: kError or kRepair (drop an identical line; differing = error).
  ReadRule duplicate_stamp = ReadRule::kError;
  // Time before the previous: kError or kRepair (drop the line, at most 100 in a row).
  ReadRule backwards_stamp = ReadRule::kError;
  // Physical range of an increment divided by its interval (max(dt_s, nominal interval)), per
  // axis; beyond it the line is an input error under every policy (a corrupted or mis-scaled
  // value, not a motion). 1e4 deg/s and 100 g lie far above the range of any navigation IMU
  // (MEMS gyros saturate at 2000-4000 deg/s, accelerometers at 16-50 g), so they never reject a
  // real recording but catch a 1e300 before it turns into a NaN solution.
  double max_gyro_rate_deg_s = 1e4;
  double max_accel_g = 100.0;

  static ImuReadPolicy strict() { return {}; }
  // For real recordings: warn on uneven intervals and gaps, repair duplicates and backwards stamps.
  static ImuReadPolicy real();
  // Throws std::invalid_argument naming the field when a rule does not fit its condition.
  void validate() const;
};

struct ImuReadOptions {
  // Nominal sample rate; 0 = unknown, then the nominal interval is the median interval of the file.
  // The first sample's dt_s is 1/nominal_rate_hz when given, else the file's second interval.
  double nominal_rate_hz = 0.0;
  ImuReadPolicy policy;
};

// Reads an IMU file. Fills *report (when given) with counts and examples of every condition met.
// Throws std::runtime_error naming path, line and value on any error (missing file, empty file,
// malformed line, column count not 7/8, NaN/inf, and the conditions whose rule is kError).
ImuSeries readImu(const std::string& path, const ImuReadOptions& options = {},
                  ReadReport* report = nullptr);

// Reads an IMU file in blocks of at most block_samples samples, in a chunk of text at a time:
// memory does not grow with the file. The samples, their dt_s and the report equal readImu's for
// the same options; options.nominal_rate_hz must be > 0 (std::invalid_argument otherwise), since
// the first interval and the interval checks cannot wait for the file's median interval. Errors
// are thrown as readImu throws them, when the block holding the offending line is read (so a
// caller may have processed earlier blocks already).
class ImuBlockReader {
 public:
  ImuBlockReader(const std::string& path, const ImuReadOptions& options,
                 std::size_t block_samples = 4096);
  // Replaces *block with the next samples; returns false (block empty) at the end of the file.
  // Throws std::runtime_error "path: no IMU samples in the file" when the file holds none.
  bool next(ImuSeries* block);
  // Counts so far; complete once next() has returned false.
  const ReadReport& report() const { return report_; }

 private:
  ImuReadOptions options_;
  std::size_t block_samples_;
  TextTableReader reader_;
  TimeOrderGuard order_;
  ReadReport report_;
  double nominal_s_ = 0.0;
  double t_prev_s_ = 0.0;
  int first_column_count_ = 0;
};

// Time of the last sample readImu would return, from the file's last 64 KiB only: the largest
// time among the data lines there (a line the repair rule drops is never later than the last
// kept one, and at most 100 are dropped in a row). For the span of a recording that is streamed.
// Throws std::runtime_error naming the path when the file cannot be read or its tail holds no
// data line.
double readLastImuTime(const std::string& path);

// Writes an IMU file atomically: time %.9f, increments %.16e (17 significant digits: exact round
// trip), temperature %.4f as an 8th column when every sample has one (all or none, else throws
// std::invalid_argument). Throws std::invalid_argument on non-finite values or times not strictly
// increasing (naming the sample index), std::runtime_error on I/O failure.
void writeImu(const std::string& path, const ImuSeries& imu);

class AtomicFile;
// writeImu one sample at a time, for a recording that is not held in memory (the streamed
// simulator): the same checks (named by the sample's index) and byte-identical text. The file
// appears at the destination only on commit(); if an exception leaves it uncommitted, the
// destination keeps its previous content.
class ImuWriter {
 public:
  explicit ImuWriter(const std::string& path);  // throws std::runtime_error like AtomicFile
  ~ImuWriter();
  ImuWriter(const ImuWriter&) = delete;
  ImuWriter& operator=(const ImuWriter&) = delete;
  void add(const ImuSample& s);
  void commit();  // throws std::invalid_argument when no sample was added
  std::size_t count() const { return count_; }

 private:
  std::unique_ptr<AtomicFile> file_;
  std::string buffer_;
  ImuSample prev_;
  bool with_temperature_ = false;
  std::size_t count_ = 0;
};

}  // namespace graftnav

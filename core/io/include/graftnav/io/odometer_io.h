#pragma once
// The wheel odometer file field/odometer.txt (dataset.md): `sow speed_m_s` per line, the forward
// speed at the odometer's lever arm in m/s, at any rate, in time order. Read as a stream like
// GNSS (one sample at a time, memory not growing with the file) or whole. Strict: a malformed
// line, a column count other than 2, a non-finite value, a time not after the previous one, a
// speed outside the range of the options, or a negative speed when the vehicle drives forward
// only, is a std::runtime_error "path:line: ...".
#include <cstddef>
#include <memory>
#include <string>
#include <vector>

#include "graftnav/estimation/vehicle_aiding.h"
#include "graftnav/io/text_table.h"
#include "graftnav/nav/time_window.h"

namespace graftnav {

struct OdometerReadOptions {
  // The vehicle drives forward only (odometer.forward_only of the run config): a negative speed
  // is an input error. False: a signed speed, reversing allowed.
  bool forward_only = true;
  // Speeds beyond this (m/s) are input errors, not motion: a land vehicle's odometer does not
  // read 360 km/h; a mis-scaled column (pulses, km/h) does.
  double max_speed_m_s = 100.0;
  void validate() const;  // throws std::invalid_argument naming the field
};

// What is wrong with a forward speed under these options ("" when nothing is): negative when the
// vehicle drives forward only, or beyond max_speed_m_s. `speed_text` is the speed as the user wrote
// it, for the message. The one rule for the file reader and for odometer arrays.
std::string odometerSpeedProblem(double speed_m_s, const std::string& speed_text,
                                 const OdometerReadOptions& options);

// The whole file. Throws as the stream reader, and "path: no odometer samples" for none.
OdometerSeries readOdometer(const std::string& path, const OdometerReadOptions& options = {},
                            ReadReport* report = nullptr);

// One sample at a time (an OdometerSource for EstimationProblem::odometer_stream).
class OdometerStreamReader final : public OdometerSource {
 public:
  OdometerStreamReader(const std::string& path, const OdometerReadOptions& options = {},
                       std::size_t chunk_bytes = std::size_t{1} << 16);
  bool next(OdometerSample* sample) override;
  const ReadReport& report() const { return report_; }

 private:
  OdometerReadOptions options_;
  TextTableReader reader_;
  TimeOrderGuard order_;
  ReadReport report_;
};

// Opens a new streamed pass over the file at each call (EstimationProblem::odometer_stream).
OdometerOpenFn odometerFileStream(const std::string& path, const OdometerReadOptions& options);

// The parts of [t_begin_s, t_end_s] (the IMU's span) where the odometer gives no speed: before
// its first sample, after its last, and inside gaps between samples longer than max_gap_s.
// Empty when the odometer covers the span.
std::vector<TimeWindow> odometerUncoveredSpans(OdometerSource& samples, double t_begin_s,
                                               double t_end_s, double max_gap_s);
// A warning naming the file and listing the spans (at most 10, then a count); empty when none.
std::string odometerCoverageWarning(const std::string& path, const std::vector<TimeWindow>& spans,
                                    double t_begin_s, double t_end_s);

// Writes the file atomically: time %.6f, speed %.6f m/s. Throws std::invalid_argument on a
// non-finite value or times not strictly increasing (naming the sample index).
void writeOdometer(const std::string& path, const OdometerSeries& samples);

}  // namespace graftnav

#include "graftnav/io/odometer_io.h"

#include <fmt/format.h>

#include <cmath>
#include <iterator>
#include <stdexcept>

#include "graftnav/io/atomic_file.h"

namespace graftnav {

namespace {
const char* const kOdometerColumns[] = {"time", "speed"};
}  // namespace

void OdometerReadOptions::validate() const {
  if (!(max_speed_m_s > 0.0) || !std::isfinite(max_speed_m_s))
    throw std::invalid_argument("OdometerReadOptions.max_speed_m_s must be > 0, got " +
                                std::to_string(max_speed_m_s));
}

std::string odometerSpeedProblem(double speed_m_s, const std::string& speed_text,
                                 const OdometerReadOptions& options) {
  if (options.forward_only && speed_m_s < 0.0)
    return "speed " + speed_text +
           " m/s is negative, but the odometer is forward only (odometer.forward_only)";
  if (std::abs(speed_m_s) > options.max_speed_m_s)
    return "speed " + speed_text + " m/s is beyond " + fmt::format("{:g}", options.max_speed_m_s) +
           " m/s (a mis-scaled column? the file is m/s)";
  return "";
}

OdometerStreamReader::OdometerStreamReader(const std::string& path,
                                           const OdometerReadOptions& options,
                                           std::size_t chunk_bytes)
    : options_(options),
      reader_(TextTableReader::streaming(path, chunk_bytes)),
      order_(ReadRule::kError, ReadRule::kError) {
  options_.validate();
  report_.path = path;
}

bool OdometerStreamReader::next(OdometerSample* sample) {
  while (reader_.next()) {
    ++report_.data_lines;
    reader_.requireColumns(2, 2, "odometer");
    reader_.requireFinite(kOdometerColumns);
    const double t = reader_.value(0), v = reader_.value(1);
    order_.accept(reader_, t, 0, report_);  // strict: throws on a repeated or earlier time
    const std::string problem = odometerSpeedProblem(v, std::string(reader_.token(1)), options_);
    if (!problem.empty()) reader_.fail(problem);
    sample->t_s = t;
    sample->speed_m_s = v;
    ++report_.records_kept;
    return true;
  }
  if (report_.records_kept == 0) throw std::runtime_error(report_.path + ": no odometer samples");
  return false;
}

OdometerSeries readOdometer(const std::string& path, const OdometerReadOptions& options,
                            ReadReport* report) {
  OdometerStreamReader reader(path, options, std::size_t{1} << 20);
  OdometerSeries out;
  OdometerSample s;
  while (reader.next(&s)) out.push_back(s);
  if (report) *report = reader.report();
  return out;
}

OdometerOpenFn odometerFileStream(const std::string& path, const OdometerReadOptions& options) {
  return [path, options]() -> std::unique_ptr<OdometerSource> {
    return std::make_unique<OdometerStreamReader>(path, options);
  };
}

std::vector<TimeWindow> odometerUncoveredSpans(OdometerSource& samples, double t_begin_s,
                                               double t_end_s, double max_gap_s) {
  std::vector<TimeWindow> spans;
  auto add = [&](double a, double b) {  // [a, b] clipped to the span
    a = std::max(a, t_begin_s);
    b = std::min(b, t_end_s);
    if (b > a) spans.push_back({a, b});
  };
  OdometerSample s;
  bool any = false;
  double t_prev = 0.0;
  while (samples.next(&s)) {
    if (!any) {
      add(-INFINITY, s.t_s);
    } else if (s.t_s - t_prev > max_gap_s) {
      add(t_prev, s.t_s);
    }
    any = true;
    t_prev = s.t_s;
  }
  if (!any) {
    add(t_begin_s, t_end_s);
  } else {
    add(t_prev, INFINITY);
  }
  return spans;
}

std::string odometerCoverageWarning(const std::string& path, const std::vector<TimeWindow>& spans,
                                    double t_begin_s, double t_end_s) {
  if (spans.empty()) return {};
  double total = 0.0;
  for (const TimeWindow& w : spans) total += w.length_s();
  std::string msg = fmt::format(
      "WARNING: {} does not cover the IMU span {:.3f} .. {:.3f} s: no odometer speed in {} "
      "span(s), {:.3f} s in all:",
      path, t_begin_s, t_end_s, spans.size(), total);
  for (std::size_t i = 0; i < spans.size() && i < 10; ++i)
    msg += fmt::format(" {:.3f} .. {:.3f}", spans[i].start_s, spans[i].end_s);
  if (spans.size() > 10) msg += fmt::format(" (and {} more)", spans.size() - 10);
  return msg;
}

void writeOdometer(const std::string& path, const OdometerSeries& samples) {
  fmt::memory_buffer buf;
  for (std::size_t k = 0; k < samples.size(); ++k) {
    const OdometerSample& s = samples[k];
    if (!std::isfinite(s.t_s) || !std::isfinite(s.speed_m_s))
      throw std::invalid_argument(path + ": writeOdometer: sample " + std::to_string(k) +
                                  " has a non-finite value");
    if (k > 0 && !(s.t_s > samples[k - 1].t_s))
      throw std::invalid_argument(path + ": writeOdometer: sample " + std::to_string(k) + " time " +
                                  fmt::format("{:.6f}", s.t_s) + " is not after the previous");
    fmt::format_to(std::back_inserter(buf), "{:.6f} {:.6f}\n", s.t_s, s.speed_m_s);
  }
  if (samples.empty()) throw std::invalid_argument(path + ": writeOdometer: no samples");
  writeFileAtomically(path, std::string_view(buf.data(), buf.size()));
}

}  // namespace graftnav

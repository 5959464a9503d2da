#include "graftnav/io/imu_recording.h"

#include <algorithm>
#include <array>
#include <memory>
#include <stdexcept>
#include <utility>
#include <vector>

#include "graftnav/io/record_spool.h"

namespace graftnav {
namespace {

constexpr std::size_t kImuDoubles = 9;  // t, dt, dtheta (3), dvel (3), temperature

std::array<double, kImuDoubles> toRecord(const ImuSample& s) {
  return {s.t_s,          s.dt_s,         s.dtheta_rad.x(), s.dtheta_rad.y(),  s.dtheta_rad.z(),
          s.dvel_m_s.x(), s.dvel_m_s.y(), s.dvel_m_s.z(),   s.temperature_degC};
}

ImuSample fromRecord(const double* r) {
  ImuSample s;
  s.t_s = r[0];
  s.dt_s = r[1];
  s.dtheta_rad = {r[2], r[3], r[4]};
  s.dvel_m_s = {r[5], r[6], r[7]};
  s.temperature_degC = r[8];
  return s;
}

}  // namespace

ImuRecording heldRecording(ImuSeries series) {
  if (series.empty()) throw std::invalid_argument("heldRecording: the IMU series is empty");
  auto held = std::make_shared<const ImuSeries>(std::move(series));
  ImuRecording r;
  r.first = held->front();
  r.last = held->back();
  r.samples = held->size();
  r.pass = [held](const ImuBlockFn& block) { block(*held); };
  return r;
}

ImuRecording viewedRecording(const ImuSeries& series) {
  if (series.empty()) throw std::invalid_argument("viewedRecording: the IMU series is empty");
  ImuRecording r;
  r.first = series.front();
  r.last = series.back();
  r.samples = series.size();
  r.pass = [&series](const ImuBlockFn& block) { block(series); };
  return r;
}

ImuSeries collectRecording(const ImuRecording& recording) {
  ImuSeries out;
  out.reserve(recording.samples);
  recording.pass([&out](const ImuSeries& b) { out.insert(out.end(), b.begin(), b.end()); });
  return out;
}

ImuRecording spooledRecording(const ImuPassFn& source, std::size_t block_samples) {
  auto spool = std::make_shared<RecordSpool>(kImuDoubles);
  ImuRecording r;
  source([&](const ImuSeries& block) {
    for (const ImuSample& s : block) {
      if (spool->size() == 0) r.first = s;
      spool->append(toRecord(s).data());
    }
    if (!block.empty()) r.last = block.back();
  });
  spool->finish();
  if (spool->size() == 0) throw std::invalid_argument("spooledRecording: the IMU pass is empty");
  r.samples = spool->size();
  const std::size_t n = std::max<std::size_t>(1, block_samples);
  std::shared_ptr<const RecordSpool> read_only = spool;
  r.pass = [read_only, n](const ImuBlockFn& block) {
    std::vector<double> raw;
    ImuSeries samples;
    for (std::size_t i = 0; i < read_only->size(); i += n) {
      const std::size_t count = std::min(n, read_only->size() - i);
      read_only->read(i, count, &raw);
      samples.resize(count);
      for (std::size_t k = 0; k < count; ++k) samples[k] = fromRecord(&raw[k * kImuDoubles]);
      block(samples);
    }
  };
  return r;
}

}  // namespace graftnav

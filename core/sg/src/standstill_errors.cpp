#include "graftnav/sg/standstill_errors.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "graftnav/nav/earth.h"
#include "graftnav/nav/rotation.h"

namespace graftnav {

StaticDetectorOptions StandstillOptions::defaultDetector() {
  StaticDetectorOptions d;
  d.gyro_threshold_rad_s = 0.05;
  d.accel_threshold_m_s2 = 0.3;
  d.min_duration_s = 2.0;
  d.trim_s = 0.5;
  return d;
}

void StandstillOptions::validate() const {
  detector.validate();
  if (!(max_gnss_speed_m_s > 0.0) || !std::isfinite(max_gnss_speed_m_s))
    throw std::invalid_argument("StandstillOptions.max_gnss_speed_m_s must be > 0, got " +
                                std::to_string(max_gnss_speed_m_s));
  if (!(speed_chord_s > 0.0) || !std::isfinite(speed_chord_s))
    throw std::invalid_argument("StandstillOptions.speed_chord_s must be > 0, got " +
                                std::to_string(speed_chord_s));
}

double medianGnssChordSpeed(const GnssSeries& gnss, double t_begin_s, double t_end_s,
                            double chord_s) {
  std::vector<double> speeds;
  for (std::size_t i = 0; i < gnss.size(); ++i) {
    if (gnss[i].t_s < t_begin_s) continue;
    std::size_t j = i + 1;
    while (j < gnss.size() && gnss[j].t_s - gnss[i].t_s < chord_s) ++j;
    if (j >= gnss.size() || gnss[j].t_s > t_end_s) break;
    speeds.push_back(earth::nedFromGeodetic(gnss[i].pos, gnss[j].pos).head<2>().norm() /
                     (gnss[j].t_s - gnss[i].t_s));
  }
  if (speeds.empty()) return 0.0;
  std::nth_element(speeds.begin(), speeds.begin() + speeds.size() / 2, speeds.end());
  return speeds[speeds.size() / 2];
}

StandstillSpans findStandstills(const ImuSeries& imu, const GnssSeries& gnss,
                                const StandstillOptions& options) {
  options.validate();
  StandstillSpans out;
  out.detection = detectStaticIntervals(imu, options.detector);
  for (const auto& sp : out.detection.intervals) {
    if (medianGnssChordSpeed(gnss, sp.t_begin_s, sp.t_end_s, options.speed_chord_s) >
        options.max_gnss_speed_m_s) {
      ++out.dropped_moving;
    } else {
      out.kept.push_back(sp);
    }
  }
  if (out.kept.empty()) {
    throw std::runtime_error("no standstill span found in the tested IMU (" +
                             std::to_string(out.detection.intervals.size()) + " detected, " +
                             std::to_string(out.dropped_moving) + " dropped for their GNSS speed)");
  }
  return out;
}

ImuSeries staticErrorIncrements(const ImuSeries& imu, const std::vector<StaticInterval>& spans,
                                const Geodetic& pos, double yaw_rad) {
  ImuSeries err;
  double t = 0.0;
  const double g = earth::gravityMagnitude(pos);
  for (const auto& sp : spans) {
    Eigen::Vector3d f = Eigen::Vector3d::Zero();
    double T = 0.0;
    for (std::size_t k = sp.begin; k < sp.end; ++k) {
      f += imu[k].dvel_m_s;
      T += imu[k].dt_s;
    }
    f /= T;
    const Eigen::Vector3d f_th = f.normalized() * g;
    const Eigen::Vector2d rp = levelFromSpecificForce(f);
    const Eigen::Matrix3d C_nb =
        quatFromEuler(Eigen::Vector3d(rp.x(), rp.y(), yaw_rad)).toRotationMatrix();
    const Eigen::Vector3d w_th = C_nb.transpose() * earth::omega_ie_n(pos.lat_rad);
    for (std::size_t k = sp.begin; k < sp.end; ++k) {
      ImuSample s = imu[k];
      t += s.dt_s;
      s.t_s = t;
      s.dtheta_rad -= w_th * s.dt_s;
      s.dvel_m_s -= f_th * s.dt_s;
      err.push_back(s);
    }
  }
  return err;
}

}  // namespace graftnav

#include <stdexcept>
#include <string>

#include "graftnav/calibration/basic_error.h"
#include "graftnav/calibration/theoretical_output.h"

namespace graftnav {

BasicErrorExtraction extractBasicErrors(const ImuSeries& imu, const Eigen::Matrix3d& C_nb,
                                        const Geodetic& lab, double gravity_m_s2) {
  if (imu.size() < 2)
    throw std::invalid_argument("extractBasicErrors: need at least 2 samples, got " +
                                std::to_string(imu.size()));
  BasicErrorExtraction r;
  r.omega_ie_b = staticEarthRate_b(C_nb, lab.lat_rad);
  r.f_b = gravity_m_s2 > 0.0 ? staticSpecificForce_b(C_nb, gravity_m_s2)
                             : staticSpecificForce_b(C_nb, lab);
  r.error.resize(imu.size());
  for (std::size_t k = 0; k < imu.size(); ++k) {
    const ImuSample& s = imu[k];
    if (!(s.dt_s > 0.0))
      throw std::invalid_argument("extractBasicErrors: sample " + std::to_string(k) +
                                  " (t = " + std::to_string(s.t_s) + ") has dt_s <= 0");
    ImuSample e = s;
    e.dtheta_rad = s.dtheta_rad - r.omega_ie_b * s.dt_s;
    e.dvel_m_s = s.dvel_m_s - r.f_b * s.dt_s;
    r.error[k] = e;
  }
  const SegmentStats st = segmentStats(r.error, "basic error");
  r.duration_s = st.duration_s;
  r.gyro_mean_rad_s = st.omega_mean_rad_s;
  r.accel_mean_m_s2 = st.f_mean_m_s2;
  r.gyro_std_rad_s = st.omega_std_rad_s;
  r.accel_std_m_s2 = st.f_std_m_s2;
  const double dt_mean = st.duration_s / static_cast<double>(st.count());
  r.gyro_white_noise = st.omega_std_rad_s * std::sqrt(dt_mean);
  r.accel_white_noise = st.f_std_m_s2 * std::sqrt(dt_mean);
  for (int i = 0; i < 3; ++i) {
    r.gyro_D[i] = averagedNoiseLevel(r.gyro_white_noise[i], r.duration_s);
    r.accel_D[i] = averagedNoiseLevel(r.accel_white_noise[i], r.duration_s);
  }
  return r;
}

}  // namespace graftnav

#include <cmath>
#include <stdexcept>

#include "graftnav/calibration/theoretical_output.h"

namespace graftnav {

Eigen::Vector3d staticSpecificForce_b(const Eigen::Matrix3d& C_nb, const Geodetic& lab) {
  return -(C_nb.transpose() * earth::gravity_n(lab));
}

Eigen::Vector3d staticSpecificForce_b(const Eigen::Matrix3d& C_nb, double gravity_m_s2) {
  return C_nb.transpose() * Eigen::Vector3d(0.0, 0.0, -gravity_m_s2);
}

Eigen::Vector3d staticEarthRate_b(const Eigen::Matrix3d& C_nb, double lat_rad) {
  return C_nb.transpose() * earth::omega_ie_n(lat_rad);
}

Eigen::Vector3d SegmentStats::omegaSigmaOfMean() const {
  return omega_std_rad_s / std::sqrt(static_cast<double>(count()));
}
Eigen::Vector3d SegmentStats::fSigmaOfMean() const {
  return f_std_m_s2 / std::sqrt(static_cast<double>(count()));
}

SegmentStats segmentStats(const ImuSeries& imu, std::size_t begin, std::size_t end,
                          const std::string& name) {
  if (end > imu.size() || begin >= end || end - begin < 2)
    throw std::invalid_argument("segmentStats: " + name + ": need at least 2 samples in [" +
                                std::to_string(begin) + ", " + std::to_string(end) + ") of " +
                                std::to_string(imu.size()));
  SegmentStats s;
  s.name = name;
  s.begin = begin;
  s.end = end;
  Eigen::Vector3d sw = Eigen::Vector3d::Zero(), sf = Eigen::Vector3d::Zero();
  Eigen::Vector3d sw2 = Eigen::Vector3d::Zero(), sf2 = Eigen::Vector3d::Zero();
  for (std::size_t k = begin; k < end; ++k) {
    const ImuSample& x = imu[k];
    if (!(x.dt_s > 0.0))
      throw std::invalid_argument("segmentStats: " + name + ": sample " + std::to_string(k) +
                                  " has dt_s <= 0");
    s.duration_s += x.dt_s;
    s.dtheta_sum_rad += x.dtheta_rad;
    s.dvel_sum_m_s += x.dvel_m_s;
    const Eigen::Vector3d w = x.dtheta_rad / x.dt_s, f = x.dvel_m_s / x.dt_s;
    sw += w;
    sf += f;
    sw2 += w.cwiseProduct(w);
    sf2 += f.cwiseProduct(f);
  }
  const double n = static_cast<double>(end - begin);
  s.omega_mean_rad_s = s.dtheta_sum_rad / s.duration_s;
  s.f_mean_m_s2 = s.dvel_sum_m_s / s.duration_s;
  const Eigen::Vector3d mw = sw / n, mf = sf / n;
  s.omega_std_rad_s = ((sw2 / n - mw.cwiseProduct(mw)).cwiseMax(0.0) * n / (n - 1.0)).cwiseSqrt();
  s.f_std_m_s2 = ((sf2 / n - mf.cwiseProduct(mf)).cwiseMax(0.0) * n / (n - 1.0)).cwiseSqrt();
  return s;
}

}  // namespace graftnav

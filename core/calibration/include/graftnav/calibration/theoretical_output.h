#pragma once
// Theoretical output of an IMU at rest in the lab (seed Eq. 15-20) and per-segment statistics of
// recorded increments, the inputs of every lab estimator.
//
// Sign convention: at rest the accelerometers sense the reaction to gravity, i.e. the specific
// force points UP. In NED f_n = -g_n = [0, 0, -g] (the seed's Eq. 18 writes +g; we use the
// physically right sign). So f_b = C_bn f_n: an axis pointing up reads +g.
// Earth rate: omega_ie_b = C_bn omega_ie_n, omega_ie_n = [w_e cos(lat), 0, -w_e sin(lat)].

#include <Eigen/Core>
#include <cstddef>
#include <string>

#include "graftnav/nav/earth.h"
#include "graftnav/nav/types.h"

namespace graftnav {

// Specific force at rest resolved in the body, f_b = -C_nb^T g_n(lab) (m/s^2).
Eigen::Vector3d staticSpecificForce_b(const Eigen::Matrix3d& C_nb, const Geodetic& lab);
// Same with a given gravity magnitude (used when the lab latitude is unknown): f_b = C_nb^T [0,0,-g].
Eigen::Vector3d staticSpecificForce_b(const Eigen::Matrix3d& C_nb, double gravity_m_s2);
// Earth rate resolved in the body, omega_ie_b = C_nb^T omega_ie_n(lat) (rad/s).
Eigen::Vector3d staticEarthRate_b(const Eigen::Matrix3d& C_nb, double lat_rad);

// Mean and spread of a run of samples [begin, end) (end exclusive).
struct SegmentStats {
  std::string name;
  std::size_t begin = 0, end = 0;
  double duration_s = 0.0;                                     // sum of dt_s
  Eigen::Vector3d omega_mean_rad_s = Eigen::Vector3d::Zero();  // sum dtheta / sum dt
  Eigen::Vector3d f_mean_m_s2 = Eigen::Vector3d::Zero();       // sum dvel / sum dt
  Eigen::Vector3d dtheta_sum_rad = Eigen::Vector3d::Zero();
  Eigen::Vector3d dvel_sum_m_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d omega_std_rad_s = Eigen::Vector3d::Zero();  // per-sample std of dtheta/dt
  Eigen::Vector3d f_std_m_s2 = Eigen::Vector3d::Zero();       // per-sample std of dvel/dt
  std::size_t count() const { return end - begin; }
  // Standard deviation of the means assuming white noise: std / sqrt(n).
  Eigen::Vector3d omegaSigmaOfMean() const;
  Eigen::Vector3d fSigmaOfMean() const;
};

// Throws std::invalid_argument (naming `name`) for an empty range, fewer than 2 samples or dt <= 0.
SegmentStats segmentStats(const ImuSeries& imu, std::size_t begin, std::size_t end,
                          const std::string& name);
inline SegmentStats segmentStats(const ImuSeries& imu, const std::string& name) {
  return segmentStats(imu, 0, imu.size(), name);
}

}  // namespace graftnav

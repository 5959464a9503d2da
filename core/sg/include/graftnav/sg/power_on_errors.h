#pragma once
// What one power-on of the tested IMU adds to the lab record's error signal when a grafted
// realization is drawn (sg/realization.h): a change of turn-on bias and a slow bias-wander path.
// Both are zero by default, which leaves grafting exactly the seed's SG#1 / SG#2.

#include <Eigen/Core>
#include <vector>

namespace graftnav {

struct PowerOnErrors {
  using Vec6 = Eigen::Matrix<double, 6, 1>;
  // Constant bias change of this power-on against the lab session: gyro (rad/s), accel (m/s^2).
  Eigen::Vector3d gyro_bias_rad_s = Eigen::Vector3d::Zero();
  Eigen::Vector3d accel_bias_m_s2 = Eigen::Vector3d::Zero();
  // Bias wander [gyro rad/s; accel m/s^2] at field times k * wander_step_s (k = 0, 1, ...),
  // linear in between and held after the last knot; empty: no wander.
  double wander_step_s = 0.0;
  std::vector<Vec6> wander_knots;

  bool empty() const {
    return gyro_bias_rad_s.isZero(0.0) && accel_bias_m_s2.isZero(0.0) && wander_knots.empty();
  }
  // Integral over field time (t0_s, t1_s], seconds since the start of the field record:
  // [dtheta (rad); dvel (m/s)].
  Vec6 integral(double t0_s, double t1_s) const;
  // The bias at field time t_s (rate units), turn-on change plus wander.
  Vec6 rate(double t_s) const;
};

}  // namespace graftnav

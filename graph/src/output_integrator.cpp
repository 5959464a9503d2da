#include "graftnav/graph/output_integrator.h"

#include <stdexcept>
#include <utility>

namespace graftnav {

OutputIntegrator::OutputIntegrator(const LocalFrame& frame, int gnss_week, FgoEpochFn output,
                                   FgoScaleFn scale_output)
    : frame_(frame),
      gnss_week_(gnss_week),
      output_(std::move(output)),
      scale_output_(std::move(scale_output)) {}

void OutputIntegrator::node(double t_s, const NodeValue& x, const PvaSigma* sigma,
                            double scale_std) {
  NavState s = frame_.toNavState(t_s, x.p_w, x.v_w, x.q_wb);
  s.gnss_week = gnss_week_;
  if (sd_) {
    sd_->setState(s);
  } else {
    sd_.emplace(s);
  }
  x_ = x;
  pending_.state = s;
  pending_.sensors.gyro_bias_rad_s = x.bg;
  pending_.sensors.accel_bias_m_s2 = x.ba;
  pending_.sensors.gyro_scale = x.imu_scale.gyro;
  pending_.sensors.accel_scale = x.imu_scale.accel;
  pending_.scale = {x.odometer_scale, scale_std};
  pending_.has_sigma = sigma != nullptr;
  if (sigma) pending_.sigma = *sigma;
}

void OutputIntegrator::sample(const ImuSample& raw) {
  if (!sd_) throw std::logic_error("OutputIntegrator: a sample before the first node");
  ImuSample c = raw;
  c.dtheta_rad -= x_.bg * c.dt_s;
  c.dvel_m_s -= x_.ba * c.dt_s;
  // (raw - b dt) / (1 + s); exact division by one when the graph has no scale factors.
  c.dtheta_rad = c.dtheta_rad.cwiseQuotient(Eigen::Vector3d::Ones() + x_.imu_scale.gyro);
  c.dvel_m_s = c.dvel_m_s.cwiseQuotient(Eigen::Vector3d::Ones() + x_.imu_scale.accel);
  sd_->step(c);
  emit();
  pending_.state = sd_->state();
}

void OutputIntegrator::finish() {
  if (sd_) emit();
}

}  // namespace graftnav

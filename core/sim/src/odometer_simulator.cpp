#include "graftnav/sim/odometer_simulator.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "graftnav/imu/gauss_markov.h"
#include "graftnav/sim/sampling_grid.h"

namespace graftnav {

namespace {
constexpr double kStandstill_m_s = 1e-3;
}  // namespace

void OdometerSimOptions::validate() const {
  auto fail = [](const std::string& what) {
    throw std::invalid_argument("OdometerSimOptions: " + what);
  };
  if (!(rate_hz > 0.0) || !std::isfinite(rate_hz)) fail("rate_hz must be > 0");
  if (!(std::abs(scale_error) < 0.5)) fail("scale_error must be a fraction within +-0.5");
  if (!(noise_std_m_s >= 0.0) || !std::isfinite(noise_std_m_s)) fail("noise_std_m_s must be >= 0");
  if (!(quantization_m_s >= 0.0) || !std::isfinite(quantization_m_s))
    fail("quantization_m_s must be >= 0");
  if (!lever_arm_b_m.allFinite()) fail("lever_arm_b_m must be finite");
  if (!mounting_rad.allFinite()) fail("mounting_rad must be finite");
}

Eigen::Vector3d odometerPointVelocity_v(const TrajectoryPoint& p, const Eigen::Matrix3d& C_vb,
                                        const Eigen::Vector3d& lever_arm_b_m) {
  return C_vb * (p.C_nb.transpose() * p.v_n + p.omega_nb_b.cross(lever_arm_b_m));
}

OdometerSeries simulateOdometer(const Trajectory& trj, double t_begin_s, double t_end_s,
                                const OdometerSimOptions& opt, uint64_t seed) {
  opt.validate();
  VehicleAidingOptions geometry;
  geometry.odometer.mounting_rad = opt.mounting_rad;
  const Eigen::Matrix3d C_vb = geometry.C_vb();
  StandardNormalSampler rng(deriveStreamSeed(seed, 101));
  OdometerSeries out;
  for (const double t : uniformEpochs_s(t_begin_s, t_end_s, opt.rate_hz)) {
    const Eigen::Vector3d v_v = odometerPointVelocity_v(trj.at(t), C_vb, opt.lever_arm_b_m);
    double s = (1.0 + opt.scale_error) * v_v.x();
    const double noise = opt.add_noise ? opt.noise_std_m_s * rng.next() : 0.0;
    if (std::abs(v_v.x()) >= kStandstill_m_s) s += noise;  // a wheel at rest gives no pulse
    if (opt.quantization_m_s > 0.0) s = opt.quantization_m_s * std::round(s / opt.quantization_m_s);
    if (opt.forward_only) s = std::max(s, 0.0);
    out.push_back({t, s});
  }
  return out;
}

}  // namespace graftnav

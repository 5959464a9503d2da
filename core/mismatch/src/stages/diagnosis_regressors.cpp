// The finder's regressor stage: what the candidate library is built from. The reference as the
// lab-calibrated tested IMU responds to it (what a time offset shifts), the temperatures, the
// attitude for the Earth terms, and the motion regressors at a time_offset pivot.
#include <fmt/core.h>

#include <cmath>
#include <string>
#include <utility>

#include "diagnosis_stages.h"
#include "graftnav/nav/earth.h"
#include "graftnav/nav/nav_interp.h"
#include "graftnav/nav/rotation.h"

namespace graftnav::diagnosis_detail {

namespace {

std::vector<Eigen::Matrix3d> attitudeAlongGrid(const BinnedImu& x, const NavState& init,
                                               const NavSeries& attitude) {
  std::vector<Eigen::Matrix3d> C_bn(x.size());
  if (!attitude.empty()) {
    for (int i = 0; i < x.size(); ++i) {
      const std::optional<NavState> s = interpolateNav(attitude, x.grid.binMid(i), 1.0);
      const Eigen::Quaterniond q =
          s ? s->q_nb
            : (x.grid.binMid(i) < attitude.front().t_s ? attitude.front().q_nb
                                                       : attitude.back().q_nb);
      C_bn[i] = q.normalized().toRotationMatrix().transpose();
    }
    return C_bn;
  }
  // Integrated from the initial attitude: C_nb' = C_nb [omega_nb x], omega_nb = omega_ib - C_bn
  // omega_ie_n (the transport rate, ~v/R, is left out).
  const Eigen::Vector3d w_ie_n = earth::omega_ie_n(init.pos.lat_rad);
  Eigen::Matrix3d C_nb = init.q_nb.normalized().toRotationMatrix();
  for (int i = 0; i < x.size(); ++i) {
    const Eigen::Vector3d w = x.omega_rad_s.row(i).transpose() - C_nb.transpose() * w_ie_n;
    const Eigen::Matrix3d half = dcmFromRotationVector(0.5 * w * x.grid.bin_s);
    C_bn[i] = (C_nb * half).transpose();  // at the bin middle
    C_nb = C_nb * half * half;
  }
  return C_bn;
}

// What the time offset shifts: the reference as the tested IMU's lab-calibrated response sees
// it, M x + c2 x^2 per sample (SensorPriors::lab_M, lab_quadratic); empty (the reference itself)
// without a lab calibration. Without the quadratic the shift's slope on z missed 2 c2_z f_z
// (-0.7 % at c2_z 3.4e-4 per m/s^2): with a 20-ms offset on road vibration that remainder was
// claimed as a -0.5 % z scale factor (random_15_18).
ImuSampleMap labResponseOfReference(const DiagnosisInputs& in) {
  PerSensor<Eigen::Matrix3d> M;
  PerSensor<Eigen::Vector3d> c2;
  bool any = false;
  for (const Sensor s : kSensors) {
    const SensorPriors& prior = in.priors[s];
    any |= prior.lab_M.has_value() || prior.lab_quadratic.has_value();
    M[s] = prior.lab_M.value_or(Eigen::Matrix3d::Identity());
    c2[s] = prior.lab_quadratic ? prior.lab_quadratic->c2 : Eigen::Vector3d::Zero();
  }
  if (!any) return {};
  return [M, c2](const ImuSample& raw) {
    ImuSample smp = raw;
    const Eigen::Vector3d dtheta = smp.dtheta_rad, dvel = smp.dvel_m_s;
    smp.dtheta_rad = M[Sensor::gyro] * dtheta;
    smp.dvel_m_s = M[Sensor::accel] * dvel;
    if (!(smp.dt_s > 0.0)) return smp;  // no mean rate to bend (binImu skips such samples)
    // Increments: the quadratic acts on the sample's mean rate, times its length.
    smp.dtheta_rad += smp.dt_s * c2[Sensor::gyro].cwiseProduct((dtheta / smp.dt_s).cwiseAbs2());
    smp.dvel_m_s += smp.dt_s * c2[Sensor::accel].cwiseProduct((dvel / smp.dt_s).cwiseAbs2());
    return smp;
  };
}

}  // namespace

std::vector<Eigen::Matrix3d> attitudeOnGrid(const DiagnosisInputs& in, const ResidualBins& bins) {
  if (!(in.initial_state && in.reference_is_simulated)) return {};
  if (in.attitude.empty() && in.read_attitude)
    return attitudeAlongGrid(bins.x, *in.initial_state, in.read_attitude());
  return attitudeAlongGrid(bins.x, *in.initial_state, in.attitude);
}

RegressorState initialRegressors(const DiagnosisInputs& in, const ResidualBins& bins,
                                 double pivot_s, std::vector<Eigen::Matrix3d> C_bn,
                                 std::vector<std::string>* notes) {
  RegressorState reg;
  reg.lab_response = labResponseOfReference(in);
  RegressorInputs& ri = reg.ri;
  const SensorPriors& gyro = in.priors[Sensor::gyro];
  const SensorPriors& accel = in.priors[Sensor::accel];
  if (accel.lab_M) ri.accel_response_M = *accel.lab_M;
  if (accel.lab_quadratic) ri.accel_response_c2 = accel.lab_quadratic->c2;
  if (gyro.lab_quadratic) ri.gyro_response_c2 = gyro.lab_quadratic->c2;
  ri.tested_temperature_degC = bins.y.temperature_degC;
  if (bins.s.temperature_degC.allFinite()) {
    ri.simulated_temperature_degC = bins.s.temperature_degC;
    notes->push_back(
        "the simulation carries a temperature history: temperature_bias is fitted "
        "on tested minus simulated temperature");
  }
  buildMotionRegressors(in, bins, pivot_s, &reg, notes);
  if (in.initial_state && in.reference_is_simulated) {
    ri.C_bn = std::move(C_bn);
    ri.omega_ie_n = earth::omega_ie_n(in.initial_state->pos.lat_rad);
  } else {
    notes->push_back(
        in.reference_is_simulated
            ? "no initial attitude: earth_rotation_omitted and gravity_model not tested"
            : "the reference signals are a recording (they carry the Earth's rotation "
              "and the true gravity): earth_rotation_omitted and gravity_model not tested");
  }
  return reg;
}

// The motion regressors (every term built from the reference signal) from the reference as the
// tested IMU moved, x(t - pv) at the time_offset pivot pv: road vibration decorrelates within
// milliseconds (a 3.9-ms offset left a lever arm 6 % short at 23 sigma when they were built at
// t), and the joint fit shifts them by tau - pv only. The specific force at the tested IMU, whose
// vibration its accelerometer rectifies and which its gyros' g-sensitivity reads, is the
// reference's or, once a lever arm is fitted, the reference's moved to the tested IMU by it.
void buildMotionRegressors(const DiagnosisInputs& in, const ResidualBins& bins, double pv,
                           RegressorState* reg, std::vector<std::string>* notes) {
  const GridSpec& grid = bins.grid;
  if (pv == reg->motion_pivot_s) return;
  const bool first = std::isnan(reg->motion_pivot_s);
  reg->motion_pivot_s = pv;
  RegressorInputs& ri = reg->ri;
  const ImuSeries& tested_f = reg->testedForce(in);
  GridSpec shifted = grid;
  shifted.t_begin_s -= pv;
  ri.reference = pv == 0.0 ? bins.x : binImu(in.reference, grid, -pv);
  ri.even_powers = binEvenPowers(in.reference, grid, -pv);
  const AngularAccelerationBins wdot = angularAccelerationPerBin(in.reference, shifted);
  ri.omega_dot_rad_s2 = wdot.omega_dot_rad_s2;
  ri.vibration_f_hp_sq =
      vibrationLevelPerBin(tested_f, shifted, variantName(TermVariant::specific_force_hp_sq));
  ri.g_sensitivity_f_m_s2 =
      reg->at_tested_imu.empty() ? Eigen::MatrixX3d() : binImu(tested_f, grid, -pv).f_m_s2;
  ri.vibration_w_hp_sq =
      vibrationLevelPerBin(in.reference, shifted, variantName(TermVariant::angular_rate_hp_sq));
  if (!first) return;  // the windows do not depend on the pivot
  notes->push_back(fmt::format(
      "lever_arm regressor: angular acceleration from edge rates over {:.1f}/{:.1f}/{:.1f} ms "
      "windows (x/y/z; shorter than the bin only while the reference's white noise, estimated "
      "{:.2g}/{:.2g}/{:.2g} rad/s per sample from its quietest 1-s blocks, stays <= 1 % of the "
      "regressor's variance; share at the chosen window {:.2g}/{:.2g}/{:.2g} %)",
      1e3 * wdot.window_s(0), 1e3 * wdot.window_s(1), 1e3 * wdot.window_s(2),
      wdot.rate_noise_sd_rad_s(0), wdot.rate_noise_sd_rad_s(1), wdot.rate_noise_sd_rad_s(2),
      100 * wdot.noise_fraction(0), 100 * wdot.noise_fraction(1), 100 * wdot.noise_fraction(2)));
}

}  // namespace graftnav::diagnosis_detail

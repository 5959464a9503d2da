#include <algorithm>
#include <cmath>
#include <cstdio>
#include <stdexcept>

#include "graftnav/calibration/lab_calibration.h"
#include "graftnav/calibration/pose_drift.h"
#include "graftnav/nav/rotation.h"

namespace graftnav {

namespace {

// Pose-to-pose drift of the accel and gyro (pose_drift.h) for the fitting-function points: windows
// as long as the median six-position pose, separated by the span of all accel poses. Neighbouring
// poses share their drift, so treating the pose offsets as independent needs the whole span as
// the scale: with half of it a random-walk bias passed a 1 % curvature test 4 % of the time, with
// the span 1.1 % (test LabQuadraticUnderPoseDrift...). Zero, with a note, without a static record
// or when it is too short.
void estimatePoseDrift(const LabData& s, LabCalibrationReport& rep) {
  if (s.six_position.empty()) return;
  std::vector<double> durations;
  double span_s = 0.0;
  for (const auto& p : s.six_position) {
    durations.push_back(p.stats.duration_s);
    span_s += p.stats.duration_s;
  }
  for (const auto& p : s.tilts) span_s += p.stats.duration_s;
  std::nth_element(durations.begin(), durations.begin() + durations.size() / 2, durations.end());
  rep.pose_drift_window_s = durations[durations.size() / 2];
  rep.pose_drift_separation_s = std::max(rep.pose_drift_window_s, span_s);
  if (!rep.has_basic) {
    rep.notes.push_back(
        "no static record: fitting-function points carry white noise only (no pose drift)");
    return;
  }
  try {
    rep.accel_pose_drift = measurePoseDrift(rep.basic.error, false, rep.pose_drift_window_s,
                                            rep.pose_drift_separation_s);
    rep.gyro_pose_drift = measurePoseDrift(rep.basic.error, true, rep.pose_drift_window_s,
                                           rep.pose_drift_separation_s);
  } catch (const std::invalid_argument& e) {
    rep.notes.push_back(std::string("no pose drift for the fitting functions: ") + e.what());
  }
  // A 600-s record gives each axis about a dozen window pairs one span apart, so one axis's
  // estimate can come out at half its drift (CRN null run 9301: z 0.11 mg against x, y 0.24 mg,
  // and a false z quadratic). The three axes of one sensor share its technology: use their RMS,
  // known to about 3 x 3.85 degrees of freedom (pose_drift.h), which the degree test carries.
  rep.accel_pose_drift = pooledOverAxes(rep.accel_pose_drift);
  rep.gyro_pose_drift = pooledOverAxes(rep.gyro_pose_drift);
}

// The fitting functions (Eq. 21) of one sensor and its M. The degrees feed back into M: with an
// axis that bends, M and bias are refitted with that axis's powers (fitLinearSensorModel's
// axis_degree), so the curvature does not inflate M_sigma through the reduced chi-square; then
// the fitting functions are fitted again on the new M, until the degrees repeat (at most three
// rounds). `lin` holds the linear fit on entry and the final one on return; `cal` gets both.
void fitFunctionsAndM(const std::vector<LinearObservation>& obs, const LabCalibrationOptions& opt,
                      const std::string& sensor, const PoseDriftEstimate& drift,
                      const std::string& method, LinearModelFit* lin, SensorCalibration* cal,
                      std::vector<std::string>* notes) {
  try {
    cal->fit = fitAxisPolynomials(obs, lin->M, opt.poly, sensor, drift);
    cal->has_fit = true;
    for (int round = 0; round < 3; ++round) {
      std::array<int, 3> degree;
      for (int i = 0; i < 3; ++i) degree[i] = std::clamp(cal->fit[i].degree, 1, 4);
      if (degree == lin->axis_degree) break;
      try {
        *lin = fitLinearSensorModel(obs, opt.lsq, degree);
      } catch (const std::runtime_error& e) {
        notes->push_back(sensor + " M kept without the fitting functions' powers: " + e.what());
        break;
      }
      cal->fit = fitAxisPolynomials(obs, lin->M, opt.poly, sensor, drift);
    }
  } catch (const std::invalid_argument& e) {
    notes->push_back(sensor + " fitting functions skipped: " + e.what());
  }
  storeLinearFit(*lin, method, *cal);
}

}  // namespace

namespace {

// Accelerometer: six-position poses and tilts (Ceres fit, fitting functions, |f| check).
void calibrateAccelerometer(const LabData& s, const LabCalibrationOptions& opt,
                            LabCalibrationReport& rep) {
  CalibrationResult& res = rep.result;
  std::vector<StaticPose> accel_poses = s.six_position;
  accel_poses.insert(accel_poses.end(), s.tilts.begin(), s.tilts.end());
  if (!s.six_position.empty()) {
    rep.accel_fit = calibrateAccelStaticPoses(accel_poses, s.gravity_m_s2, opt.lsq);
    for (const auto& p : accel_poses)
      rep.accel_obs.push_back({p.file, staticSpecificForce_b(p.C_nb, s.gravity_m_s2),
                               p.stats.f_mean_m_s2, p.stats.fSigmaOfMean()});
    Eigen::Matrix<double, 3, Eigen::Dynamic> U(3, rep.accel_obs.size());
    Eigen::Matrix<double, 4, Eigen::Dynamic> A(4, rep.accel_obs.size());
    for (std::size_t k = 0; k < rep.accel_obs.size(); ++k) {
      U.col(k) = rep.accel_obs[k].measured;
      A.col(k) << rep.accel_obs[k].true_value, 1.0;
    }
    rep.accel_closed_form = closedFormLinearModel(U, A);
    fitFunctionsAndM(rep.accel_obs, opt, "accel", rep.accel_pose_drift, "six_position_ceres",
                     &rep.accel_fit, &res.accel, &rep.notes);
    rep.has_accel = true;
    double s0 = 0.0, s1 = 0.0;
    for (const auto& p : accel_poses) {
      PoseNormCheck c;
      c.name = p.name;
      c.raw_norm = p.stats.f_mean_m_s2.norm();
      c.calibrated_norm = res.accel.correct(p.stats.f_mean_m_s2).norm();
      s0 += std::pow(c.raw_norm - s.gravity_m_s2, 2);
      s1 += std::pow(c.calibrated_norm - s.gravity_m_s2, 2);
      rep.norm_checks.push_back(c);
    }
    rep.norm_rms_before = std::sqrt(s0 / accel_poses.size());
    rep.norm_rms_after = std::sqrt(s1 / accel_poses.size());
  } else {
    res.accel.method = "none (no six-position data: M identity, bias 0, sigma 0)";
    rep.notes.push_back(
        "no six-position data: accelerometer M not calibrated (identity written, sigma 0)");
  }
}

// Gyro: Eq. 9 from up/down pairs, Eq. 10-11 and the Ceres fit from the rate table, else the
// static mean.
void calibrateGyro(const LabData& s, const LabCalibrationOptions& opt, LabCalibrationReport& rep) {
  CalibrationResult& res = rep.result;
  const double lat = s.lab.lat_rad;
  std::vector<StaticPose> gyro_poses = s.six_position;
  if (gyro_poses.empty() && s.has_static) {
    StaticPose p;
    p.name = "static";
    p.file = s.static_file;
    p.C_nb = s.static_C_nb;
    p.stats = segmentStats(s.static_imu, s.static_file);
    gyro_poses.push_back(p);
  }
  if (s.six_position.size() == 6) {
    rep.eq9 = gyroBiasFromUpDown(s.six_position, lat);
    rep.has_eq9 = true;
  }
  const Eigen::Vector3d noise = staticGyroNoiseStd(gyro_poses);
  if (!s.rate_runs.empty()) {
    try {
      rep.eq10 = gyroScaleFromTurns(
          s.rate_runs, rep.has_eq9 ? rep.eq9.bias : gyro_poses[0].stats.omega_mean_rad_s, lat,
          noise);
      rep.has_eq10 = true;
    } catch (const std::invalid_argument& e) {
      rep.notes.push_back(std::string("Eq. 10-11 not applicable: ") + e.what());
    }
    rep.gyro_obs = gyroObservations(gyro_poses, s.rate_runs, lat, noise);
    rep.gyro_fit = fitLinearSensorModel(rep.gyro_obs, opt.lsq);
    fitFunctionsAndM(rep.gyro_obs, opt, "gyro", rep.gyro_pose_drift, "rate_table_ceres",
                     &rep.gyro_fit, &res.gyro, &rep.notes);
    rep.has_gyro_lsq = true;
  } else if (rep.has_eq9) {
    res.gyro.bias = rep.eq9.bias;
    res.gyro.bias_sigma = rep.eq9.bias_sigma;
    res.gyro.method = "up_down_pairs_eq9 (no rate runs: M identity, sigma 0)";
    rep.notes.push_back("no rate-table files: gyro M not calibrated");
  } else {
    const StaticPose& p = gyro_poses[0];
    res.gyro.bias = p.stats.omega_mean_rad_s - staticEarthRate_b(p.C_nb, lat);
    res.gyro.bias_sigma = p.stats.omegaSigmaOfMean();
    res.gyro.method = "static_mean (no six-position or rate data: M identity, sigma 0)";
  }
}

// Allan analysis of the basic error signals of the static record.
void allanOfBasicErrors(const LabCalibrationOptions& opt, LabCalibrationReport& rep) {
  CalibrationResult& res = rep.result;
  if (rep.has_basic) {
    if (opt.allan && rep.basic.duration_s >= opt.min_allan_duration_s) {
      rep.gyro_allan = allanDeviation(rep.basic.error, true, opt.allan_curve);
      rep.accel_allan = allanDeviation(rep.basic.error, false, opt.allan_curve);
      rep.gyro_allan_fit = fitAllanNoiseTerms(rep.gyro_allan, opt.allan_fit);
      rep.accel_allan_fit = fitAllanNoiseTerms(rep.accel_allan, opt.allan_fit);
      res.gyro.has_allan = res.accel.has_allan = true;
      res.gyro.allan = rep.gyro_allan_fit.terms;
      res.accel.allan = rep.accel_allan_fit.terms;
      rep.has_allan = true;
    } else if (opt.allan) {
      rep.notes.push_back("static record shorter than " + std::to_string(opt.min_allan_duration_s) +
                          " s: no Allan analysis");
    }
  }
}

}  // namespace

LabCalibrationReport calibrateLab(const LabData& s, const LabCalibrationOptions& opt) {
  if (s.six_position.empty() && !s.has_static)
    throw std::runtime_error(s.case_dir +
                             ": insufficient lab data: no six-position poses and no static record");
  LabCalibrationReport rep;
  rep.notes = s.notes;
  CalibrationResult& res = rep.result;
  res.case_name = s.name;
  res.lab_latitude_deg = s.latitude_known ? s.lab.lat_rad * kRadToDeg : 0.0;
  res.gravity_m_s2 = s.gravity_m_s2;

  if (s.has_static) {
    rep.basic = extractBasicErrors(s.static_imu, s.static_C_nb, s.lab, s.gravity_m_s2);
    rep.has_basic = true;
  }
  estimatePoseDrift(s, rep);

  calibrateAccelerometer(s, opt, rep);
  calibrateGyro(s, opt, rep);
  allanOfBasicErrors(opt, rep);
  return rep;
}

}  // namespace graftnav

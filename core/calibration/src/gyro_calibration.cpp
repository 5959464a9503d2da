#include <cmath>
#include <map>
#include <stdexcept>

#include "graftnav/calibration/gyro_calibration.h"
#include "graftnav/nav/earth.h"
#include "graftnav/nav/rotation.h"

namespace graftnav {
namespace {
constexpr double kTwoPi = 6.283185307179586477;
}

double RateRun::trueAngle_rad(double lat_rad) const {
  return sign * kTwoPi * turns + earth::rotationRate_rad_s() * std::sin(lat_rad) * stats.duration_s;
}

Eigen::Vector3d RateRun::trueMeanRate_b(double lat_rad) const {
  Eigen::Vector3d w = Eigen::Vector3d::Zero();
  w[axis] = trueAngle_rad(lat_rad) / stats.duration_s;
  return w;
}

RateRun makeRateRun(const std::string& file, int axis, int sign, double rate_deg_s,
                    const SegmentStats& stats) {
  if (axis < 0 || axis > 2 || (sign != 1 && sign != -1) || !(rate_deg_s > 0.0))
    throw std::invalid_argument("makeRateRun: " + file + ": bad axis/sign/rate in the file name");
  RateRun r;
  r.file = file;
  r.axis = axis;
  r.sign = sign;
  r.nominal_rate_rad_s = rate_deg_s * kDegToRad;
  r.stats = stats;
  return r;
}

void assignWholeTurns(RateRun& run, const RateRunOptions& opt) {
  const double turns_nominal = run.nominal_rate_rad_s * run.stats.duration_s / kTwoPi;
  const long n = std::lround(turns_nominal);
  if (n < 1 || std::abs(turns_nominal - n) > opt.max_turn_fraction)
    throw std::runtime_error("rate run " + run.file + ": nominal rate x duration = " +
                             std::to_string(turns_nominal) + " turns, not a whole number of turns");
  const double measured = std::abs(run.stats.dtheta_sum_rad[run.axis]) / (kTwoPi * n);
  if (std::abs(measured - 1.0) > opt.max_angle_mismatch)
    throw std::runtime_error("rate run " + run.file + ": integrated angle about the axis is " +
                             std::to_string(measured * n) + " turns, expected " +
                             std::to_string(n));
  const double s = run.stats.dtheta_sum_rad[run.axis];
  if ((s > 0) != (run.sign > 0))
    throw std::runtime_error("rate run " + run.file +
                             ": integrated angle has the wrong sign for '" +
                             (run.sign > 0 ? "pos" : "neg") + "'");
  run.turns = static_cast<int>(n);
}

GyroBiasEstimate gyroBiasFromUpDown(const std::vector<StaticPose>& poses, double lat_rad) {
  auto find = [&](const std::string& name) -> const StaticPose& {
    for (const auto& p : poses)
      if (p.name == name) return p;
    throw std::invalid_argument("gyroBiasFromUpDown: missing six-position pose '" + name + "'");
  };
  GyroBiasEstimate e;
  const char* axes[3] = {"x", "y", "z"};
  for (int i = 0; i < 3; ++i) {
    const StaticPose& up = find(std::string(axes[i]) + "_up");
    const StaticPose& dn = find(std::string(axes[i]) + "_down");
    const Eigen::Vector3d lu = up.stats.omega_mean_rad_s - staticEarthRate_b(up.C_nb, lat_rad);
    const Eigen::Vector3d ld = dn.stats.omega_mean_rad_s - staticEarthRate_b(dn.C_nb, lat_rad);
    e.bias[i] = 0.5 * (lu[i] + ld[i]);
    e.bias_sigma[i] =
        0.5 * std::hypot(up.stats.omegaSigmaOfMean()[i], dn.stats.omegaSigmaOfMean()[i]);
  }
  return e;
}

Eigen::Vector3d staticGyroNoiseStd(const std::vector<StaticPose>& poses) {
  if (poses.empty()) throw std::invalid_argument("staticGyroNoiseStd: no static poses");
  Eigen::Vector3d s = Eigen::Vector3d::Zero();
  for (const auto& p : poses) s += p.stats.omega_std_rad_s.cwiseProduct(p.stats.omega_std_rad_s);
  return (s / static_cast<double>(poses.size())).cwiseSqrt();
}

TurnTableEstimate gyroScaleFromTurns(const std::vector<RateRun>& runs, const Eigen::Vector3d& bias,
                                     double lat_rad, const Eigen::Vector3d& noise) {
  TurnTableEstimate est;
  const char* axes[3] = {"x", "y", "z"};
  for (int i = 0; i < 3; ++i) {
    // Pair runs by nominal rate (deg/s rounded to 1e-6).
    std::map<long long, std::pair<const RateRun*, const RateRun*>> pairs;
    for (const auto& r : runs) {
      if (r.axis != i) continue;
      const long long key = std::llround(r.nominal_rate_rad_s * kRadToDeg * 1e6);
      (r.sign > 0 ? pairs[key].first : pairs[key].second) = &r;
    }
    Eigen::Vector3d col_sum = Eigen::Vector3d::Zero(), var_sum = Eigen::Vector3d::Zero();
    int used = 0;
    for (const auto& kv : pairs) {
      const RateRun* p = kv.second.first;
      const RateRun* n = kv.second.second;
      if (!p || !n) continue;
      const Eigen::Vector3d Lp = p->stats.dtheta_sum_rad - bias * p->stats.duration_s;
      const Eigen::Vector3d Ln = n->stats.dtheta_sum_rad - bias * n->stats.duration_s;
      const double dref = p->trueAngle_rad(lat_rad) - n->trueAngle_rad(lat_rad);
      col_sum += (Lp - Ln) / dref;
      // Angle noise of each integral: sigma_rate * sqrt(T dt) = sigma_rate * T / sqrt(n).
      const Eigen::Vector3d sp = noise * p->stats.duration_s / std::sqrt(double(p->stats.count()));
      const Eigen::Vector3d sn = noise * n->stats.duration_s / std::sqrt(double(n->stats.count()));
      var_sum += (sp.cwiseProduct(sp) + sn.cwiseProduct(sn)) / (dref * dref);
      ++used;
    }
    if (used == 0)
      throw std::invalid_argument(std::string("gyroScaleFromTurns: axis ") + axes[i] +
                                  " has no pos/neg pair of rate files at the same rate");
    est.M.col(i) = col_sum / used;
    est.M_sigma.col(i) = (var_sum / (used * used)).cwiseSqrt();
    est.pairs_used += used;
  }
  return est;
}

std::vector<LinearObservation> gyroObservations(const std::vector<StaticPose>& poses,
                                                const std::vector<RateRun>& runs, double lat_rad,
                                                const Eigen::Vector3d& noise) {
  std::vector<LinearObservation> obs;
  for (const auto& p : poses)
    obs.push_back({p.file.empty() ? p.name : p.file, staticEarthRate_b(p.C_nb, lat_rad),
                   p.stats.omega_mean_rad_s, p.stats.omegaSigmaOfMean()});
  for (const auto& r : runs) {
    if (r.turns < 1)
      throw std::invalid_argument("gyroObservations: " + r.file + ": turns not assigned");
    obs.push_back({r.file, r.trueMeanRate_b(lat_rad), r.stats.omega_mean_rad_s,
                   noise / std::sqrt(double(r.stats.count()))});
  }
  return obs;
}

LinearModelFit calibrateGyroLeastSquares(const std::vector<StaticPose>& poses,
                                         const std::vector<RateRun>& runs, double lat_rad,
                                         const LinearModelOptions& options) {
  return fitLinearSensorModel(gyroObservations(poses, runs, lat_rad, staticGyroNoiseStd(poses)),
                              options);
}

}  // namespace graftnav

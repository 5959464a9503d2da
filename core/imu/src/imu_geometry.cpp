// The field-mounting geometry of the tested IMU (imu_error_model.h: applyGeometry): the
// reference IMU's increments carried to the tested IMU's lever arm, mounting misalignment and
// time-tag offset.
#include <fmt/format.h>

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "graftnav/imu/imu_error_model.h"
#include "graftnav/nav/rotation.h"

namespace graftnav {

namespace {

using Vector6d = Eigen::Matrix<double, 6, 1>;

// ---- geometry helpers on a contiguous series ------------------------------------------------
// Nodes n = 0..N are the sample boundaries; sample k covers [T_k, T_{k+1}] with T_{k+1} - T_k =
// dt_s of sample k. Only time differences built from dt_s are used (never differences of large
// absolute time tags, whose rounding would be amplified by the differentiation of the rates).
class IncrementSeriesView {
 public:
  explicit IncrementSeriesView(const ImuSeries& s) : s_(s), n_(static_cast<int>(s.size())) {}

  int size() const { return n_; }
  double length(int k) const { return s_[k].dt_s; }
  Vector6d increment(int k) const {
    Vector6d d;
    d << s_[k].dtheta_rad, s_[k].dvel_m_s;
    return d;
  }

  // d Theta / dt at node n: derivative of the Lagrange polynomial through up to 5 nodes of the
  // cumulative increment (exact for Theta of degree <= 4, i.e. rates up to cubic in time).
  Vector6d nodeRate(int n) const {
    const int num_nodes = n_ + 1;
    const int m = std::min(5, num_nodes);
    const int lo = std::clamp(n - 2, 0, num_nodes - m);
    // Offsets of the nodes from node n and the cumulative increment from node n.
    double off[5];
    Vector6d theta[5];
    off[n - lo] = 0.0;
    theta[n - lo].setZero();
    for (int j = n + 1; j < lo + m; ++j) {
      off[j - lo] = off[j - 1 - lo] + length(j - 1);
      theta[j - lo] = theta[j - 1 - lo] + increment(j - 1);
    }
    for (int j = n - 1; j >= lo; --j) {
      off[j - lo] = off[j + 1 - lo] - length(j);
      theta[j - lo] = theta[j + 1 - lo] - increment(j);
    }
    Vector6d rate = Vector6d::Zero();
    for (int j = 0; j < m; ++j) {
      if (j == n - lo) continue;  // theta at node n is 0
      double w = 1.0 / off[j];
      for (int q = 0; q < m; ++q) {
        if (q == j || q == n - lo) continue;
        w *= (0.0 - off[q]) / (off[j] - off[q]);
      }
      rate += w * theta[j];
    }
    return rate;
  }

  // Integral of the Hermite-interpolated rate from T_k to T_k + s (0 <= s <= h_k).
  Vector6d partial(int k, double s) const {
    const double h = length(k);
    const double u = s / h;
    const double u2 = u * u;
    const double u3 = u2 * u;
    return h * (u3 - 2.0 * u2 + u) * nodeRate(k) + (-2.0 * u3 + 3.0 * u2) * increment(k) +
           h * (u3 - u2) * nodeRate(k + 1);
  }

  // Integral from node n to T_n + offset (either sign), holding the end rates beyond the ends.
  Vector6d thetaFromNode(int n, double offset) const {
    Vector6d acc = Vector6d::Zero();
    int j = n;
    double rest = offset;  // remaining offset from node j
    if (rest >= 0.0) {
      while (j < n_ && rest > length(j)) {
        acc += increment(j);
        rest -= length(j);
        ++j;
      }
      if (j == n_) return acc + rest * nodeRate(n_);
      return acc + partial(j, rest);
    }
    while (j > 0 && rest < -length(j - 1)) {
      acc -= increment(j - 1);
      rest += length(j - 1);
      --j;
    }
    if (j == 0) return acc + rest * nodeRate(0);
    // Target in [T_{j-1}, T_j]: integral T_j -> T_j + rest = -(D_{j-1} - partial(j-1, h + rest)).
    return acc - increment(j - 1) + partial(j - 1, length(j - 1) + rest);
  }

 private:
  const ImuSeries& s_;
  int n_;
};

void requireContiguous(const ImuSeries& s, const char* why) {
  for (size_t k = 0; k < s.size(); ++k) {
    if (!(s[k].dt_s > 0.0)) {
      throw std::invalid_argument(fmt::format(
          "applyGeometry ({}): sample {} (t={:.6f}) has dt_s = {}", why, k, s[k].t_s, s[k].dt_s));
    }
    if (k > 0 && std::abs(s[k - 1].t_s - (s[k].t_s - s[k].dt_s)) > 1e-3 * s[k].dt_s) {
      throw std::invalid_argument(fmt::format(
          "applyGeometry ({}): samples not contiguous at sample {}: t_prev={:.6f}, t-dt={:.6f}",
          why, k, s[k - 1].t_s, s[k].t_s - s[k].dt_s));
    }
  }
}

double interpolateTemperature(const ImuSeries& s, double t) {
  // Sample temperatures are tagged at t_s; linear in between, held beyond the ends.
  if (t <= s.front().t_s) return s.front().temperature_degC;
  if (t >= s.back().t_s) return s.back().temperature_degC;
  const auto it = std::lower_bound(s.begin(), s.end(), t,
                                   [](const ImuSample& a, double v) { return a.t_s < v; });
  const ImuSample& b = *it;
  const ImuSample& a = *(it - 1);
  const double w = (t - a.t_s) / (b.t_s - a.t_s);
  return a.temperature_degC + w * (b.temperature_degC - a.temperature_degC);
}
}  // namespace

// ---- geometry ----------------------------------------------------------------------------

ImuSeries applyGeometry(const ImuSeries& reference, const ImuErrorModel& model) {
  model.validate();
  ImuSeries out = reference;
  if (reference.empty() || !model.hasGeometry()) return out;

  // A1 lever arm and A2 misalignment, sample by sample from the reference series.
  if (model.lever_arm.isActive() || model.mounting_misalignment.isActive()) {
    if (model.lever_arm.isActive()) requireContiguous(reference, "lever_arm");
    const IncrementSeriesView view(reference);
    const Eigen::Vector3d r = model.lever_arm.r_m;
    const Eigen::Matrix3d C_tb =
        dcmFromRotationVector(model.mounting_misalignment.rotation_rad).transpose();
    // 3-point Gauss-Legendre on [0, 1].
    const double gl_s[3] = {0.5 - 0.5 * std::sqrt(0.6), 0.5, 0.5 + 0.5 * std::sqrt(0.6)};
    const double gl_w[3] = {5.0 / 18.0, 8.0 / 18.0, 5.0 / 18.0};
    Eigen::Vector3d omega_start = Eigen::Vector3d::Zero();
    if (model.lever_arm.isActive()) omega_start = view.nodeRate(0).head<3>();
    for (int k = 0; k < view.size(); ++k) {
      ImuSample& s = out[k];
      if (model.lever_arm.isActive()) {
        const double h = view.length(k);
        const Eigen::Vector3d omega_end = view.nodeRate(k + 1).head<3>();
        const Eigen::Vector3d omega_mean = reference[k].dtheta_rad / h;
        // Quadratic rate a + b s + c s^2 on s in [0, 1] matching both node rates and the mean.
        const Eigen::Vector3d a = omega_start;
        const Eigen::Vector3d b =
            6.0 * (omega_mean - omega_start) - 2.0 * (omega_end - omega_start);
        const Eigen::Vector3d c = (omega_end - omega_start) - b;
        Eigen::Vector3d centripetal = Eigen::Vector3d::Zero();
        for (int i = 0; i < 3; ++i) {
          const double u = gl_s[i];
          const Eigen::Vector3d w = a + u * b + u * u * c;
          centripetal += gl_w[i] * w.cross(w.cross(r));
        }
        s.dvel_m_s += (omega_end - omega_start).cross(r) + h * centripetal;
        omega_start = omega_end;
      }
      if (model.mounting_misalignment.isActive()) {
        s.dtheta_rad = C_tb * s.dtheta_rad;
        s.dvel_m_s = C_tb * s.dvel_m_s;
      }
    }
  }

  // A3 time offset on the geometric series.
  if (model.time_offset.isActive()) {
    requireContiguous(out, "time_offset");
    const ImuSeries geo = out;
    const IncrementSeriesView view(geo);
    const double tau = model.time_offset.tau_s;
    for (int k = 0; k < view.size(); ++k) {
      // Integral over [T_k - tau, T_{k+1} - tau] = D_k + (T_{k+1} -> T_{k+1} - tau)
      //                                              - (T_k -> T_k - tau).
      const Vector6d d =
          view.increment(k) + view.thetaFromNode(k + 1, -tau) - view.thetaFromNode(k, -tau);
      out[k].dtheta_rad = d.head<3>();
      out[k].dvel_m_s = d.tail<3>();
      if (geo[k].hasTemperature())
        out[k].temperature_degC = interpolateTemperature(geo, geo[k].t_s - tau);
    }
  }
  return out;
}

}  // namespace graftnav

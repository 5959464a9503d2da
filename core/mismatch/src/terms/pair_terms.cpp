// Builders of the terms of the pair of IMUs (term_builders.h): motion, geometry and the
// simulation's own omissions. Each appends its term (and its fixed part) once, on its row's scope.
#include <algorithm>
#include <array>
#include <cmath>
#include <string>
#include <utility>
#include <vector>

#include "graftnav/mismatch/term_spec.h"
#include "graftnav/nav/rotation.h"
#include "term_builders.h"

namespace graftnav::term_builders {

namespace {

// Slope of the tested accelerometer's lab-calibrated response at bin i's specific force.
Eigen::Matrix3d accelSlope(const RegressorInputs& in, const BinnedImu& x, int i) {
  Eigen::Matrix3d J = in.accel_response_M;
  for (int a = 0; a < 3; ++a) J(a, a) += 2.0 * in.accel_response_c2(a) * x.f_m_s2(i, a);
  return J;
}

}  // namespace

// Gyro rows, specific-force columns.
void gSensitivity(const TermSpec& spec, const TermBuildContext& ctx, SensorScope scope,
                  std::vector<CandidateTerm>* out) {
  const int n = ctx.n;
  const int c0 = firstChannel(sensorOf(scope));
  CandidateTerm t(spec, scope);
  t.explanation = "the gyros read part of the specific force as rotation (proof-mass unbalance)";
  const Eigen::MatrixX3d& f =
      ctx.in.g_sensitivity_f_m_s2.rows() == n ? ctx.in.g_sensitivity_f_m_s2 : ctx.x().f_m_s2;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) {
      RegressorColumn col;
      col.channel[c0 + i] = f.col(j);
      t.columns.push_back(col);
    }
  out->push_back(std::move(t));
}

void timeOffset(const TermSpec& spec, const TermBuildContext& ctx, SensorScope scope,
                std::vector<CandidateTerm>* out) {
  const Eigen::MatrixXd& u = ctx.in.time_offset_column;
  if (!(u.rows() == ctx.n && u.cols() == kMismatchChannels)) return;
  CandidateTerm t(spec, scope);
  t.explanation = "the tested IMU's time tags are shifted from the reference's";
  RegressorColumn col;
  for (int c = 0; c < kMismatchChannels; ++c) col.channel[c] = u.col(c);
  t.columns.push_back(col);
  out->push_back(std::move(t));
}

// Accelerometer rows: omega_dot x r + omega x (omega x r) through the lab's slope.
void leverArm(const TermSpec& spec, const TermBuildContext& ctx, SensorScope scope,
              std::vector<CandidateTerm>* out) {
  const RegressorInputs& in = ctx.in;
  const BinnedImu& x = ctx.x();
  const int n = ctx.n;
  const int c0 = firstChannel(sensorOf(scope));
  Eigen::MatrixX3d wdot(n, 3);
  if (in.omega_dot_rad_s2.rows() == n) {
    wdot = in.omega_dot_rad_s2;
  } else {
    for (int i = 0; i < n; ++i) {
      const int a = std::max(0, i - 1), b = std::min(n - 1, i + 1);
      wdot.row(i) = (x.omega_rad_s.row(b) - x.omega_rad_s.row(a)) / ((b - a) * x.grid.bin_s);
    }
  }
  CandidateTerm t(spec, scope);
  t.explanation =
      "the tested IMU sits away from the reference IMU and feels the tangential and "
      "centripetal acceleration of the turning vehicle";
  for (int j = 0; j < 3; ++j) {
    RegressorColumn col;
    Eigen::MatrixX3d v(n, 3);
    const Eigen::Vector3d e = Eigen::Vector3d::Unit(j);
    for (int i = 0; i < n; ++i) {
      const Eigen::Vector3d w = x.omega_rad_s.row(i).transpose();
      const Eigen::Vector3d wd = wdot.row(i).transpose();
      v.row(i) = (accelSlope(in, x, i) * (wd.cross(e) + w.cross(w.cross(e)))).transpose();
    }
    for (int a = 0; a < 3; ++a) col.channel[c0 + a] = v.col(a);
    t.columns.push_back(col);
  }
  out->push_back(std::move(t));
}

// The tested output C_tb(phi) x, C_tb = exp(-[phi x]), linearized at the pivot phi0:
// C_tb(phi0) x + D0 (phi - phi0), D0 = [(C_tb(phi0) x) x] Jr(phi0) (x omega x phi at phi0 = 0).
// The columns are D0; a non-zero pivot adds the fixed remainder (C_tb(phi0) - I) x - D0 phi0 as a
// part of the term, so theta stays the rotation vector and the model is exact to first order
// about phi0 (a 4-deg rotation's second order is a -0.4 % "scale factor" and 0.2 % "cross-axis"
// terms under the first-order model).
void mountingMisalignment(const TermSpec& spec, const TermBuildContext& ctx, SensorScope scope,
                          std::vector<CandidateTerm>* out) {
  const RegressorInputs& in = ctx.in;
  const BinnedImu& x = ctx.x();
  const int n = ctx.n;
  const Eigen::Vector3d& phi0 = in.mounting_rotation_pivot_rad;
  const bool pivoted = phi0.squaredNorm() > 0.0;
  const Eigen::Matrix3d C0 = dcmFromRotationVector(phi0).transpose();
  const Eigen::Matrix3d Jr0 = rightJacobianSO3(phi0);
  std::array<Eigen::MatrixX3d, 3> vg, va;  // per column j: n x 3 (gyro rows, accel rows)
  Eigen::MatrixX3d rg(n, 3), ra(n, 3);     // the remainder (pivoted only)
  for (int j = 0; j < 3; ++j) {
    vg[j].resize(n, 3);
    va[j].resize(n, 3);
  }
  for (int i = 0; i < n; ++i) {
    const Eigen::Vector3d w = x.omega_rad_s.row(i).transpose();
    const Eigen::Vector3d f = x.f_m_s2.row(i).transpose();
    const Eigen::Matrix3d Dg = skew(C0 * w) * Jr0;
    const Eigen::Matrix3d J = accelSlope(in, x, i);
    const Eigen::Matrix3d Da = J * skew(C0 * f) * Jr0;
    for (int j = 0; j < 3; ++j) {
      vg[j].row(i) = Dg.col(j).transpose();
      va[j].row(i) = Da.col(j).transpose();
    }
    if (pivoted) {
      rg.row(i) = (C0 * w - w - Dg * phi0).transpose();
      ra.row(i) = (J * (C0 * f - f) - Da * phi0).transpose();
    }
  }
  const int g0 = firstChannel(Sensor::gyro), a0 = firstChannel(Sensor::accel);
  CandidateTerm t(spec, scope);
  t.explanation = "the tested IMU is mounted slightly rotated relative to the reference IMU";
  for (int j = 0; j < 3; ++j) {
    RegressorColumn col;
    for (int a = 0; a < 3; ++a) {
      col.channel[g0 + a] = vg[j].col(a);
      col.channel[a0 + a] = va[j].col(a);
    }
    t.columns.push_back(col);
  }
  if (!pivoted) {
    out->push_back(std::move(t));
    return;
  }
  CandidateTerm rem(termSpec(TermKind::mounting_rotation_remainder), scope);
  rem.part_of = t.key();
  rem.explanation = "the mounting rotation's departure from its linearization at the pivot";
  RegressorColumn col;
  for (int a = 0; a < 3; ++a) {
    col.channel[g0 + a] = rg.col(a);
    col.channel[a0 + a] = ra.col(a);
  }
  rem.columns.push_back(col);
  t.requires_terms = {rem.key()};
  out->push_back(std::move(t));
  out->push_back(std::move(rem));
}

// Gyro rows C_bn omega_ie_n, coefficient 1: only for a simulated reference with an attitude.
void earthRotationOmitted(const TermSpec& spec, const TermBuildContext& ctx, SensorScope scope,
                          std::vector<CandidateTerm>* out) {
  const RegressorInputs& in = ctx.in;
  const int n = ctx.n;
  if (static_cast<int>(in.C_bn.size()) != n) return;
  const int c0 = firstChannel(sensorOf(scope));
  CandidateTerm t(spec, scope);
  t.explanation = "the simulation leaves out the Earth's rotation, which every real gyro senses";
  RegressorColumn col;
  Eigen::MatrixX3d v(n, 3);
  for (int i = 0; i < n; ++i) v.row(i) = (in.C_bn[i] * in.omega_ie_n).transpose();
  for (int a = 0; a < 3; ++a) col.channel[c0 + a] = v.col(a);
  t.columns.push_back(col);
  out->push_back(std::move(t));
}

// Accelerometer rows -C_bn [0 0 1] dg: the simulation's gravity magnitude off by dg.
void gravityModel(const TermSpec& spec, const TermBuildContext& ctx, SensorScope scope,
                  std::vector<CandidateTerm>* out) {
  const RegressorInputs& in = ctx.in;
  const int n = ctx.n;
  if (static_cast<int>(in.C_bn.size()) != n) return;
  const int c0 = firstChannel(sensorOf(scope));
  CandidateTerm t(spec, scope);
  t.explanation = "the simulation's gravity magnitude differs from the true local gravity";
  RegressorColumn col;
  Eigen::MatrixX3d v(n, 3);
  for (int i = 0; i < n; ++i) v.row(i) = (-in.C_bn[i].col(2)).transpose();
  for (int a = 0; a < 3; ++a) col.channel[c0 + a] = v.col(a);
  t.columns.push_back(col);
  out->push_back(std::move(t));
}

}  // namespace graftnav::term_builders

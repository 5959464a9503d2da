#include <ceres/ceres.h>
#include <ceres/rotation.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

#include "graftnav/calibration/multi_position.h"
#include "graftnav/calibration/theoretical_output.h"
#include "graftnav/nav/earth.h"

namespace graftnav {
namespace {

// K lower triangular from p = [k11, k21, k22, k31, k32, k33].
template <typename T>
void lowerK(const T* p, T K[3][3]) {
  K[0][0] = p[0];
  K[0][1] = T(0);
  K[0][2] = T(0);
  K[1][0] = p[1];
  K[1][1] = p[2];
  K[1][2] = T(0);
  K[2][0] = p[3];
  K[2][1] = p[4];
  K[2][2] = p[5];
}

// (|K (u - b)| - g) / sigma for one static interval.
struct AccelNormResidual {
  AccelNormResidual(const Eigen::Vector3d& f_mean, double gravity, double sigma)
      : u(f_mean), g(gravity), w(1.0 / sigma) {}
  template <typename T>
  bool operator()(const T* k, const T* b, T* r) const {
    T K[3][3];
    lowerK(k, K);
    T v[3] = {u[0] - b[0], u[1] - b[1], u[2] - b[2]};
    T n2 = T(0);
    for (int i = 0; i < 3; ++i) {
      T t = K[i][0] * v[0] + K[i][1] * v[1] + K[i][2] * v[2];
      n2 += t * t;
    }
    r[0] = (sqrt(n2) - g) * w;
    return true;
  }
  Eigen::Vector3d u;
  double g, w;
};

// Gravity-direction residual of one motion between static intervals (see the header).
struct GyroMotionResidual {
  GyroMotionResidual(std::vector<Eigen::Vector3d> increments, const Eigen::Vector3d& up_before,
                     const Eigen::Vector3d& up_after)
      : dtheta(std::move(increments)), u0(up_before), u1(up_after) {}
  template <typename T>
  bool operator()(const T* k, T* r) const {
    T q[4] = {T(1), T(0), T(0), T(0)};  // q_{b_k b}: body now -> body at interval k
    for (const auto& d : dtheta) {
      T phi[3];
      for (int i = 0; i < 3; ++i)
        phi[i] = k[3 * i] * d[0] + k[3 * i + 1] * d[1] + k[3 * i + 2] * d[2];
      T dq[4], qn[4];
      ceres::AngleAxisToQuaternion(phi, dq);
      ceres::QuaternionProduct(q, dq, qn);
      for (int i = 0; i < 4; ++i) q[i] = qn[i];
    }
    const T nq = sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
    T qc[4] = {q[0] / nq, -q[1] / nq, -q[2] / nq, -q[3] / nq};
    T a[3] = {T(u0[0]), T(u0[1]), T(u0[2])}, p[3];
    ceres::UnitQuaternionRotatePoint(qc, a, p);  // R^T u0
    for (int i = 0; i < 3; ++i) r[i] = T(u1[i]) - p[i];
    return true;
  }
  std::vector<Eigen::Vector3d> dtheta;
  Eigen::Vector3d u0, u1;
};

// Row-major vec: vec(A X B) = (A kron B^T) vec(X).
Eigen::Matrix<double, 9, 9> kronRowMajor(const Eigen::Matrix3d& A, const Eigen::Matrix3d& Bt) {
  Eigen::Matrix<double, 9, 9> K;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) K.block<3, 3>(3 * i, 3 * j) = A(i, j) * Bt;
  return K;
}

double angleBetween(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return std::atan2(a.cross(b).norm(), a.dot(b));
}

Eigen::Matrix3d integrateRotation(const std::vector<Eigen::Vector3d>& dtheta,
                                  const Eigen::Matrix3d& K) {
  double k[9];
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) k[3 * i + j] = K(i, j);
  GyroMotionResidual f(dtheta, Eigen::Vector3d::UnitX(), Eigen::Vector3d::Zero());
  // Reuse the functor's integration through its residual for three basis vectors.
  Eigen::Matrix3d Rt;
  for (int c = 0; c < 3; ++c) {
    f.u0 = Eigen::Vector3d::Unit(c);
    double r[3];
    f(k, r);
    Rt.col(c) = -Eigen::Vector3d(r[0], r[1], r[2]);
  }
  return Rt.transpose();  // R
}

}  // namespace

void MultiPositionOptions::validate() const {
  detector.validate();
  if (!(gravity_m_s2 > 0.0))
    throw std::invalid_argument("MultiPositionOptions: gravity_m_s2 must be > 0");
  if (min_intervals < 9)
    throw std::invalid_argument(
        "MultiPositionOptions: min_intervals = " + std::to_string(min_intervals) + " must be >= 9");
}

namespace {

// Gravity directions (of the static means) more than `distinct_deg` apart.
int countDistinctAttitudes(const std::vector<SegmentStats>& st, double distinct_deg) {
  std::vector<Eigen::Vector3d> dirs;
  for (const auto& s : st) {
    const Eigen::Vector3d d = s.f_mean_m_s2.normalized();
    bool seen = false;
    for (const auto& e : dirs) seen = seen || angleBetween(d, e) < distinct_deg * M_PI / 180.0;
    if (!seen) dirs.push_back(d);
  }
  return static_cast<int>(dirs.size());
}

ceres::Solver::Options fitSolverOptions(int max_iterations) {
  ceres::Solver::Options so;
  so.linear_solver_type = ceres::DENSE_QR;
  so.max_num_iterations = max_iterations;
  so.function_tolerance = 1e-12;
  so.parameter_tolerance = 1e-12;
  return so;
}

// M = K^-1 and the sigmas of M and b from the fitted K (lower-triangular, 6 numbers kp) and b.
void accelCovariance(ceres::Problem& pa, double* kp, double* bp, double final_cost, int n,
                     const std::string& source, MultiPositionResult& res) {
  ceres::Covariance::Options co;
  co.algorithm_type = ceres::DENSE_SVD;
  ceres::Covariance cov(co);
  std::vector<std::pair<const double*, const double*>> blocks{{kp, kp}, {kp, bp}, {bp, bp}};
  if (!cov.Compute(blocks, &pa))
    throw std::runtime_error("calibrateMultiPosition: " + source +
                             ": accelerometer covariance rank deficient (poses too similar?)");
  double ckk[36], ckb[18], cbb[9];
  cov.GetCovarianceBlock(kp, kp, ckk);
  cov.GetCovarianceBlock(kp, bp, ckb);
  cov.GetCovarianceBlock(bp, bp, cbb);
  Eigen::Matrix<double, 9, 9> C;
  C.topLeftCorner<6, 6>() = Eigen::Map<Eigen::Matrix<double, 6, 6, Eigen::RowMajor>>(ckk);
  C.topRightCorner<6, 3>() = Eigen::Map<Eigen::Matrix<double, 6, 3, Eigen::RowMajor>>(ckb);
  C.bottomLeftCorner<3, 6>() = C.topRightCorner<6, 3>().transpose();
  C.bottomRightCorner<3, 3>() = Eigen::Map<Eigen::Matrix<double, 3, 3, Eigen::RowMajor>>(cbb);
  const int dof = n - (res.accel_diagonal_only ? 6 : 9);
  const double s2 = dof > 0 ? 2.0 * final_cost / dof : 1.0;
  C *= std::max(1.0, s2);
  const Eigen::Matrix3d Ma = res.accel.M;
  Eigen::Matrix<double, 9, 6> S = Eigen::Matrix<double, 9, 6>::Zero();  // K6 -> vec_r(K)
  S(0, 0) = S(3, 1) = S(4, 2) = S(6, 3) = S(7, 4) = S(8, 5) = 1.0;
  const Eigen::Matrix<double, 9, 6> J = -kronRowMajor(Ma, Ma.transpose()) * S;
  const Eigen::Matrix<double, 9, 9> CM = J * C.topLeftCorner<6, 6>() * J.transpose();
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j)
      res.accel.M_sigma(i, j) = std::sqrt(std::max(0.0, CM(3 * i + j, 3 * i + j)));
    res.accel.bias_sigma[i] = std::sqrt(C(6 + i, 6 + i));
  }
}

// Accelerometer K, b from |K (f - b)| = g over the static means (res.accel and its fields);
// returns the corrected specific-force direction (up in the body) of every interval.
std::vector<Eigen::Vector3d> fitAccelerometer(const std::vector<SegmentStats>& st,
                                              const MultiPositionOptions& opt,
                                              const std::string& source, MultiPositionResult& res) {
  const int n = static_cast<int>(st.size());
  double kp[6] = {1, 0, 1, 0, 0, 1}, bp[3] = {0, 0, 0};
  ceres::Problem pa;
  double ss0 = 0.0;
  for (const auto& s : st) {
    const Eigen::Vector3d u = s.f_mean_m_s2;
    const Eigen::Vector3d sm = s.fSigmaOfMean();
    // sigma of |u|: the sigma-of-mean projected on the direction of u (floored).
    double sig = std::sqrt((u.normalized().cwiseProduct(sm)).squaredNorm());
    sig = std::max(sig, 1e-9 * opt.gravity_m_s2);
    pa.AddResidualBlock(new ceres::AutoDiffCostFunction<AccelNormResidual, 1, 6, 3>(
                            new AccelNormResidual(u, opt.gravity_m_s2, sig)),
                        nullptr, kp, bp);
    ss0 += std::pow(u.norm() - opt.gravity_m_s2, 2);
  }
  res.accel_norm_rms_before = std::sqrt(ss0 / n);
  if (res.accel_diagonal_only) pa.SetManifold(kp, new ceres::SubsetManifold(6, {1, 3, 4}));
  ceres::Solver::Summary sa;
  ceres::Solve(fitSolverOptions(opt.max_iterations), &pa, &sa);
  res.accel_converged = sa.termination_type == ceres::CONVERGENCE;
  res.accel_iterations = static_cast<int>(sa.iterations.size());
  if (!sa.IsSolutionUsable() || !res.accel_converged)
    throw std::runtime_error("calibrateMultiPosition: " + source +
                             ": accelerometer fit did not converge on " + std::to_string(n) +
                             " static intervals: " + sa.message);
  Eigen::Matrix3d Ka = Eigen::Matrix3d::Zero();
  Ka << kp[0], 0, 0, kp[1], kp[2], 0, kp[3], kp[4], kp[5];
  const Eigen::Vector3d ba(bp[0], bp[1], bp[2]);
  double ss1 = 0.0;
  std::vector<Eigen::Vector3d> dir(n);
  for (int k = 0; k < n; ++k) {
    const Eigen::Vector3d t = Ka * (st[k].f_mean_m_s2 - ba);
    ss1 += std::pow(t.norm() - opt.gravity_m_s2, 2);
    dir[k] = t.normalized();
  }
  res.accel_norm_rms_after = std::sqrt(ss1 / n);
  res.accel.M = Ka.inverse();
  res.accel.bias = ba;
  accelCovariance(pa, kp, bp, sa.final_cost, n, source, res);
  res.accel.method = res.accel_diagonal_only ? "multi_position_norm (M diagonal: too few attitudes)"
                                             : "multi_position_norm (M lower-triangular)";
  return dir;
}

// Gyro bias: the duration-weighted mean of the static means less the Earth rate's vertical part.
void gyroBiasFromStatics(const std::vector<SegmentStats>& st,
                         const std::vector<Eigen::Vector3d>& dir, const MultiPositionOptions& opt,
                         MultiPositionResult& res) {
  const int n = static_cast<int>(st.size());
  Eigen::Vector3d bg = Eigen::Vector3d::Zero(), bsum2 = Eigen::Vector3d::Zero();
  double T = 0.0;
  const double we_v =
      opt.latitude_known ? earth::rotationRate_rad_s() * std::sin(opt.latitude_rad) : 0.0;
  std::vector<Eigen::Vector3d> means(n);
  for (int k = 0; k < n; ++k) {
    means[k] = st[k].omega_mean_rad_s - we_v * dir[k];  // dir = up in the body
    bg += means[k] * st[k].duration_s;
    T += st[k].duration_s;
  }
  bg /= T;
  for (int k = 0; k < n; ++k) bsum2 += (means[k] - bg).cwiseAbs2();
  res.gyro.bias = bg;
  res.gyro.bias_sigma = (bsum2 / (n - 1.0) / n).cwiseSqrt();
}

// M = K^-1 of the gyro and its sigmas from the fitted K (9 numbers kg).
void gyroCovariance(ceres::Problem& pg, double* kg, double final_cost, int n,
                    const std::string& source, MultiPositionResult& res) {
  ceres::Covariance::Options co;
  co.algorithm_type = ceres::DENSE_SVD;
  ceres::Covariance cov(co);
  std::vector<std::pair<const double*, const double*>> blocks{{kg, kg}};
  if (!cov.Compute(blocks, &pg))
    throw std::runtime_error(
        "calibrateMultiPosition: " + source +
        ": gyro covariance rank deficient (motions too few or about one axis)");
  double ck[81];
  cov.GetCovarianceBlock(kg, kg, ck);
  Eigen::Matrix<double, 9, 9> C = Eigen::Map<Eigen::Matrix<double, 9, 9, Eigen::RowMajor>>(ck);
  const int dof = 2 * (n - 1) - 9;  // a unit-vector residual carries 2 degrees of freedom
  C *= dof > 0 ? 2.0 * final_cost / dof : 1.0;
  const Eigen::Matrix3d Mg = res.gyro.M;
  const Eigen::Matrix<double, 9, 9> J = -kronRowMajor(Mg, Mg.transpose());
  const Eigen::Matrix<double, 9, 9> CM = J * C * J.transpose();
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      res.gyro.M_sigma(i, j) = std::sqrt(std::max(0.0, CM(3 * i + j, 3 * i + j)));
}

// Gyro scale and misalignment: each motion between two static intervals must rotate the first
// interval's gravity direction onto the next one's.
void fitGyroMotions(const ImuSeries& imu, const std::vector<StaticInterval>& intervals,
                    const std::vector<Eigen::Vector3d>& dir, const MultiPositionOptions& opt,
                    const std::string& source, MultiPositionResult& res) {
  const int n = static_cast<int>(intervals.size());
  const Eigen::Vector3d bg = res.gyro.bias;
  double kg[9] = {1, 0, 0, 0, 1, 0, 0, 0, 1};
  ceres::Problem pg;
  std::vector<std::vector<Eigen::Vector3d>> motions;
  double a0 = 0.0;
  for (int k = 0; k + 1 < n; ++k) {
    std::vector<Eigen::Vector3d> d;
    for (std::size_t j = intervals[k].end; j < intervals[k + 1].begin; ++j)
      d.push_back(imu[j].dtheta_rad - bg * imu[j].dt_s);
    const Eigen::Matrix3d R0 = integrateRotation(d, Eigen::Matrix3d::Identity());
    a0 += std::pow(angleBetween(dir[k + 1], R0.transpose() * dir[k]), 2);
    motions.push_back(d);
    pg.AddResidualBlock(new ceres::AutoDiffCostFunction<GyroMotionResidual, 3, 9>(
                            new GyroMotionResidual(d, dir[k], dir[k + 1])),
                        nullptr, kg);
  }
  res.gyro_angle_rms_before = std::sqrt(a0 / (n - 1));
  ceres::Solver::Summary sg;
  ceres::Solve(fitSolverOptions(opt.max_iterations), &pg, &sg);
  res.gyro_converged = sg.termination_type == ceres::CONVERGENCE;
  res.gyro_iterations = static_cast<int>(sg.iterations.size());
  if (!sg.IsSolutionUsable() || !res.gyro_converged)
    throw std::runtime_error("calibrateMultiPosition: " + source +
                             ": gyro fit did not converge: " + sg.message);
  Eigen::Matrix3d Kg;
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j) Kg(i, j) = kg[3 * i + j];
  double a1 = 0.0;
  for (int k = 0; k + 1 < n; ++k) {
    const Eigen::Matrix3d R = integrateRotation(motions[k], Kg);
    a1 += std::pow(angleBetween(dir[k + 1], R.transpose() * dir[k]), 2);
  }
  res.gyro_angle_rms_after = std::sqrt(a1 / (n - 1));
  res.gyro.M = Kg.inverse();
  gyroCovariance(pg, kg, sg.final_cost, n, source, res);
  res.gyro.method = "multi_position_gravity_rotation (M full, accel frame)";
}

}  // namespace

MultiPositionResult calibrateMultiPosition(const ImuSeries& imu, const MultiPositionOptions& opt,
                                           const std::string& source) {
  opt.validate();
  MultiPositionResult res;
  const StaticDetection det = detectStaticIntervals(imu, opt.detector);
  res.intervals = det.intervals;
  res.gyro_threshold_rad_s = det.gyro_threshold_rad_s;
  res.accel_threshold_m_s2 = det.accel_threshold_m_s2;
  const int n = static_cast<int>(det.intervals.size());
  if (n < opt.min_intervals)
    throw std::runtime_error(
        "calibrateMultiPosition: " + source + ": only " + std::to_string(n) +
        " static intervals found (need >= " + std::to_string(opt.min_intervals) +
        "); thresholds gyro " + std::to_string(det.gyro_threshold_rad_s) + " rad/s, accel " +
        std::to_string(det.accel_threshold_m_s2) + " m/s^2");
  std::vector<SegmentStats> st;
  for (int k = 0; k < n; ++k)
    st.push_back(segmentStats(imu, det.intervals[k].begin, det.intervals[k].end,
                              source + " static interval " + std::to_string(k + 1)));

  res.distinct_attitudes = countDistinctAttitudes(st, opt.distinct_attitude_deg);
  if (res.distinct_attitudes < 6)
    throw std::runtime_error("calibrateMultiPosition: " + source + ": the " + std::to_string(n) +
                             " static intervals hold only " +
                             std::to_string(res.distinct_attitudes) +
                             " distinct attitudes (need >= 6, better >= 9)");
  res.accel_diagonal_only = res.distinct_attitudes < opt.min_distinct_for_full_accel;
  if (res.accel_diagonal_only)
    res.notes.push_back(
        "only " + std::to_string(res.distinct_attitudes) +
        " distinct attitudes: accelerometer non-orthogonality not observable from |f| = g, "
        "M fitted diagonal (scale + bias)");
  const std::vector<Eigen::Vector3d> dir = fitAccelerometer(st, opt, source, res);
  if (!opt.calibrate_gyro) return res;
  gyroBiasFromStatics(st, dir, opt, res);
  fitGyroMotions(imu, det.intervals, dir, opt, source, res);
  return res;
}

ImuSeries readRawCountPair(const std::string& accel_path, const std::string& gyro_path,
                           const RawCountScale& scale) {
  auto readAll = [](const std::string& path) {
    std::ifstream f(path);
    if (!f) throw std::runtime_error("readRawCountPair: cannot open " + path);
    std::vector<std::array<double, 4>> rows;
    std::string line;
    int ln = 0;
    while (std::getline(f, line)) {
      ++ln;
      if (line.find_first_not_of(" \t\r") == std::string::npos) continue;
      std::istringstream is(line);
      std::array<double, 4> r;
      if (!(is >> r[0] >> r[1] >> r[2] >> r[3]))
        throw std::runtime_error("readRawCountPair: " + path + ":" + std::to_string(ln) +
                                 ": expected 4 numbers `t x y z`");
      for (double v : r)
        if (!std::isfinite(v))
          throw std::runtime_error("readRawCountPair: " + path + ":" + std::to_string(ln) +
                                   ": not finite");
      if (!rows.empty() && !(r[0] > rows.back()[0]))
        throw std::runtime_error("readRawCountPair: " + path + ":" + std::to_string(ln) +
                                 ": time not increasing");
      rows.push_back(r);
    }
    return rows;
  };
  const auto A = readAll(accel_path), G = readAll(gyro_path);
  if (A.size() != G.size() || A.size() < 3)
    throw std::runtime_error("readRawCountPair: " + accel_path + " and " + gyro_path +
                             " must have the same number (>= 3) of lines");
  ImuSeries out(A.size());
  for (std::size_t k = 0; k < A.size(); ++k) {
    if (std::abs(A[k][0] - G[k][0]) > 1e-9)
      throw std::runtime_error("readRawCountPair: " + gyro_path + ":" + std::to_string(k + 1) +
                               ": time differs from " + accel_path);
    const double dt = k > 0 ? A[k][0] - A[k - 1][0] : A[1][0] - A[0][0];
    ImuSample& s = out[k];
    s.t_s = A[k][0];
    s.dt_s = dt;
    for (int i = 0; i < 3; ++i) {
      s.dvel_m_s[i] = (A[k][1 + i] - scale.accel_offset[i]) * scale.accel_scale[i] * dt;
      s.dtheta_rad[i] = (G[k][1 + i] - scale.gyro_offset[i]) * scale.gyro_scale[i] * dt;
    }
  }
  return out;
}

}  // namespace graftnav

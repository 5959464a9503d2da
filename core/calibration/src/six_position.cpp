#include <ceres/ceres.h>

#include <cmath>
#include <stdexcept>

#include "graftnav/calibration/six_position.h"
#include "graftnav/nav/rotation.h"

namespace graftnav {
namespace {

// Whitened residual of one observation: (measured - M true - b - powers) / sigma.
// Parameters p = [M row-major (9), b (3)] and, with kPowers = 9, the own-axis powers
// a[3 i + d - 2], the coefficient of true_i^d (d = 2..4; unused ones held at 0 by a
// SubsetManifold). kPowers = 0 is the linear model of Eq. 3.
template <int kPowers>
struct SensorModelResidual {
  SensorModelResidual(const Eigen::Vector3d& t, const Eigen::Vector3d& m, const Eigen::Vector3d& s)
      : true_value(t), measured(m), inv_sigma(s.cwiseInverse()) {}
  template <typename T>
  bool operator()(const T* p, T* r) const {
    for (int i = 0; i < 3; ++i) {
      T pred = p[9 + i];
      for (int j = 0; j < 3; ++j) pred += p[3 * i + j] * true_value[j];
      if (kPowers > 0) {
        double x_pow = true_value[i];
        for (int d = 2; d <= 4; ++d) {
          x_pow *= true_value[i];
          pred += p[12 + 3 * i + d - 2] * x_pow;
        }
      }
      r[i] = (measured[i] - pred) * inv_sigma[i];
    }
    return true;
  }
  static ceres::CostFunction* Create(const LinearObservation& o, const Eigen::Vector3d& sigma) {
    return new ceres::AutoDiffCostFunction<SensorModelResidual, 3, 12 + kPowers>(
        new SensorModelResidual(o.true_value, o.measured, sigma));
  }
  Eigen::Vector3d true_value, measured, inv_sigma;
};

}  // namespace

namespace {

// Checks the observations and the per-axis degrees; returns the number of curvature terms.
int checkLinearModelInputs(const std::vector<LinearObservation>& obs,
                           const std::array<int, 3>& axis_degree) {
  if (obs.size() < 4)
    throw std::invalid_argument("fitLinearSensorModel: need at least 4 observations, got " +
                                std::to_string(obs.size()));
  int extra = 0;
  for (int i = 0; i < 3; ++i) {
    if (axis_degree[i] < 1 || axis_degree[i] > 4)
      throw std::invalid_argument("fitLinearSensorModel: axis_degree[" + std::to_string(i) +
                                  "] = " + std::to_string(axis_degree[i]) + " is outside 1..4");
    extra += axis_degree[i] - 1;
  }
  for (const auto& o : obs) {
    if (!o.true_value.allFinite() || !o.measured.allFinite() || !o.sigma.allFinite())
      throw std::invalid_argument("fitLinearSensorModel: observation '" + o.name +
                                  "' is not finite");
    if ((o.sigma.array() < 0.0).any())
      throw std::invalid_argument("fitLinearSensorModel: observation '" + o.name +
                                  "' has sigma < 0");
  }
  return extra;
}

// The closed-form M and bias as the starting point p[0..11] (p[12..20]: curvature terms, 0).
void closedFormStart(const std::vector<LinearObservation>& obs, double* p) {
  Eigen::Matrix<double, 3, Eigen::Dynamic> U(3, obs.size());
  Eigen::Matrix<double, 4, Eigen::Dynamic> A(4, obs.size());
  for (std::size_t k = 0; k < obs.size(); ++k) {
    U.col(k) = obs[k].measured;
    A.col(k) << obs[k].true_value, 1.0;
  }
  const Eigen::Matrix4d AAt = A * A.transpose();
  Eigen::JacobiSVD<Eigen::Matrix4d> svd(AAt);
  const Eigen::Vector4d sv = svd.singularValues();
  if (!(sv(3) > 1e-12 * sv(0))) {
    std::string names;
    for (const auto& o : obs) names += (names.empty() ? "" : ", ") + o.name;
    throw std::runtime_error(
        "fitLinearSensorModel: the true values of the observations [" + names +
        "] do not span three axes plus a constant: M and bias are not observable");
  }
  const Eigen::Matrix<double, 3, 4> Mb0 = closedFormLinearModel(U, A);
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) p[3 * i + j] = Mb0(i, j);
    p[9 + i] = Mb0(i, 3);
  }
}

// The 12 x 12 covariance of M (row-major) and bias, scaled as the options say.
void linearModelCovariance(ceres::Problem& problem, double* p, int extra, CovarianceScaling scaling,
                           LinearModelFit& fit) {
  ceres::Covariance::Options co;
  co.algorithm_type = ceres::DENSE_SVD;
  ceres::Covariance cov(co);
  std::vector<std::pair<const double*, const double*>> blocks{{p, p}};
  if (!cov.Compute(blocks, &problem))
    throw std::runtime_error("fitLinearSensorModel: covariance is rank deficient");
  if (extra == 0) {
    double c[144];
    cov.GetCovarianceBlock(p, p, c);
    fit.covariance = Eigen::Map<Eigen::Matrix<double, 12, 12, Eigen::RowMajor>>(c);
  } else {
    double c[441];
    cov.GetCovarianceBlock(p, p, c);
    fit.covariance =
        Eigen::Map<Eigen::Matrix<double, 21, 21, Eigen::RowMajor>>(c).topLeftCorner<12, 12>();
  }
  double s2 = fit.dof > 0 ? fit.chi2 / fit.dof : 1.0;
  switch (scaling) {
    case CovarianceScaling::kNone:
      fit.covariance_scale = 1.0;
      break;
    case CovarianceScaling::kReducedChiSquare:
      fit.covariance_scale = fit.dof > 0 ? s2 : 1.0;
      break;
    case CovarianceScaling::kReducedChiSquareAtLeastOne:
      fit.covariance_scale = std::max(1.0, s2);
      break;
  }
  fit.covariance *= fit.covariance_scale;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) fit.M_sigma(i, j) = std::sqrt(fit.covariance(3 * i + j, 3 * i + j));
    fit.bias_sigma[i] = std::sqrt(fit.covariance(9 + i, 9 + i));
  }
}

void linearModelResiduals(const std::vector<LinearObservation>& obs, LinearModelFit& fit) {
  double ss = 0.0;
  for (const auto& o : obs) {
    Eigen::Vector3d r = o.measured - fit.M * o.true_value - fit.bias;
    for (int i = 0; i < 3; ++i)
      for (int d = 2; d <= fit.axis_degree[i]; ++d)
        r(i) -= fit.axis_powers(i, d - 2) * std::pow(o.true_value(i), d);
    fit.residuals.push_back(r);
    ss += r.squaredNorm();
  }
  fit.residual_rms = std::sqrt(ss / (3.0 * obs.size()));
}

}  // namespace

LinearModelFit fitLinearSensorModel(const std::vector<LinearObservation>& obs,
                                    const LinearModelOptions& options,
                                    const std::array<int, 3>& axis_degree) {
  const int extra = checkLinearModelInputs(obs, axis_degree);
  double scale = 0.0;
  for (const auto& o : obs) scale = std::max(scale, o.measured.cwiseAbs().maxCoeff());
  const double floor = options.relative_sigma_floor * std::max(scale, 1e-300);

  // Initial value: the closed form when it is well posed.
  double p[21] = {};
  closedFormStart(obs, p);
  ceres::Problem problem;
  for (const auto& o : obs) {
    const Eigen::Vector3d s = o.sigma.cwiseMax(floor);
    problem.AddResidualBlock(
        extra == 0 ? SensorModelResidual<0>::Create(o, s) : SensorModelResidual<9>::Create(o, s),
        nullptr, p);
  }
  if (extra > 0) {
    std::vector<int> fixed;
    for (int i = 0; i < 3; ++i)
      for (int d = axis_degree[i] + 1; d <= 4; ++d) fixed.push_back(12 + 3 * i + d - 2);
    if (!fixed.empty()) problem.SetManifold(p, new ceres::SubsetManifold(21, fixed));
  }
  ceres::Solver::Options so;
  so.linear_solver_type = ceres::DENSE_QR;
  so.max_num_iterations = 20;
  so.function_tolerance = 1e-14;
  so.gradient_tolerance = 1e-16;
  so.parameter_tolerance = 1e-14;
  ceres::Solver::Summary summary;
  ceres::Solve(so, &problem, &summary);
  if (!summary.IsSolutionUsable())
    throw std::runtime_error("fitLinearSensorModel: Ceres failed: " + summary.message);

  LinearModelFit fit;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) fit.M(i, j) = p[3 * i + j];
    fit.bias[i] = p[9 + i];
    for (int d = 2; d <= 4; ++d) fit.axis_powers(i, d - 2) = p[12 + 3 * i + d - 2];
  }
  fit.axis_degree = axis_degree;
  fit.chi2 = 2.0 * summary.final_cost;
  fit.dof = static_cast<int>(3 * obs.size()) - 12 - extra;
  linearModelCovariance(problem, p, extra, options.scaling, fit);
  linearModelResiduals(obs, fit);
  return fit;
}

Eigen::Matrix<double, 3, 4> closedFormLinearModel(
    const Eigen::Matrix<double, 3, Eigen::Dynamic>& U,
    const Eigen::Matrix<double, 4, Eigen::Dynamic>& A) {
  if (U.cols() != A.cols() || U.cols() < 4)
    throw std::invalid_argument(
        "closedFormLinearModel: U and A need the same number (>= 4) of columns");
  const Eigen::Matrix4d AAt = A * A.transpose();
  return U * A.transpose() * AAt.inverse();
}

Eigen::Vector3d sixPositionDefaultEuler(const std::string& n) {
  const double d = kDegToRad;
  if (n == "x_up") return {0.0, 90.0 * d, 0.0};
  if (n == "x_down") return {0.0, -90.0 * d, 0.0};
  if (n == "y_up") return {-90.0 * d, 0.0, 0.0};
  if (n == "y_down") return {90.0 * d, 0.0, 0.0};
  if (n == "z_up") return {180.0 * d, 0.0, 0.0};
  if (n == "z_down") return {0.0, 0.0, 0.0};
  throw std::invalid_argument("sixPositionDefaultEuler: unknown pose '" + n +
                              "' (expected x_up, x_down, y_up, y_down, z_up, z_down)");
}

LinearModelFit calibrateAccelStaticPoses(const std::vector<StaticPose>& poses, double gravity_m_s2,
                                         const LinearModelOptions& options) {
  if (!(gravity_m_s2 > 0.0))
    throw std::invalid_argument("calibrateAccelStaticPoses: gravity must be > 0");
  std::vector<LinearObservation> obs;
  for (const auto& p : poses)
    obs.push_back({p.file.empty() ? p.name : p.file, staticSpecificForce_b(p.C_nb, gravity_m_s2),
                   p.stats.f_mean_m_s2, p.stats.fSigmaOfMean()});
  return fitLinearSensorModel(obs, options);
}

void storeLinearFit(const LinearModelFit& fit, const std::string& method, SensorCalibration& out) {
  out.M = fit.M;
  out.bias = fit.bias;
  out.M_sigma = fit.M_sigma;
  out.bias_sigma = fit.bias_sigma;
  out.method = method;
}

}  // namespace graftnav

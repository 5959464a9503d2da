#include <gtest/gtest.h>

#include <array>
#include <cmath>
#include <cstdio>
#include <random>

#include "graftnav/calibration/calibration_io.h"
#include "graftnav/calibration/fitting_function.h"
#include "graftnav/calibration/pose_drift.h"
#include "test_support.h"

namespace graftnav {
namespace {

std::vector<FitPoint> samplePoly(const std::vector<double>& c, const std::vector<double>& xs,
                                 double sigma, unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, sigma);
  std::vector<FitPoint> pts;
  for (double x : xs) {
    double y = 0.0, p = 1.0;
    for (double ck : c) {
      y += ck * p;
      p *= x;
    }
    pts.push_back({x, y + g(rng), sigma});
  }
  return pts;
}

std::vector<double> rateGrid() {  // rad/s, like a rate table +-10..+-200 deg/s plus static points
  std::vector<double> xs;
  for (double d : {-200.0, -150.0, -100.0, -60.0, -30.0, -10.0, 0.0, 0.0, 10.0, 30.0, 60.0, 100.0,
                   150.0, 200.0})
    xs.push_back(d * 0.017453292519943295);
  return xs;
}

TEST(CalibFittingFunction, QuadraticChosenAndCoefficientsWithinThreeSigma) {
  const std::vector<double> c = {2e-4, 1.0 + 3e-3,
                                 4e-3};  // bias, 1 + scale, nonlinearity (1/(rad/s))
  int deg2 = 0;
  for (unsigned seed : {1u, 2u, 3u, 4u}) {
    const auto pts = samplePoly(c, rateGrid(), 1e-4, seed);
    const PolynomialFit f = fitPolynomialSelectDegree(pts, PolynomialFitOptions{}, "gyro.x");
    deg2 += f.degree == 2;
    ASSERT_GE(f.degree, 2);
    ASSERT_EQ(f.coeffs.size(), static_cast<std::size_t>(f.degree + 1));
    for (int k = 0; k <= 2; ++k)
      EXPECT_LT(std::abs(f.coeffs[k] - c[k]), 3.0 * f.coeffs_sigma[k])
          << "seed " << seed << " c" << k;
    EXPECT_LT(f.residual_rms, 2e-4);
  }
  EXPECT_GE(deg2, 3);  // the degree test does not over-fit
}

TEST(CalibFittingFunction, LinearDataGetsDegreeOneAndCubicGetsThree) {
  const auto lin = samplePoly({1e-3, 0.999}, rateGrid(), 1e-4, 8);
  EXPECT_EQ(fitPolynomialSelectDegree(lin, PolynomialFitOptions{}, "lin").degree, 1);
  const auto cub = samplePoly({0.0, 1.0, 0.0, 5e-3}, rateGrid(), 1e-5, 9);
  const PolynomialFit f = fitPolynomialSelectDegree(cub, PolynomialFitOptions{}, "cub");
  EXPECT_EQ(f.degree, 3);
  // Sigmas "estimated" to 1e20 degrees of freedom are known: the same degree (the F tail's
  // incomplete beta is not asked for such nu).
  auto cub_nu = cub;
  for (auto& p : cub_nu) p.sigma_dof = 1e20;
  EXPECT_EQ(fitPolynomialSelectDegree(cub_nu, PolynomialFitOptions{}, "cub nu").degree, 3);
  EXPECT_NEAR(f.evaluate(2.0), 2.0 + 5e-3 * 8.0, 1e-4);
}

TEST(CalibFittingFunction, CrossAxisPartRemovedBeforeTheAxisFit) {
  // measured = M true + b with a cross-axis term; per-axis fit must see only its own axis.
  Eigen::Matrix3d M = Eigen::Matrix3d::Identity();
  M(0, 1) = 2e-3;
  M(0, 0) = 1.001;
  const Eigen::Vector3d b(0.01, 0.0, 0.0);
  std::vector<LinearObservation> obs;
  for (double x : {-9.8, 0.0, 9.8})
    for (double y : {-9.8, 0.0, 9.8}) {
      const Eigen::Vector3d t(x, y, 0.5 * x);
      obs.push_back({"p", t, M * t + b, Eigen::Vector3d::Constant(1e-4)});
    }
  const auto fits = fitAxisPolynomials(obs, M, PolynomialFitOptions{}, "accel");
  EXPECT_EQ(fits[0].degree, 1);
  EXPECT_NEAR(fits[0].coeffs[0], 0.01, 1e-9);
  EXPECT_NEAR(fits[0].coeffs[1], 1.001, 1e-9);
}

// One accelerometer axis through a six-position + tilt session as the lab simulator runs it: the
// axis sees 0 g in the four x/y poses, +-g in its own pair, -0.89 g in the tilt, with the pose
// means (30 s, 10 s for the tilt) taken from a bias random walk at the pose centres.
struct DriftingSession {
  std::vector<FitPoint> points;
};
DriftingSession driftingSession(double k2, double K, double point_sigma, std::mt19937_64& rng) {
  const double g = 9.7936;
  const double x[] = {0.0, 0.0, 0.0, 0.0, g, -g, -0.8925 * g};
  const double t[] = {15.0, 45.0, 75.0, 105.0, 135.0, 165.0, 217.0};  // rate runs before the tilt
  std::normal_distribution<double> n01(0.0, 1.0);
  DriftingSession s;
  double b = 0.0, t_prev = 0.0;
  for (int i = 0; i < 7; ++i) {
    b += K * std::sqrt(t[i] - t_prev) * n01(rng);
    t_prev = t[i];
    const double white = (i == 6 ? 1.8e-4 * std::sqrt(3.0) : 1.8e-4) * n01(rng);
    s.points.push_back({x[i], 0.01 + 1.0004 * x[i] + k2 * x[i] * x[i] + b + white, point_sigma});
  }
  return s;
}

TEST(CalibFittingFunction, LabQuadraticUnderPoseDriftFoundAndDriftNotTakenForCurvature) {
  // A 1-mg, 1-h Gauss-Markov bias drifts like a random walk of K = 2.3e-4 m/s^2/sqrt(s) over a
  // session: pose means a session span (190 s) apart differ by K sqrt(190 / 2) = 2.2e-3 m/s^2
  // (pose_drift.h), twelve times their white sigma-of-mean. random_11_15's k2 = 2.5e-4 per m/s^2
  // (24 mg at +-g) was missed by leave-one-out cross-validation.
  const double K = 2.3e-4, drift = K * std::sqrt(190.0 / 2.0);
  const double sigma = std::hypot(1.8e-4, drift);
  std::mt19937_64 rng(20261124);
  const int trials = 400;
  int null_white = 0, null_drift = 0, found = 0, within = 0, null_c2_within = 0, c2_within = 0;
  for (int k = 0; k < trials; ++k) {
    DriftingSession s = driftingSession(0.0, K, sigma, rng);
    const PolynomialFit null_fit =
        fitPolynomialSelectDegree(s.points, PolynomialFitOptions{}, "null");
    null_drift += null_fit.degree > 1;
    // The degree-2 estimate the test weighed is reported with a line too, with a sigma that
    // holds: the mismatch finder uses it as evidence (mismatch/gain_or_curvature.h).
    null_c2_within += std::abs(null_fit.c2_tested) < 3.0 * null_fit.c2_tested_sigma;
    for (auto& p : s.points) p.sigma = 1.8e-4;  // white sigma-of-mean only
    null_white +=
        fitPolynomialSelectDegree(s.points, PolynomialFitOptions{}, "null white").degree > 1;
    const DriftingSession q = driftingSession(2.5e-4, K, sigma, rng);
    const PolynomialFit f =
        fitPolynomialSelectDegree(q.points, PolynomialFitOptions{}, "quadratic");
    c2_within += std::abs(f.c2_tested - 2.5e-4) < 3.0 * f.c2_tested_sigma;
    if (f.degree == 2) {
      EXPECT_EQ(f.c2_tested, f.coeffs[2]);
      ++found;
      within += std::abs(f.coeffs[2] - 2.5e-4) < 3.0 * f.coeffs_sigma[2];
    }
  }
  EXPECT_GE(found, trials * 99 / 100);
  EXPECT_GE(within, found * 95 / 100);
  // The 1 % test with the drift of a session span in the sigmas: 1.1 % over 2000 trials (2.5 %
  // allowed here). With white sigmas only, the drift passes for curvature 4-5 times as often (a
  // half-span drift gave 4.2 %: neighbouring poses share their drift, so the span is the scale).
  EXPECT_LE(null_drift, trials * 25 / 1000);
  EXPECT_GE(null_white, trials * 35 / 1000);
  EXPECT_GE(null_c2_within, trials * 97 / 100);
  EXPECT_GE(c2_within, trials * 97 / 100);
}

// Static error record of `duration_s` at `rate_hz`: white noise per sample and a random walk
// K [m/s^2/sqrt(s)] per axis.
ImuSeries staticRecord(double duration_s, double rate_hz, double white, const Eigen::Vector3d& K,
                       std::mt19937_64& rng) {
  const double dt = 1.0 / rate_hz;
  std::normal_distribution<double> n01(0.0, 1.0);
  ImuSeries e(static_cast<std::size_t>(std::lround(duration_s * rate_hz)));
  Eigen::Vector3d b = Eigen::Vector3d::Zero();
  for (std::size_t k = 0; k < e.size(); ++k) {
    Eigen::Vector3d f;
    for (int a = 0; a < 3; ++a) {
      b[a] += K[a] * std::sqrt(dt) * n01(rng);
      f[a] = b[a] + white * n01(rng);
    }
    e[k].t_s = (k + 1) * dt;
    e[k].dt_s = dt;
    e[k].dvel_m_s = f * dt;
    e[k].dtheta_rad = 1e-3 * f * dt;
  }
  return e;
}

TEST(PoseDrift, RecoversRandomWalkBetweenWindowsAndIgnoresWhiteNoise) {
  // Static record 3600 s at 100 Hz: white noise on every axis, random walks K = [1, 3, 0] e-4.
  // Window means T = 30 s, dT = 90 s apart: D = K^2 (dT - T / 3) / 2.
  const Eigen::Vector3d K(1e-4, 3e-4, 0.0);
  std::mt19937_64 rng(7);
  const ImuSeries e = staticRecord(3600.0, 100.0, 0.02, K, rng);
  const PoseDriftEstimate d = measurePoseDrift(e, false, 30.0, 90.0);
  for (int a = 0; a < 2; ++a)
    EXPECT_NEAR(d.sigma[a], K[a] * std::sqrt(0.5 * (90.0 - 10.0)), 0.2 * K[a] * std::sqrt(40.0))
        << "axis " << a;
  EXPECT_LT(d.sigma[2], 0.3 * 1e-4 * std::sqrt(40.0));  // white noise alone: (nearly) no drift
  EXPECT_NEAR(measurePoseDrift(e, true, 30.0, 90.0).sigma[1], 1e-3 * d.sigma[1], 1e-12);
  EXPECT_THROW(measurePoseDrift(ImuSeries(e.begin(), e.begin() + 10000), false, 30.0, 90.0),
               std::invalid_argument);
  EXPECT_THROW(measurePoseDrift(e, false, 0.0, 90.0), std::invalid_argument);
}

TEST(PoseDrift, DegreesOfFreedomMatchTheSpreadOfTheEstimate) {
  // A lab's 600-s static record, 30-s windows 190 s apart (m = 6, 14 overlapping pairs): the
  // spread of sigma^2 over repeated records, as Satterthwaite's 2 mean^2 / var, against the
  // dof the estimator states (pose_drift.h; 3.85 for a pure random walk), and the pooled dof.
  const Eigen::Vector3d K = Eigen::Vector3d::Constant(2.3e-4);
  std::mt19937_64 rng(11);
  const int trials = 300;
  double s1 = 0.0, s2 = 0.0, dof_sum = 0.0, pooled_dof_sum = 0.0;
  for (int k = 0; k < trials; ++k) {
    const PoseDriftEstimate d =
        measurePoseDrift(staticRecord(600.0, 50.0, 1e-2, K, rng), false, 30.0, 190.0);
    for (int a = 0; a < 3; ++a) {
      const double v = d.sigma[a] * d.sigma[a];
      s1 += v;
      s2 += v * v;
      dof_sum += std::isfinite(d.dof[a]) ? d.dof[a] : 0.0;
    }
    pooled_dof_sum += pooledOverAxes(d).dof[0];
  }
  const double n = 3.0 * trials, mean = s1 / n, var = s2 / n - mean * mean;
  const double empirical_dof = 2.0 * mean * mean / var, stated_dof = dof_sum / n;
  EXPECT_NEAR(stated_dof, empirical_dof, 0.25 * empirical_dof) << "stated " << stated_dof;
  EXPECT_GT(stated_dof, 2.5);
  EXPECT_LT(stated_dof, 6.0);
  // Pooled: three times an axis's for equal axes; less when the axes' estimates differ.
  std::printf("sigma^2 dof: stated %.2f, empirical %.2f; pooled over 3 axes %.2f\n", stated_dof,
              empirical_dof, pooled_dof_sum / trials);
  EXPECT_GT(pooled_dof_sum / trials, 2.0 * stated_dof);
  EXPECT_LE(pooled_dof_sum / trials, 3.0 * stated_dof);

  PoseDriftEstimate two;
  two.sigma = Eigen::Vector3d(1.0, 1.0, 0.0);
  two.dof = Eigen::Vector3d(4.0, 4.0, INFINITY);
  const PoseDriftEstimate p = pooledOverAxes(two);
  EXPECT_NEAR(p.sigma[2], std::sqrt(2.0 / 3.0), 1e-12);
  EXPECT_NEAR(p.dof[1], 8.0, 1e-12);  // (1 + 1)^2 / (1/4 + 1/4)
  EXPECT_TRUE(std::isinf(pooledOverAxes(PoseDriftEstimate{}).dof[0]));
}

TEST(CalibFittingFunction, DriftEstimatedFromAShortStaticRecordCarriesItsDofIntoTheDegreeTest) {
  // The CRN failure (docs/calibration.md): the drift in the point sigmas is itself estimated from
  // a 600-s record, so in some labs it comes out at half its size and the drift passes for
  // curvature. Per trial: a static record gives the pooled drift (measurePoseDrift,
  // pooledOverAxes); three independent sessions (one per axis) go through fitAxisPolynomials with
  // that estimate, once with its dof (F reference) and once as if it were known.
  const double K = 2.3e-4, white = 1.8e-4;
  std::mt19937_64 rng(20261125);
  const int trials = 400;
  int null_dof = 0, null_known = 0, found = 0;
  const auto sessions = [&](double k2) {
    std::array<DriftingSession, 3> s = {driftingSession(k2, K, 1.0, rng),
                                        driftingSession(k2, K, 1.0, rng),
                                        driftingSession(k2, K, 1.0, rng)};
    std::vector<LinearObservation> obs;
    for (std::size_t i = 0; i < s[0].points.size(); ++i) {
      const Eigen::Vector3d x = Eigen::Vector3d::Constant(s[0].points[i].x);
      const Eigen::Vector3d y(s[0].points[i].y, s[1].points[i].y, s[2].points[i].y);
      obs.push_back(
          {"pose", x, y, Eigen::Vector3d::Constant(i == 6 ? white * std::sqrt(3.0) : white)});
    }
    return obs;
  };
  PolynomialFitOptions per_axis_1pct;  // the sensor's alpha that gives 1 % per axis (Sidak)
  per_axis_1pct.degree_alpha = 1.0 - std::pow(0.99, 3.0);
  for (int k = 0; k < trials; ++k) {
    const PoseDriftEstimate est = pooledOverAxes(measurePoseDrift(
        staticRecord(600.0, 50.0, 1e-2, Eigen::Vector3d::Constant(K), rng), false, 30.0, 190.0));
    PoseDriftEstimate as_known = est;
    as_known.dof.setConstant(INFINITY);
    const auto null_obs = sessions(0.0);
    for (const auto& f :
         fitAxisPolynomials(null_obs, Eigen::Matrix3d::Identity(), per_axis_1pct, "accel", est))
      null_dof += f.degree > 1;
    for (const auto& f : fitAxisPolynomials(null_obs, Eigen::Matrix3d::Identity(), per_axis_1pct,
                                            "accel", as_known))
      null_known += f.degree > 1;
    for (const auto& f : fitAxisPolynomials(sessions(2.5e-4), Eigen::Matrix3d::Identity(),
                                            per_axis_1pct, "accel", est))
      found += f.degree == 2;
  }
  std::printf(
      "null axes with degree > 1: %d/%d with the dof, %d/%d as if known; k2 2.5e-4 found %d/%d\n",
      null_dof, 3 * trials, null_known, 3 * trials, found, 3 * trials);
  EXPECT_LE(null_dof, 3 * trials * 2 / 100);
  EXPECT_GT(null_known, null_dof);  // as if known: 2.5 %, the CRN failure
  EXPECT_GE(found, 3 * trials * 97 / 100);
}

TEST(CalibFittingFunction, DegreeAlphaHoldsForTheSensorNotEachAxis) {
  // Six-position + tilt sessions with white errors only and known sigmas: a lab whose any axis
  // takes degree > 1 is a false curvature in SG#2. At the default 1 % that happens in at most 1 %
  // of the labs (0.5 % here: the F-test branch is conservative), three times as often if each axis
  // were tested at 1 %.
  std::mt19937_64 rng(5);
  std::normal_distribution<double> n01(0.0, 1.0);
  const double g = 9.7936, sigma = 2e-4;
  const double xs[] = {0.0, 0.0, 0.0, 0.0, g, -g, -0.8925 * g};
  const int labs = 3000;
  int any_sensor = 0, any_per_axis = 0;
  PolynomialFitOptions per_axis_1pct;
  per_axis_1pct.degree_alpha = 1.0 - std::pow(0.99, 3.0);
  ASSERT_NEAR(per_axis_1pct.perAxisAlpha(), 0.01, 1e-12);
  for (int k = 0; k < labs; ++k) {
    std::vector<LinearObservation> obs;
    for (double x : xs)
      obs.push_back({"pose", Eigen::Vector3d::Constant(x),
                     Eigen::Vector3d::Constant(0.01 + x) +
                         sigma * Eigen::Vector3d(n01(rng), n01(rng), n01(rng)),
                     Eigen::Vector3d::Constant(sigma)});
    bool a = false, b = false;
    for (const auto& f : fitAxisPolynomials(obs, Eigen::Matrix3d::Identity(), {}, "accel"))
      a |= f.degree > 1;
    for (const auto& f :
         fitAxisPolynomials(obs, Eigen::Matrix3d::Identity(), per_axis_1pct, "accel"))
      b |= f.degree > 1;
    any_sensor += a;
    any_per_axis += b;
  }
  std::printf("labs with a false curvature: %d/%d at 1 %% per sensor, %d/%d at 1 %% per axis\n",
              any_sensor, labs, any_per_axis, labs);
  EXPECT_LE(any_sensor, labs * 16 / 1000);
  EXPECT_GE(any_sensor, labs * 3 / 1000);
  EXPECT_GE(any_per_axis, 2 * any_sensor);
}

TEST(CalibFittingFunction, BadInputs) {
  EXPECT_THROW(fitPolynomialSelectDegree({{0, 0, 1}, {1, 1, 1}}, PolynomialFitOptions{}, "two"),
               std::invalid_argument);
  EXPECT_THROW(fitPolynomialSelectDegree({{1, 0, 1}, {1, 1, 1}, {1, 2, 1}}, PolynomialFitOptions{},
                                         "same x"),
               std::invalid_argument);
  EXPECT_THROW(
      fitPolynomialSelectDegree({{0, 0, 0}, {1, 1, 1}, {2, 2, 1}}, PolynomialFitOptions{}, "sigma"),
      std::invalid_argument);
  PolynomialFitOptions o;
  o.max_degree = 5;
  EXPECT_THROW(o.validate(), std::invalid_argument);
  o.max_degree = 3;
  o.folds = 1;
  EXPECT_THROW(o.validate(), std::invalid_argument);
}

// The fit's response to the shapes it leaves out (PolynomialFit::slope_per_abs, slope_per_sq,
// c2_tested_per_abs): six-position poses (-g, 0 x 4, +g) see an asymmetric gain d |x| as the
// quadratic d / g x^2 and leave the slope alone; a tilted pose makes the fold inexact, and the
// responses then still predict what the fit does with an asymmetry it cannot model.
TEST(CalibFittingFunction, ResponsesToAnAsymmetryAndACurvatureItLeavesOut) {
  const double g = 9.79;
  std::vector<FitPoint> six;
  for (double x : {-g, 0.0, 0.0, 0.0, 0.0, g}) six.push_back({x, 0.0, 1e-4});
  const double d = 3e-3;  // output = x + d |x|, one-sided gains 1 + 2d and 1 on the two signs
  for (auto& p : six) p.y = p.x + d * std::abs(p.x);
  const PolynomialFit line = fitPolynomialSelectDegree(six, PolynomialFitOptions{}, "six");
  ASSERT_EQ(line.degree, 1);
  EXPECT_NEAR(line.slope_per_abs, 0.0, 1e-12);
  EXPECT_NEAR(line.slope_per_sq, 0.0, 1e-12);
  EXPECT_TRUE(std::isnan(line.c2_tested_per_abs)) << "three support values: no quadratic";
  // A tilted pose (x = -g cos 25 deg) supports a quadratic; the fold is then inexact and the
  // fit's coefficients are what the responses predict, for the asymmetry and for a curvature.
  std::vector<FitPoint> tilted = six;
  tilted.push_back({-g * std::cos(25.0 * M_PI / 180.0), 0.0, 1e-4});
  for (auto& p : tilted) p.y = p.x + d * std::abs(p.x);
  PolynomialFitOptions keep_quadratic;
  keep_quadratic.degree_alpha = 0.999;  // keep the quadratic whatever the points say
  const PolynomialFit q = fitPolynomialSelectDegree(tilted, keep_quadratic, "tilted");
  ASSERT_EQ(q.degree, 2);
  EXPECT_NEAR(q.coeffs[1], 1.0 + d * q.slope_per_abs, 1e-12);
  EXPECT_NEAR(q.coeffs[2], d * q.c2_tested_per_abs, 1e-12);
  EXPECT_NEAR(q.c2_tested_per_abs, 1.0 / g, 0.2 / g) << "close to the six-position fold";
  EXPECT_GT(std::abs(q.c2_tested_per_abs - 1.0 / g), 1e-4 / g) << "but not exactly it";
  EXPECT_EQ(q.slope_per_sq, 0.0);
  // A line on the tilted points (the default 1 % test on a pure curvature too small to keep):
  // its slope moves by k2 * slope_per_sq under a curvature it does not model.
  const double k2 = 1e-7;
  for (auto& p : tilted) p.y = p.x + k2 * p.x * p.x;
  const PolynomialFit l = fitPolynomialSelectDegree(tilted, PolynomialFitOptions{}, "tilted line");
  ASSERT_EQ(l.degree, 1);
  EXPECT_NEAR(l.coeffs[1], 1.0 + k2 * l.slope_per_sq, 1e-12);
  EXPECT_GT(std::abs(l.slope_per_sq), 0.1) << "the tilted pose makes the points asymmetric";
  EXPECT_NEAR(l.c2_tested, k2, 1e-12);
}

CalibrationResult sampleResult() {
  CalibrationResult r;
  r.case_name = "unit";
  r.lab_latitude_deg = 30.5;
  r.gravity_m_s2 = 9.7936;
  r.accel.M << 1.001, 2e-4, -3e-4, 1e-4, 0.999, 5e-5, 0, 0, 1.0002;
  r.accel.bias << 0.01, -0.02, 0.03;
  r.accel.M_sigma.setConstant(1e-5);
  r.accel.bias_sigma.setConstant(1e-4);
  r.accel.method = "six_position_ceres";
  r.gyro = r.accel;
  r.gyro.bias *= 1e-3;
  r.gyro.has_allan = true;
  r.gyro.allan.white_noise << 1e-4, 2e-4, 3e-4;
  r.gyro.allan.bias_instability << 1e-5, 2e-5, 3e-5;
  r.gyro.allan.rate_random_walk << 1e-7, 0, 3e-7;
  r.gyro.has_fit = true;
  for (int a = 0; a < 3; ++a) {
    r.gyro.fit[a].degree = 2;
    r.gyro.fit[a].coeffs = {1e-4 * a, 1.001, 3e-3};
    r.gyro.fit[a].coeffs_sigma = {1e-6, 1e-5, 1e-4};
    r.gyro.fit[a].n_points = 14;
  }
  r.gyro.fit[1].c2_tested = 2e-5;  // a line kept, its degree-2 estimate reported
  r.gyro.fit[1].c2_tested_sigma = 1e-5;
  r.gyro.fit[1].slope_per_abs = -3e-3;
  r.gyro.fit[1].slope_per_sq = 0.02;
  r.gyro.fit[1].c2_tested_per_abs = 0.1;
  return r;
}

TEST(CalibIo, YamlRoundTrip) {
  const std::string dir = test::makeTempDir("calib_io");
  const CalibrationResult r = sampleResult();
  writeCalibrationYaml(dir + "/calibration.yaml", r);
  const CalibrationResult q = readCalibrationYaml(dir + "/calibration.yaml");
  EXPECT_EQ(q.case_name, "unit");
  EXPECT_NEAR(q.gravity_m_s2, r.gravity_m_s2, 1e-12);
  EXPECT_LT((q.accel.M - r.accel.M).cwiseAbs().maxCoeff(), 1e-11);
  EXPECT_LT((q.gyro.bias - r.gyro.bias).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_LT((q.accel.M_sigma - r.accel.M_sigma).cwiseAbs().maxCoeff(), 1e-15);
  EXPECT_FALSE(q.accel.has_allan);
  ASSERT_TRUE(q.gyro.has_allan);
  EXPECT_LT((q.gyro.allan.white_noise - r.gyro.allan.white_noise).cwiseAbs().maxCoeff(), 1e-15);
  ASSERT_TRUE(q.gyro.has_fit);
  EXPECT_EQ(q.gyro.fit[2].degree, 2);
  EXPECT_NEAR(q.gyro.fit[2].coeffs[0], 2e-4, 1e-15);
  EXPECT_NEAR(q.gyro.fit[1].c2_tested, 2e-5, 1e-18);
  EXPECT_NEAR(q.gyro.fit[1].c2_tested_sigma, 1e-5, 1e-18);
  EXPECT_TRUE(std::isnan(q.gyro.fit[0].c2_tested)) << "absent stays absent";
  EXPECT_NEAR(q.gyro.fit[1].slope_per_abs, -3e-3, 1e-18);
  EXPECT_NEAR(q.gyro.fit[1].slope_per_sq, 0.02, 1e-17);
  EXPECT_NEAR(q.gyro.fit[1].c2_tested_per_abs, 0.1, 1e-17);
  EXPECT_TRUE(std::isnan(q.gyro.fit[0].slope_per_abs)) << "absent stays absent";
  EXPECT_EQ(q.gyro.method, "six_position_ceres");
}

TEST(CalibIo, MissingOrMalformedKeysNameTheKey) {
  const std::string dir = test::makeTempDir("calib_io_bad");
  auto expectError = [&](const std::string& text, const std::string& key) {
    const std::string p = dir + "/c.yaml";
    FILE* f = std::fopen(p.c_str(), "w");
    std::fputs(text.c_str(), f);
    std::fclose(f);
    try {
      readCalibrationYaml(p);
      FAIL() << "no error for " << key;
    } catch (const std::runtime_error& e) {
      EXPECT_NE(std::string(e.what()).find(key), std::string::npos) << e.what();
      EXPECT_NE(std::string(e.what()).find(p), std::string::npos) << e.what();
    }
  };
  const std::string gyro = "gyro: {M: [[1,0,0],[0,1,0],[0,0,1]], bias: [0,0,0]}\n";
  expectError(gyro, "accel");
  expectError("accel: {M: [[1,0,0],[0,1,0]], bias: [0,0,0]}\n" + gyro, "accel.M");
  expectError("accel: {M: [[1,0,0],[0,1,0],[0,0,1]], bias: [0,.nan,0]}\n" + gyro, "accel.bias");
  expectError(
      "accel: {M: [[1,0,0],[0,1,0],[0,0,1]], bias: [0,0,0], fit: {x: {degree: 2, coeffs: [0,1]}}}\n" +
          gyro,
      "accel.fit");
  EXPECT_THROW(readCalibrationYaml(dir + "/does_not_exist.yaml"), std::runtime_error);
}

}  // namespace
}  // namespace graftnav

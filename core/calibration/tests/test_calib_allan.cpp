#include <gtest/gtest.h>

#include <filesystem>
#include <random>

#include "graftnav/calibration/allan.h"
#include "graftnav/calibration/basic_error.h"
#include "graftnav/io/imu_io.h"
#include "graftnav/nav/rotation.h"
#include "test_support.h"

namespace graftnav {
namespace {

// Allan variance of a first-order Gauss-Markov rate (variance s2, correlation time T):
// AVAR = 2 s2 T / tau [1 - T / (2 tau) (3 - 4 e^{-tau/T} + e^{-2 tau/T})].
double gmAvar(double s2, double T, double tau) {
  const double x = tau / T;
  return 2.0 * s2 * T / tau * (1.0 - (3.0 - 4.0 * std::exp(-x) + std::exp(-2.0 * x)) / (2.0 * x));
}

// Flicker-like noise: equal-variance Gauss-Markov processes at octave correlation times
// T0 2^j, j < n; between ~T0 and T0 2^n the Allan deviation is flat.
struct FlickerSource {
  std::vector<double> T, x;
  double s2;
  FlickerSource(double s2_each, double T0, int n) : s2(s2_each) {
    for (int j = 0; j < n; ++j) T.push_back(T0 * std::pow(2.0, j));
    x.assign(n, 0.0);
  }
  double avar(double tau) const {
    double a = 0.0;
    for (double t : T) a += gmAvar(s2, t, tau);
    return a;
  }
};

struct Signal {
  std::vector<Eigen::Vector3d> rate;
  double dt;
};

// White (density N) + rate random walk (K) + flicker source per axis.
Signal makeSignal(double N, double K, FlickerSource* flick, double dt, std::size_t n,
                  unsigned seed) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, 1.0);
  Signal s{std::vector<Eigen::Vector3d>(n), dt};
  for (int a = 0; a < 3; ++a) {
    double rw = 0.0;
    std::vector<double> x =
        flick ? std::vector<double>(flick->T.size(), 0.0) : std::vector<double>();
    if (flick)
      for (auto& v : x) v = std::sqrt(flick->s2) * g(rng);
    for (std::size_t k = 0; k < n; ++k) {
      double v = N / std::sqrt(dt) * g(rng);
      rw += K * std::sqrt(dt) * g(rng);
      v += rw;
      if (flick)
        for (std::size_t j = 0; j < x.size(); ++j) {
          const double phi = std::exp(-dt / flick->T[j]);
          x[j] = phi * x[j] + std::sqrt(flick->s2 * (1.0 - phi * phi)) * g(rng);
          v += x[j];
        }
      s.rate[k][a] = v;
    }
  }
  return s;
}

TEST(CalibAllan, WhiteNoiseSlopeAndLevel) {
  const double N = 0.01;  // rad/sqrt(s)
  const Signal s = makeSignal(N, 0.0, nullptr, 0.01, 200000, 7);
  const AllanCurve c = allanDeviation(s.rate, s.dt);
  ASSERT_GT(c.tau_s.size(), 10u);
  EXPECT_DOUBLE_EQ(c.tau_s[0], 0.01);
  for (std::size_t i = 0; i < c.tau_s.size(); ++i)
    for (int a = 0; a < 3; ++a) {
      const double expected = N / std::sqrt(c.tau_s[i]);
      EXPECT_LT(std::abs(c.adev[i][a] - expected), 4.0 * c.rel_error[i] * expected)
          << "tau " << c.tau_s[i];
    }
  const AllanFit f = fitAllanNoiseTerms(c);
  for (int a = 0; a < 3; ++a) {
    EXPECT_LT(std::abs(f.terms.white_noise[a] - N), 3.0 * f.terms.white_noise_sigma[a]);
    EXPECT_LT(f.terms.white_noise_sigma[a], 0.02 * N);
  }
}

TEST(CalibAllan, RecoversWhiteAndRateRandomWalkWithinThreeSigma) {
  const double N = 0.002, K = 2e-5;
  for (unsigned seed : {41u, 42u, 43u}) {
    const Signal s = makeSignal(N, K, nullptr, 0.1, 100000, seed);  // 10 Hz, 2.8 h
    const AllanFit f = fitAllanNoiseTerms(allanDeviation(s.rate, s.dt));
    for (int a = 0; a < 3; ++a) {
      EXPECT_LT(std::abs(f.terms.white_noise[a] - N), 3.0 * f.terms.white_noise_sigma[a]) << seed;
      EXPECT_LT(std::abs(f.terms.rate_random_walk[a] - K), 3.0 * f.terms.rate_random_walk_sigma[a])
          << seed << " K " << f.terms.rate_random_walk[a];
      EXPECT_LT(f.terms.white_noise_sigma[a], 0.05 * N);
      EXPECT_LT(f.terms.rate_random_walk_sigma[a], 0.5 * K);
    }
  }
}

TEST(CalibAllan, RecoversFlickerBiasInstabilityWithinThreeSigma) {
  const double N = 0.001;
  FlickerSource fl(1.0e-7, 0.5, 14);  // flat from ~1 s to ~2000 s
  // The injected bias instability: the flat level of the exact Allan variance of the source.
  const double B_true = std::sqrt(fl.avar(40.0) / 0.44130);
  ASSERT_NEAR(fl.avar(10.0), fl.avar(100.0), 0.05 * fl.avar(40.0));  // really flat
  for (unsigned seed : {51u, 52u}) {
    const Signal s = makeSignal(N, 0.0, &fl, 0.1, 100000, seed);
    const AllanFit f = fitAllanNoiseTerms(allanDeviation(s.rate, s.dt));
    for (int a = 0; a < 3; ++a) {
      EXPECT_LT(std::abs(f.terms.bias_instability[a] - B_true),
                3.0 * f.terms.bias_instability_sigma[a])
          << seed << " B " << f.terms.bias_instability[a] << " vs " << B_true;
      EXPECT_LT(f.terms.bias_instability_sigma[a], 0.3 * B_true);
      // Read-off (min ADEV / 0.664) is in the same range.
      EXPECT_NEAR(f.readoff_bias_instability[a], B_true, 0.3 * B_true);
    }
  }
}

TEST(CalibAllan, DenseSpacingAndBadInputs) {
  const Signal s = makeSignal(0.01, 0.0, nullptr, 0.01, 20000, 3);
  AllanOptions o;
  o.octave = false;
  o.points_per_decade = 10;
  const AllanCurve c = allanDeviation(s.rate, s.dt, o);
  EXPECT_GT(c.tau_s.size(), 25u);
  for (std::size_t i = 1; i < c.m.size(); ++i) EXPECT_GT(c.m[i], c.m[i - 1]);
  EXPECT_THROW(allanDeviation(std::vector<Eigen::Vector3d>(10), 0.01), std::invalid_argument);
  EXPECT_THROW(allanDeviation(s.rate, 0.0), std::invalid_argument);
  o.max_cluster_fraction = 0.9;
  EXPECT_THROW(allanDeviation(s.rate, 0.01, o), std::invalid_argument);
  AllanFitOptions fo;
  fo.min_tau_s = 5.0;
  fo.max_tau_s = 1.0;
  EXPECT_THROW(fitAllanNoiseTerms(c, fo), std::invalid_argument);
  fo = {};
  fo.min_tau_s = 1e6;
  EXPECT_THROW(fitAllanNoiseTerms(c, fo), std::invalid_argument);  // nothing in range
}

TEST(CalibBasicError, RemovesTheoreticalOutputAndReportsEq12) {
  const Geodetic lab{30.53 * kDegToRad, 0.0, 25.0};
  const Eigen::Matrix3d C_nb = dcmFromEuler(Eigen::Vector3d(0.02, -0.01, 1.0));
  const Eigen::Vector3d bg(1e-4, -2e-4, 3e-4), ba(0.01, 0.02, -0.03);
  const double N = 1e-3, dt = 0.01;
  std::mt19937_64 rng(9);
  std::normal_distribution<double> g(0.0, 1.0);
  const Eigen::Vector3d w = C_nb.transpose() * earth::omega_ie_n(lab.lat_rad);
  const Eigen::Vector3d f = -C_nb.transpose() * earth::gravity_n(lab);
  ImuSeries imu;
  for (int k = 1; k <= 60000; ++k) {
    ImuSample s;
    s.t_s = k * dt;
    s.dt_s = dt;
    for (int i = 0; i < 3; ++i) {
      s.dtheta_rad[i] = (w[i] + bg[i] + N / std::sqrt(dt) * g(rng)) * dt;
      s.dvel_m_s[i] = (f[i] + ba[i]) * dt;
    }
    imu.push_back(s);
  }
  const BasicErrorExtraction r = extractBasicErrors(imu, C_nb, lab);
  ASSERT_EQ(r.error.size(), imu.size());
  EXPECT_NEAR(r.duration_s, 600.0, 1e-6);
  EXPECT_LT((r.accel_mean_m_s2 - ba).cwiseAbs().maxCoeff(), 1e-9);  // exact: no accel noise
  EXPECT_LT((r.error[5].dvel_m_s / dt - ba).cwiseAbs().maxCoeff(), 1e-9);
  for (int i = 0; i < 3; ++i) {
    EXPECT_NEAR(r.gyro_white_noise[i], N, 0.02 * N);
    EXPECT_NEAR(r.gyro_D[i], r.gyro_white_noise[i] / std::sqrt(600.0), 1e-15);  // Eq. 12
    EXPECT_LT(std::abs(r.gyro_mean_rad_s[i] - bg[i]), 3.0 * r.gyro_D[i]);
  }
  // The seed's Eq. 18 sign (+g) would leave 2g in the z error of a level pose: check the sign.
  EXPECT_GT(f.z(), -10.0);
  EXPECT_LT(f.z(), -9.7);
  EXPECT_THROW(extractBasicErrors(ImuSeries(1), C_nb, lab), std::invalid_argument);
  imu[3].dt_s = 0.0;
  EXPECT_THROW(extractBasicErrors(imu, C_nb, lab), std::invalid_argument);
}

// Real static recording (ADIS16405, shared/data/real/adis16405_static): the whole hour (0.2 s to read).
TEST(CalibAllan, RealAdis16405GyroNoiseInDatasheetClass) {
  const std::string path = test::sharedDir() + "/data/real/adis16405_static/lab/static.txt";
  GRAFTNAV_REQUIRE_SHARED_PATH(path);
  ImuReadOptions ro;
  ro.nominal_rate_hz = 100.0;
  ro.policy = ImuReadPolicy::real();
  ImuSeries imu = readImu(path, ro);
  const BasicErrorExtraction b =
      extractBasicErrors(imu, Eigen::Matrix3d::Identity(), Geodetic{}, 9.80665);
  const AllanFit g = fitAllanNoiseTerms(allanDeviation(b.error, true));
  for (int a = 0; a < 3; ++a) {
    const double arw_deg_rt_h = g.terms.white_noise[a] * kRadToDeg * 60.0;
    const double bi_deg_h = g.terms.bias_instability[a] * kRadToDeg * 3600.0;
    // ADIS16405 datasheet (Rev. B): ARW 2.0 deg/sqrt(h), in-run bias stability 0.007 deg/s = 25 deg/h.
    // The README's white noise 0.050-0.061 deg/s/sqrt(Hz) = 3.0-3.7 deg/sqrt(h).
    EXPECT_GT(arw_deg_rt_h, 1.0) << a;
    EXPECT_LT(arw_deg_rt_h, 6.0) << a;
    EXPECT_GT(bi_deg_h, 2.0) << a;
    EXPECT_LT(bi_deg_h, 150.0) << a;
    std::printf("ADIS16405 gyro %c: ARW %.2f deg/sqrt(h) (+- %.2f), BI %.1f deg/h (+- %.1f)\n",
                'x' + a, arw_deg_rt_h, g.terms.white_noise_sigma[a] * kRadToDeg * 60.0, bi_deg_h,
                g.terms.bias_instability_sigma[a] * kRadToDeg * 3600.0);
  }
}

}  // namespace
}  // namespace graftnav

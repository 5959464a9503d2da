// Simulator building blocks: rest outputs, motion-script turns, quadrature, GNSS lever arm, lab.
#include <gtest/gtest.h>

#include <cmath>

#include "graftnav/nav/earth.h"
#include "graftnav/sim/gnss_simulator.h"
#include "graftnav/sim/imu_simulator.h"
#include "graftnav/sim/lab_simulator.h"
#include "graftnav/nav/mechanization.h"
#include "graftnav/sim/motion_script.h"
#include "graftnav/sim/sampling_grid.h"
#include "graftnav/nav/rotation.h"
#include "graftnav/sim/track_trajectory.h"
#include "graftnav/nav/units.h"

namespace graftnav {
namespace {

constexpr double kDeg = units::kDegToRad;

MotionScript turnScript(double rate_deg_s) {
  MotionScript s;
  s.start_time_s = 1000.0;
  s.start = {30.5 * kDeg, 114.3 * kDeg, 20.0};
  s.initial_yaw_rad = 30.0 * kDeg;
  s.ramp_s = 1.0;
  using T = MotionSegment::Type;
  s.segments = {{T::kStatic, 5.0},
                {T::kAccelerate, 10.0, 10.0},
                {T::kTurn, 20.0, 0.0, rate_deg_s * kDeg},
                {T::kCruise, 5.0},
                {T::kStop, 8.0},
                {T::kStatic, 2.0}};
  return s;
}

// At rest an ideal IMU senses exactly f_b = -C_bn g_n and omega_ib_b = C_bn omega_ie_n.
TEST(SimModels, RestOutputsAreGravityAndEarthRate) {
  const ScriptTrajectory script(turnScript(10.0));
  for (double t : {1000.0, 1002.5, 1048.5}) {  // first static, last static (after the stop)
    const TrajectoryPoint p = script.at(t);
    const BodyRates r = bodyRates(p);
    const Eigen::Matrix3d C_bn = p.C_nb.transpose();
    EXPECT_LT((r.f_b + C_bn * earth::gravity_n(p.pos)).norm(), 1e-12) << t;
    EXPECT_LT((r.omega_ib_b - C_bn * earth::omega_ie_n(p.pos.lat_rad)).norm(), 1e-18) << t;
  }
  // A tilted body in the lab: the same identities, and the magnitudes are those of gravity and
  // of the Earth rate.
  const Geodetic site{30.53 * kDeg, 114.35 * kDeg, 25.0};
  const Eigen::Matrix3d C_nb = dcmFromEuler({12.0 * kDeg, -33.0 * kDeg, 140.0 * kDeg});
  const LabTrajectory lab(site, C_nb, 2, 0.0, 0.0, 10.0);
  const BodyRates r = bodyRates(lab.at(3.0));
  EXPECT_LT((r.f_b + C_nb.transpose() * earth::gravity_n(site)).norm(), 1e-12);
  EXPECT_NEAR(r.f_b.norm(), earth::gravityMagnitude(site), 1e-12);
  EXPECT_NEAR(r.omega_ib_b.norm(), earth::rotationRate_rad_s(), 1e-18);
}

// A scripted turn yields the commanded yaw rate: the strapdown heading from the ideal increments
// changes by rate * plateau length, and the gyro senses the rate through the (small) roll.
TEST(SimModels, ScriptTurnYieldsCommandedYawRate) {
  const double rate_deg_s = 15.0;
  const ScriptTrajectory trj(turnScript(rate_deg_s));
  const double t_turn = 1000.0 + 5.0 + 10.0;  // start of the turn segment
  const ImuSeries imu = simulateIdealImu(trj, trj.startTime_s(), trj.endTime_s());
  Strapdown sd(trj.navState(trj.startTime_s()));
  double yaw_a = 0.0, yaw_b = 0.0;
  Eigen::Vector3d gyro_sum = Eigen::Vector3d::Zero();
  double gyro_t = 0.0;
  for (const auto& s : imu) {
    sd.step(s);
    if (std::abs(s.t_s - (t_turn + 2.0)) < 1e-9) yaw_a = eulerFromQuat(sd.state().q_nb).z();
    if (std::abs(s.t_s - (t_turn + 10.0)) < 1e-9) yaw_b = eulerFromQuat(sd.state().q_nb).z();
    if (s.t_s > t_turn + 2.0 + 1e-9 && s.t_s <= t_turn + 10.0 + 1e-9) {
      gyro_sum += s.dtheta_rad;
      gyro_t += s.dt_s;
    }
  }
  const double turned = wrapAngle(yaw_b - yaw_a);
  EXPECT_NEAR(turned / 8.0, rate_deg_s * kDeg, 1e-9);
  // On the plateau roll is constant, so omega_ib_b = yaw_rate [ -sin(pitch), sin(roll), cos(roll) ]
  // plus the Earth and transport rates (< 1e-4 rad/s).
  const Eigen::Vector3d e = eulerFromDcm(trj.at(t_turn + 10.0).C_nb);
  const Eigen::Vector3d w = gyro_sum / gyro_t;
  EXPECT_NEAR(w.z() / std::cos(e.x()), rate_deg_s * kDeg, 1e-4);
  EXPECT_LT(e.x(), -0.5 * kDeg);  // a right turn rolls the body to the left (outward)
  // The position at the end is reproduced by the strapdown to millimetres.
  const Eigen::Vector3d d = earth::nedFromGeodetic(trj.at(trj.endTime_s()).pos, sd.state().pos);
  EXPECT_LT(d.head<2>().norm(), 1e-3);
}

// Gauss-Legendre increments equal a fine reference (Richardson-extrapolated composite trapezoid)
// to far below 1e-12 of the increments, on an interval with turning and road oscillations.
TEST(SimModels, GaussLegendreIncrementsMatchFineTrapezoid) {
  MotionScript s = turnScript(20.0);
  const ScriptTrajectory trj(s);
  const GaussLegendreRule gl = gaussLegendreRule(6);
  for (double t1 : {1000.0 + 15.0 + 0.5, 1000.0 + 15.0 + 19.7, 1000.0 + 12.0}) {
    const double t0 = t1 - 0.005;
    const ImuSample inc = idealImuSample(trj, t0, t1, gl);
    auto trap = [&](int n) {
      Eigen::Matrix<double, 6, 1> sum = Eigen::Matrix<double, 6, 1>::Zero();
      for (int i = 0; i <= n; ++i) {
        const BodyRates r = bodyRates(trj.at(t0 + (t1 - t0) * i / n));
        Eigen::Matrix<double, 6, 1> v;
        v << r.omega_ib_b, r.f_b;
        sum += (i == 0 || i == n ? 0.5 : 1.0) * v;
      }
      return Eigen::Matrix<double, 6, 1>(sum * (t1 - t0) / n);
    };
    const Eigen::Matrix<double, 6, 1> ref = (4.0 * trap(512) - trap(256)) / 3.0;
    EXPECT_LT((inc.dtheta_rad - ref.head<3>()).norm(),
              1e-12 * std::max(1e-6, ref.head<3>().norm()));
    EXPECT_LT((inc.dvel_m_s - ref.tail<3>()).norm(), 1e-12 * ref.tail<3>().norm());
  }
  // The rule itself integrates x^(2n-1) and x^(2n-2) exactly and not x^(2n).
  const GaussLegendreRule r = gaussLegendreRule(6);
  double m10 = 0.0, m12 = 0.0;
  for (std::size_t i = 0; i < r.nodes.size(); ++i) {
    m10 += r.weights[i] * std::pow(r.nodes[i], 10);
    m12 += r.weights[i] * std::pow(r.nodes[i], 12);
  }
  EXPECT_NEAR(m10, 2.0 / 11.0, 1e-15);
  EXPECT_GT(std::abs(m12 - 2.0 / 13.0), 1e-6);
}

// A body at rest whose attitude vibrates at 25 / 33 / 38 Hz (about 50 urad): what the road does
// to a car body near the Nyquist frequency of a 100-Hz IMU.
class VibratingBody : public TangentPlaneTrajectory {
 public:
  VibratingBody() : TangentPlaneTrajectory({30.5 * kDeg, 114.3 * kDeg, 20.0}) {}
  double startTime_s() const override { return 0.0; }
  double endTime_s() const override { return 10.0; }
  LocalKinematics local(double t) const override {
    LocalKinematics k;
    for (int a = 0; a < 3; ++a) {
      const double w = 2.0 * M_PI * kFreqHz[a];
      k.euler_rad(a) = kAmpRad[a] * std::sin(w * t + a);
      k.euler_rate_rad_s(a) = kAmpRad[a] * w * std::cos(w * t + a);
    }
    k.euler_rad(2) += 0.4;  // a heading
    return k;
  }

 private:
  static constexpr double kFreqHz[3] = {25.0, 33.0, 38.0};
  static constexpr double kAmpRad[3] = {6e-5, 4e-5, 5e-5};
};

// A sensor at lever arm r measures, on top of the trajectory point's specific force, the
// acceleration of the point C_nb(t) r relative to it, rotated into the body: here from a
// numerical second derivative of C_nb(t) r and a fine quadrature, a route independent of the
// simulator's end-rate formula (rms error 8e-7 of the signal). The increment-series lever arm of
// the error model (5-point node rates), which the case simulator used before, is 43 % off here.
TEST(SimModels, LeverArmIncrementsFollowVibrationNearNyquist) {
  const VibratingBody trj;
  const Eigen::Vector3d r(0.3, -0.2, 0.5);
  IdealImuOptions opt;
  opt.rate_hz = 100.0;
  opt.quadrature_nodes = 4;
  const ImuSeries plain = simulateIdealImu(trj, 1.0, 3.0, opt);
  opt.lever_arm_b_m = r;
  const ImuSeries arm = simulateIdealImu(trj, 1.0, 3.0, opt);
  ASSERT_EQ(plain.size(), arm.size());
  const GaussLegendreRule fine = gaussLegendreRule(16);
  const auto pointAccel_b = [&](double t) {  // C_bn d^2/dt^2 (C_nb r), central difference
    const double h = 1e-5;
    const Eigen::Vector3d a_n =
        (trj.at(t + h).C_nb * r - 2.0 * trj.at(t).C_nb * r + trj.at(t - h).C_nb * r) / (h * h);
    return Eigen::Vector3d(trj.at(t).C_nb.transpose() * a_n);
  };
  double err2 = 0.0, sig2 = 0.0;
  for (const ImuSample& s : arm) {
    const double t0 = s.t_s - s.dt_s, half = 0.5 * s.dt_s, mid = t0 + half;
    Eigen::Vector3d expected = Eigen::Vector3d::Zero();
    for (std::size_t i = 0; i < fine.nodes.size(); ++i)
      expected += fine.weights[i] * half * pointAccel_b(mid + half * fine.nodes[i]);
    const std::size_t k = &s - arm.data();
    const Eigen::Vector3d got = s.dvel_m_s - plain[k].dvel_m_s;
    err2 += (got - expected).squaredNorm();
    sig2 += expected.squaredNorm();
    EXPECT_EQ(s.dtheta_rad, plain[k].dtheta_rad);  // a lever arm does not change the rotation
  }
  // Left out by the independent route: the Earth rate's share (~1e-5 of this).
  EXPECT_LT(std::sqrt(err2 / sig2), 1e-3)
      << "rms lever-arm increment " << std::sqrt(sig2 / arm.size());
}

// The antenna sits at pos + C_nb r_b; noise has the configured spread.
TEST(SimModels, GnssLeverArmGeometryAndNoise) {
  const ScriptTrajectory trj(turnScript(10.0));
  GnssSimOptions opt;
  opt.lever_arm_b_m = {1.0, -0.5, -1.5};
  opt.add_noise = false;
  const GnssSeries clean = simulateGnss(trj, trj.startTime_s(), trj.endTime_s(), opt, 7);
  ASSERT_EQ(clean.size(), static_cast<std::size_t>(trj.endTime_s() - trj.startTime_s()) + 1);
  for (const auto& f : clean) {
    const TrajectoryPoint p = trj.at(f.t_s);
    const Eigen::Vector3d d = earth::nedFromGeodetic(p.pos, f.pos);
    EXPECT_LT((d - p.C_nb * opt.lever_arm_b_m).norm(), 1e-6);
  }
  // Known answer: heading 30 deg, level at the start: forward 1 m is (cos 30, sin 30) N/E,
  // right -0.5 m is -0.5 (-sin 30, cos 30), up 1.5 m is -1.5 down.
  const Eigen::Vector3d d0 =
      earth::nedFromGeodetic(trj.at(clean.front().t_s).pos, clean.front().pos);
  const double c = std::cos(30 * kDeg), s = std::sin(30 * kDeg);
  EXPECT_LT((d0 - Eigen::Vector3d(c + 0.5 * s, s - 0.5 * c, -1.5)).norm(), 1e-6);

  opt.add_noise = true;
  opt.noise_std_neu_m = {0.03, 0.05, 0.1};
  LabTrajectory still({0.5, 2.0, 10.0}, Eigen::Matrix3d::Identity(), 2, 0.0, 0.0, 4000.0);
  const GnssSeries noisy = simulateGnss(still, 0.0, 4000.0, opt, 11);
  Eigen::Vector3d var = Eigen::Vector3d::Zero();
  const Geodetic ant =
      antennaPosition(still.at(0.0).pos, Eigen::Matrix3d::Identity(), opt.lever_arm_b_m);
  for (const auto& f : noisy) {
    EXPECT_EQ(f.std_ned_m, opt.noise_std_neu_m);
    var += earth::nedFromGeodetic(ant, f.pos).cwiseAbs2();
  }
  const Eigen::Vector3d sd = (var / noisy.size()).cwiseSqrt();
  for (int a = 0; a < 3; ++a) EXPECT_NEAR(sd[a] / opt.noise_std_neu_m[a], 1.0, 0.06) << a;
  // Same seed, same noise.
  EXPECT_EQ(simulateGnss(still, 0.0, 10.0, opt, 11)[5].pos.lat_rad, noisy[5].pos.lat_rad);
}

// Lab poses point the named axis up; whole rate-table turns integrate to 360 deg plus the Earth
// rate's vertical component along the axis.
TEST(SimModels, LabPosesAndRateTable) {
  LabSimOptions opt;
  opt.static_duration_s = 2.0;
  opt.six_position_duration_s = 1.0;
  opt.rate_table_rad_s = {30 * kDeg, 100 * kDeg};
  opt.rate_table_turns = 1;
  opt.tilt_duration_s = 1.0;
  opt.tilt_euler_rad["t1"] = Eigen::Vector3d(10, 20, 30) * kDeg;
  const std::vector<LabSession> s = simulateLabSessions(opt);
  ASSERT_EQ(s.size(), 1u + 6u + 12u + 1u);
  const Geodetic site{opt.latitude_rad, opt.longitude_rad, opt.height_m};
  const double g = earth::gravityMagnitude(site);
  const double we_up = earth::rotationRate_rad_s() * std::sin(opt.latitude_rad);
  for (const auto& ses : s) {
    const std::string& p = ses.relative_path;
    if (p.rfind("lab/six_position/", 0) == 0) {
      const int axis = p[17] - 'x';
      const bool up = p.find("_up") != std::string::npos;
      const Eigen::Vector3d f = ses.ideal.front().dvel_m_s / ses.ideal.front().dt_s;
      // Specific force points up: +g on an axis that points up.
      EXPECT_NEAR(f[axis], up ? g : -g, 1e-4 * g) << p;
      EXPECT_NEAR(f.norm(), g, 1e-10) << p;
    }
    if (p.rfind("lab/rate/", 0) == 0) {
      const int axis = p[9] - 'x';
      const int sign = p.find("_pos_") != std::string::npos ? 1 : -1;
      Eigen::Vector3d th = Eigen::Vector3d::Zero();
      double T = 0.0;
      for (const auto& x : ses.ideal) {
        th += x.dtheta_rad;
        T += x.dt_s;
      }
      // Axis up: it senses +we sin(lat) (Earth rate up component) on top of the table rate.
      EXPECT_NEAR(th[axis], sign * 2.0 * units::kPi + we_up * T, 1e-9) << p;
      for (int o = 0; o < 3; ++o) {
        if (o != axis) {
          EXPECT_LT(std::abs(th[o]), 2e-5 * T) << p;
        }
      }
      EXPECT_NEAR(T,
                  2.0 * units::kPi / (p.find("_100") != std::string::npos ? 100 * kDeg : 30 * kDeg),
                  1e-9)
          << p;
    }
  }
  // A rate that does not give whole turns on the sample grid is refused.
  opt.rate_table_rad_s = {7.0 * kDeg};
  EXPECT_THROW(simulateLabSessions(opt), std::invalid_argument);
}

}  // namespace
}  // namespace graftnav

namespace graftnav {
namespace {

TEST(SamplingGrid, WholeMultiplesOfThePeriodInsideTheSpanEndsIncluded) {
  const std::vector<double> t = uniformEpochs_s(100.05, 101.0, 5.0);
  ASSERT_EQ(t.size(), 5u);  // 100.2 .. 101.0; 100.0 lies before the span
  EXPECT_DOUBLE_EQ(t.front(), 100.2);
  EXPECT_DOUBLE_EQ(t.back(), 101.0);
  for (std::size_t i = 1; i < t.size(); ++i) EXPECT_NEAR(t[i] - t[i - 1], 0.2, 1e-9);
  EXPECT_EQ(uniformEpochs_s(100.0, 100.0, 1.0).size(), 1u);  // an end on the grid is kept
  EXPECT_TRUE(uniformEpochs_s(100.1, 100.9, 1.0).empty());   // no whole second inside
  EXPECT_THROW(uniformEpochs_s(0.0, 1.0, 0.0), std::invalid_argument);
  EXPECT_THROW(uniformEpochs_s(0.0, std::nan(""), 1.0), std::invalid_argument);
}

}  // namespace
}  // namespace graftnav

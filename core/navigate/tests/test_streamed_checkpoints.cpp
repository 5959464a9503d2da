// The check point errors of a solution streamed epoch by epoch equal evaluateAtCheckpoints on the
// held series bit for bit: sparse check points (the interpolator's binary search), dense ones
// (its step from the last bracket), check points on epoch times, duplicate epoch times, windows
// that overlap or lie outside the solution, and check points within the end tolerance.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "graftnav/eval/gnss_latency.h"
#include "graftnav/nav/nav_interp.h"
#include "graftnav/navigate/streamed_checkpoints.h"
#include "graftnav/nav/rotation.h"

namespace graftnav {
namespace {

// A curving, accelerating track with noise on every epoch, its height around sea level: every
// interpolated column differs from its ends, and with heights of both signs a + (b - a) is not
// always b to the last bit (which bracket an epoch time gets shows in the numbers).
NavSeries curvingTrack(double t0_s, double dt_s, int epochs) {
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 1.0);
  NavSeries s;
  for (int k = 0; k < epochs; ++k) {
    const double t = k * dt_s;
    NavState st;
    st.t_s = t0_s + t;
    st.pos.lat_rad = 0.5 + 1e-6 * t + 1e-9 * t * t + 1e-8 * noise(rng);
    st.pos.lon_rad = 2.0 + 1e-6 * std::sin(0.05 * t) + 1e-8 * noise(rng);
    st.pos.h_m = 0.01 * std::cos(0.1 * t) + 0.05 * noise(rng);
    st.v_n = Eigen::Vector3d(6.4 + 0.01 * t, 6.4 * std::cos(0.05 * t), 0.03 * std::sin(0.1 * t));
    st.q_nb = quatFromEuler(Eigen::Vector3d(0.01 * std::sin(t), 0.02, 0.05 * t));
    s.push_back(st);
  }
  return s;
}

// Fixes at `times`, millimetres off the track (small residuals keep the last bits of the
// interpolated state in the numbers).
GnssSeries fixesAt(const std::vector<double>& times, const NavSeries& track) {
  std::mt19937 rng(7);
  std::normal_distribution<double> n(0.0, 1.0);
  GnssSeries g;
  for (double t : times) {
    GnssFix f;
    f.t_s = t;
    f.pos = interpolateNav(track, std::clamp(t, track.front().t_s, track.back().t_s))->pos;
    f.pos.lat_rad += 1e-10 * n(rng);
    f.pos.lon_rad += 1e-10 * n(rng);
    f.pos.h_m += 1e-3 * n(rng);
    g.push_back(f);
  }
  return g;
}

CheckpointEvaluation streamed(const NavSeries& track, const GnssSeries& g,
                              const std::vector<TimeWindow>& w, const Eigen::Vector3d& lever) {
  StreamedCheckpoints s(g, w, lever);
  for (const NavState& st : track) s.add(st);
  return s.finish();
}

void expectSame(const CheckpointEvaluation& a, const CheckpointEvaluation& b) {
  ASSERT_EQ(a.windows.size(), b.windows.size());
  EXPECT_EQ(a.n, b.n);
  EXPECT_EQ(a.rms_h_m, b.rms_h_m);
  EXPECT_EQ(a.rms_v_m, b.rms_v_m);
  EXPECT_EQ(a.rms_of_max_h_m, b.rms_of_max_h_m);
  EXPECT_EQ(a.rms_of_max_v_m, b.rms_of_max_v_m);
  EXPECT_EQ(a.mean_of_max_h_m, b.mean_of_max_h_m);
  for (std::size_t k = 0; k < a.windows.size(); ++k) {
    EXPECT_EQ(a.windows[k].window.start_s, b.windows[k].window.start_s) << k;
    EXPECT_EQ(a.windows[k].n, b.windows[k].n) << k;
    EXPECT_EQ(a.windows[k].rms_h_m, b.windows[k].rms_h_m) << k;
    EXPECT_EQ(a.windows[k].max_h_m, b.windows[k].max_h_m) << k;
    EXPECT_EQ(a.windows[k].rms_v_m, b.windows[k].rms_v_m) << k;
    EXPECT_EQ(a.windows[k].max_v_m, b.windows[k].max_v_m) << k;
    EXPECT_EQ(a.windows[k].last_h_m, b.windows[k].last_h_m) << k;
  }
}

const Eigen::Vector3d kLever(0.1, -0.2, -1.2);

TEST(StreamedCheckpoints, SparseCheckPointsOnEpochTimesGiveTheHeldNumbers) {
  // 256 Hz (exact binary times), fixes at whole seconds: each one on an epoch, 256 epochs apart.
  const NavSeries track = curvingTrack(1000.0, 1.0 / 256.0, 256 * 120 + 1);
  std::vector<double> times;
  for (int k = 0; k <= 120; ++k) times.push_back(1000.0 + k);
  const GnssSeries g = fixesAt(times, track);
  const std::vector<TimeWindow> w = {{1010.0, 1030.0}, {1050.0, 1080.0}, {1100.0, 1120.0}};
  const CheckpointEvaluation held = evaluateAtCheckpoints(track, g, w, kLever);
  ASSERT_EQ(held.n, 21 + 31 + 21);
  expectSame(streamed(track, g, w, kLever), held);
}

TEST(StreamedCheckpoints, DenseCheckPointsDuplicateEpochsAndOverlappingWindows) {
  // 64 Hz with a repeated epoch, fixes at 8 Hz (8 epochs apart: the interpolator steps on from
  // its last bracket) on and between epochs.
  NavSeries track = curvingTrack(500.0, 1.0 / 64.0, 64 * 40 + 1);
  track.insert(track.begin() + 700, track[700]);
  std::vector<double> times;
  for (int k = 0; k <= 8 * 40; ++k) times.push_back(500.0 + k / 8.0 + (k % 3 == 0 ? 0.004 : 0.0));
  const GnssSeries g = fixesAt(times, track);
  const std::vector<TimeWindow> w = {{505.0, 515.0}, {510.0, 520.0}, {530.0, 541.0}};
  const CheckpointEvaluation held = evaluateAtCheckpoints(track, g, w, kLever);
  ASSERT_GT(held.n, 200);
  expectSame(streamed(track, g, w, kLever), held);
}

TEST(StreamedCheckpoints, EndsWithinToleranceAndWindowsOutsideTheSolution) {
  const NavSeries track = curvingTrack(200.0, 0.005, 2001);  // 200.0 .. 210.0
  const GnssSeries g =
      fixesAt({199.0, 200.0 - 5e-7, 200.0, 200.5, 209.5, 210.0, 210.0 + 5e-7, 211.0}, track);
  const std::vector<TimeWindow> w = {{190.0, 199.5}, {199.0, 201.0}, {209.0, 212.0}, {220, 230}};
  const CheckpointEvaluation held = evaluateAtCheckpoints(track, g, w, kLever);
  ASSERT_EQ(held.windows.size(), 2u);
  EXPECT_EQ(held.n, 3 + 3);
  expectSame(streamed(track, g, w, kLever), held);
  // One epoch: no residual at all, as fixResiduals gives for a series that short.
  expectSame(streamed({track.front()}, g, w, kLever),
             evaluateAtCheckpoints({track.front()}, g, w, kLever));
}

TEST(StreamedCheckpoints, CheckPointsOutOfOrderAreRefused) {
  const NavSeries track = curvingTrack(0.0, 0.01, 10);
  EXPECT_THROW(StreamedCheckpoints(fixesAt({1.0, 0.5}, track), {{0.0, 2.0}}, kLever),
               std::invalid_argument);
}

}  // namespace
}  // namespace graftnav

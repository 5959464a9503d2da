// Spools: what is written comes back bit for bit, in any block size and from several threads at
// once; misuse (reading before the end of writing, past the end) is refused.
#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <stdexcept>
#include <thread>
#include <vector>

#include "graftnav/io/imu_recording.h"
#include "graftnav/io/nav_spool.h"
#include "graftnav/io/record_spool.h"

namespace graftnav {
namespace {

ImuSeries samples(int n) {
  ImuSeries s;
  for (int k = 1; k <= n; ++k) {
    ImuSample x;
    x.t_s = 100.0 + k / 3.0;
    x.dt_s = 1.0 / 3.0;
    x.dtheta_rad = {std::sin(k * 0.1), 1e-300 * k, -k / 7.0};
    x.dvel_m_s = {std::cos(k * 0.2), std::nextafter(1.0, 2.0), k * 1e7};
    if (k % 2 == 0) x.temperature_degC = 20.0 + k / 9.0;  // NaN on odd samples
    s.push_back(x);
  }
  return s;
}

TEST(RecordSpool, ReadsBackWhatWasWrittenFromSeveralThreads) {
  RecordSpool spool(3);
  for (int k = 0; k < 100000; ++k) {
    const double r[3] = {k / 3.0, -k * 1e-9, std::numeric_limits<double>::denorm_min() * k};
    spool.append(r);
  }
  EXPECT_THROW(spool.read(0, 1, nullptr), std::logic_error);  // before finish()
  spool.finish();
  ASSERT_EQ(spool.size(), 100000u);
  EXPECT_THROW(spool.append(std::vector<double>(3).data()), std::logic_error);
  std::vector<double> out;
  EXPECT_THROW(spool.read(99999, 2, &out), std::out_of_range);
  auto check = [&spool](std::size_t from, int* bad) {
    std::vector<double> r;
    for (std::size_t i = from; i < spool.size(); i += 997) {
      spool.read(i, 1, &r);
      const double k = static_cast<double>(i);
      if (r[0] != k / 3.0 || r[1] != -k * 1e-9 ||
          r[2] != std::numeric_limits<double>::denorm_min() * k)
        ++*bad;
    }
  };
  int bad_a = 0, bad_b = 0;
  std::thread a(check, 0, &bad_a), b(check, 500, &bad_b);
  a.join();
  b.join();
  EXPECT_EQ(bad_a + bad_b, 0);
}

TEST(ImuRecording, ASpooledRecordingGivesTheSamplesBitForBitInAnyBlockSize) {
  const ImuSeries s = samples(1001);
  for (std::size_t block : {1u, 64u, 5000u}) {
    const ImuRecording r = spooledRecording(heldRecording(s).pass, block);
    EXPECT_EQ(r.samples, s.size());
    EXPECT_EQ(r.first.t_s, s.front().t_s);
    EXPECT_EQ(r.last.dvel_m_s, s.back().dvel_m_s);
    EXPECT_DOUBLE_EQ(r.beginTime_s(), 100.0);
    std::size_t blocks = 0;
    r.pass([&blocks, block](const ImuSeries& b) {
      ++blocks;
      EXPECT_LE(b.size(), block);
    });
    EXPECT_EQ(blocks, (s.size() + block - 1) / block);
    const ImuSeries back = collectRecording(r);
    ASSERT_EQ(back.size(), s.size());
    for (std::size_t k = 0; k < s.size(); ++k) {
      ASSERT_EQ(back[k].t_s, s[k].t_s) << k;
      ASSERT_EQ(back[k].dt_s, s[k].dt_s) << k;
      ASSERT_EQ(back[k].dtheta_rad, s[k].dtheta_rad) << k;
      ASSERT_EQ(back[k].dvel_m_s, s[k].dvel_m_s) << k;
      ASSERT_EQ(back[k].hasTemperature(), s[k].hasTemperature()) << k;
      if (s[k].hasTemperature()) {
        ASSERT_EQ(back[k].temperature_degC, s[k].temperature_degC);
      }
    }
  }
  EXPECT_THROW(spooledRecording([](const ImuBlockFn&) {}), std::invalid_argument);
}

TEST(NavSpool, EveryPassGivesTheStatesBitForBit) {
  NavSeries states;
  for (int k = 0; k < 5000; ++k) {
    NavState x;
    x.t_s = 1e5 + k * 0.005;
    x.pos = {0.5 + k * 1e-9, -2.0 / (k + 1), 1e3 / 7.0};
    x.v_n = {k / 11.0, -1e-12, 3.0};
    x.q_nb = Eigen::Quaterniond(Eigen::AngleAxisd(k * 1e-3, Eigen::Vector3d(1, 2, 3).normalized()));
    x.gnss_week = 2100 + k % 2;
    states.push_back(x);
  }
  std::unique_ptr<NavSource> source = seriesNavSource(states);
  const NavSpool spool = spoolNav(*source);
  EXPECT_EQ(spool.size(), states.size());
  EXPECT_NEAR(spool.rateHz(), 200.0, 1e-6);
  for (int pass = 0; pass < 2; ++pass) {
    std::unique_ptr<NavSource> p = spool.opener()();
    NavState x;
    std::size_t k = 0;
    while (p->next(&x)) {
      ASSERT_LT(k, states.size());
      ASSERT_EQ(x.t_s, states[k].t_s) << k;
      ASSERT_EQ(x.pos.lat_rad, states[k].pos.lat_rad) << k;
      ASSERT_EQ(x.pos.lon_rad, states[k].pos.lon_rad) << k;
      ASSERT_EQ(x.pos.h_m, states[k].pos.h_m) << k;
      ASSERT_EQ(x.v_n, states[k].v_n) << k;
      ASSERT_EQ(x.q_nb.coeffs(), states[k].q_nb.coeffs()) << k;
      ASSERT_EQ(x.gnss_week, states[k].gnss_week) << k;
      ++k;
    }
    EXPECT_EQ(k, states.size());
  }
}

}  // namespace
}  // namespace graftnav

// Binning a record read in blocks (StreamedBinning) against binning it held whole: the bin means
// of the record's cumulative integral (CumulativeImu over the whole series), its temperature and
// its within-bin vibration, number by number.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "graftnav/mismatch/common_grid.h"
#include "graftnav/mismatch/streamed_binning.h"
#include "mismatch_signal_fixture.h"

namespace graftnav {
namespace {

using namespace mismatch_test;

// The held binning: every edge from the whole record's cumulative integral, the vibration of
// the samples whose end tag falls inside each (shifted) bin about its mean.
BinnedImu heldBinning(const ImuSeries& imu, const GridSpec& grid, double shift,
                      const ImuSampleMap& map) {
  const CumulativeImu cum(imu, map);
  BinnedImu out;
  const int n = grid.count;
  out.omega_rad_s.resize(n, 3);
  out.f_m_s2.resize(n, 3);
  out.temperature_degC.setConstant(n, std::nan(""));
  out.f_within_rms_m_s2.setZero(n);
  for (int i = 0; i < n; ++i) {
    const double a = grid.binStart(i) + shift, b = grid.binStart(i + 1) + shift;
    const Vector6d mean = (cum.at(b) - cum.at(a)) / grid.bin_s;
    out.omega_rad_s.row(i) = mean.head<3>().transpose();
    out.f_m_s2.row(i) = mean.tail<3>().transpose();
    if (cum.hasTemperature())
      out.temperature_degC(i) =
          (cum.temperatureIntegralAt(b) - cum.temperatureIntegralAt(a)) / grid.bin_s;
  }
  std::vector<double> sum_sq(n, 0.0);
  std::vector<int> count(n, 0);
  for (const ImuSample& raw : imu) {
    const int i = static_cast<int>(std::floor((raw.t_s - shift - grid.t_begin_s) / grid.bin_s));
    if (i < 0 || i >= n) continue;
    const Eigen::Vector3d f = (map ? map(raw) : raw).dvel_m_s / raw.dt_s;
    sum_sq[i] += (f - out.f_m_s2.row(i).transpose()).squaredNorm();
    ++count[i];
  }
  for (int i = 0; i < n; ++i)
    out.f_within_rms_m_s2(i) = count[i] > 0 ? std::sqrt(sum_sq[i] / count[i]) : 0.0;
  return out;
}

// A 200 Hz car record with temperature, three lost samples (the interpolation falls back to the
// Hermite curve around them) and a jittered stretch.
ImuSeries testRecord() {
  ImuSeries imu = sampleMotion(carMotion(7), 200.0, 120.0);
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> jitter(-2e-4, 2e-4);
  for (std::size_t k = 0; k < imu.size(); ++k) {
    imu[k].temperature_degC = 20.0 + 1e-3 * static_cast<double>(k);
    if (k > 9000 && k < 9400) imu[k].t_s += jitter(rng);
  }
  imu.erase(imu.begin() + 5000, imu.begin() + 5003);
  for (std::size_t k = 1; k < imu.size(); ++k) imu[k].dt_s = imu[k].t_s - imu[k - 1].t_s;
  return imu;
}

void expectSameBins(const BinnedImu& held, const BinnedImu& streamed, const std::string& what) {
  ASSERT_EQ(held.omega_rad_s.rows(), streamed.omega_rad_s.rows()) << what;
  int differing = 0;
  for (int i = 0; i < held.omega_rad_s.rows(); ++i) {
    for (int c = 0; c < 3; ++c) {
      differing += held.omega_rad_s(i, c) != streamed.omega_rad_s(i, c);
      differing += held.f_m_s2(i, c) != streamed.f_m_s2(i, c);
    }
    const double th = held.temperature_degC(i), ts = streamed.temperature_degC(i);
    differing += !(th == ts || (std::isnan(th) && std::isnan(ts)));
    differing += held.f_within_rms_m_s2(i) != streamed.f_within_rms_m_s2(i);
  }
  EXPECT_EQ(differing, 0) << what;
}

TEST(MismatchStreamedBinning, BlocksGiveTheHeldBinsNumberByNumber) {
  const ImuSeries imu = testRecord();
  // The grid starts before the record and ends after it (the integral's extrapolations).
  GridSpec grid;
  grid.bin_s = 0.05;
  grid.t_begin_s = imu.front().t_s - imu.front().dt_s - 0.12;
  grid.count = static_cast<int>((imu.back().t_s - grid.t_begin_s) / grid.bin_s) + 3;
  const ImuSampleMap abs_map = [](const ImuSample& s) {
    ImuSample out = s;
    out.dtheta_rad = s.dtheta_rad.cwiseAbs();
    out.dvel_m_s = s.dvel_m_s.cwiseAbs();
    return out;
  };
  for (const double shift : {0.0, -0.0137, 0.4}) {
    for (const bool mapped : {false, true}) {
      const ImuSampleMap map = mapped ? abs_map : ImuSampleMap();
      const BinnedImu held = heldBinning(imu, grid, shift, map);
      // Blocks of 37 samples: boundaries fall inside the 10-sample bins.
      StreamedBinning streamed(grid, shift, map);
      for (std::size_t k = 0; k < imu.size(); k += 37)
        streamed.add(ImuSeries(imu.begin() + k, imu.begin() + std::min(imu.size(), k + 37)));
      EXPECT_EQ(streamed.samplesAdded(), imu.size());
      const std::string what = "shift " + std::to_string(shift) + (mapped ? ", |x|" : "");
      expectSameBins(held, streamed.finish(), what);
      expectSameBins(held, binImu(imu, grid, shift, map), "binImu, " + what);
    }
  }
}

// A binning of the rates only gives the whole binning's rates bit for bit and no other column.
TEST(MismatchStreamedBinning, RatesOnlyAreTheWholeBinningsRates) {
  const ImuSeries imu = testRecord();
  GridSpec grid;
  grid.bin_s = 0.01;
  grid.t_begin_s = imu.front().t_s;
  grid.count = static_cast<int>((imu.back().t_s - grid.t_begin_s) / grid.bin_s) - 1;
  const BinnedImu all = binImu(imu, grid, 0.013);
  StreamedBinning rates(grid, 0.013, {}, BinnedColumns::rates_only);
  for (std::size_t k = 0; k < imu.size(); k += 37)
    rates.add(ImuSeries(imu.begin() + k, imu.begin() + std::min(imu.size(), k + 37)));
  const BinnedImu only = rates.finish();
  ASSERT_EQ(only.omega_rad_s.rows(), grid.count);
  for (int i = 0; i < grid.count; ++i)
    for (int a = 0; a < 3; ++a)
      ASSERT_EQ(only.omega_rad_s(i, a), all.omega_rad_s(i, a)) << "bin " << i << " axis " << a;
  EXPECT_EQ(only.f_m_s2.size(), 0);
  EXPECT_EQ(only.temperature_degC.size(), 0);
  EXPECT_EQ(only.f_within_rms_m_s2.size(), 0);
}

// A sample without a temperature leaves every bin's temperature NaN, as in the held binning.
TEST(MismatchStreamedBinning, ARecordWithoutTemperatureHasNone) {
  ImuSeries imu = testRecord();
  imu[4321].temperature_degC = std::nan("");
  const GridSpec grid = commonGrid(imu, imu, 0.05);
  StreamedBinning streamed(grid);
  streamed.add(imu);
  const BinnedImu b = streamed.finish();
  EXPECT_TRUE(b.temperature_degC.array().isNaN().all());
  expectSameBins(heldBinning(imu, grid, 0.0, {}), b, "no temperature");
}

TEST(MismatchStreamedBinning, RefusesWhatTheCumulativeIntegralRefuses) {
  const GridSpec grid{0.0, 0.05, 20};
  EXPECT_THROW(StreamedBinning(grid).finish(), std::invalid_argument);
  ImuSeries imu = sampleMotion(carMotion(3), 200.0, 2.0);
  imu[100].t_s = imu[99].t_s;
  StreamedBinning streamed(grid);
  try {
    streamed.add(imu);
    ADD_FAILURE() << "a repeated time tag was accepted";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("sample 100"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace graftnav

// Reading a 1 h, 200 Hz IMU file (720 000 lines) must take well under 1 s. The file is
// written once to /tmp (full-precision increments, as the simulator writes them) and read per
// iteration; writing is measured too.
#include <benchmark/benchmark.h>

#include <cstdio>
#include <filesystem>
#include <random>
#include <string>

#include "graftnav/io/imu_io.h"

namespace {

constexpr double kRateHz = 200.0;
constexpr int kSamples = 3600 * 200;

graftnav::ImuSeries makeImu() {
  std::mt19937 rng(42);
  std::normal_distribution<double> g(0.0, 1.0);
  graftnav::ImuSeries imu(kSamples);
  for (int k = 0; k < kSamples; ++k) {
    auto& s = imu[k];
    s.t_s = 456300.0 + (k + 1) / kRateHz;
    s.dt_s = 1.0 / kRateHz;
    s.dtheta_rad = Eigen::Vector3d(g(rng), g(rng), g(rng)) * 1e-4;
    s.dvel_m_s = Eigen::Vector3d(0.01 * g(rng), 0.01 * g(rng), -9.8 / kRateHz + 0.01 * g(rng));
  }
  return imu;
}

const std::string& benchFile() {
  static const std::string path = [] {
    const std::string p =
        (std::filesystem::temp_directory_path() / "graftnav_bench_imu_1h_200hz.txt").string();
    graftnav::writeImu(p, makeImu());
    return p;
  }();
  return path;
}

void BM_ReadImu1h200Hz(benchmark::State& state) {
  const std::string& path = benchFile();
  graftnav::ImuReadOptions options;
  options.nominal_rate_hz = kRateHz;
  for (auto _ : state) {
    graftnav::ImuSeries imu = graftnav::readImu(path, options);
    benchmark::DoNotOptimize(imu.data());
    if (imu.size() != static_cast<std::size_t>(kSamples)) state.SkipWithError("wrong sample count");
  }
  state.counters["lines"] = kSamples;
  state.counters["MB"] = static_cast<double>(std::filesystem::file_size(path)) / 1e6;
}
BENCHMARK(BM_ReadImu1h200Hz)->Unit(benchmark::kMillisecond)->MinTime(2.0);

void BM_WriteImu1h200Hz(benchmark::State& state) {
  const graftnav::ImuSeries imu = makeImu();
  const std::string path =
      (std::filesystem::temp_directory_path() / "graftnav_bench_imu_write.txt").string();
  for (auto _ : state) graftnav::writeImu(path, imu);
  std::remove(path.c_str());
}
BENCHMARK(BM_WriteImu1h200Hz)->Unit(benchmark::kMillisecond)->Iterations(2);

}  // namespace

BENCHMARK_MAIN();

// Mechanizing one hour of 200 Hz increments (target: under 1 s on the 2-core machine).
#include <benchmark/benchmark.h>

#include <random>

#include "graftnav/nav/earth.h"
#include "graftnav/nav/mechanization.h"
#include "graftnav/nav/rotation.h"

namespace {

graftnav::ImuSeries makeHour() {
  const double dt = 0.005;
  const int n = 3600 * 200;
  graftnav::ImuSeries imu(n);
  std::mt19937_64 rng(1);
  std::normal_distribution<double> nd(0.0, 1.0);
  for (int k = 0; k < n; ++k) {
    auto& s = imu[k];
    s.t_s = 456300.0 + (k + 1) * dt;
    s.dt_s = dt;
    s.dtheta_rad = Eigen::Vector3d(1e-4 * nd(rng), 1e-4 * nd(rng), 5e-4 * std::sin(k * 1e-3)) * dt;
    s.dvel_m_s = Eigen::Vector3d(0.3 * std::sin(k * 2e-4), 0.05 * nd(rng), -9.79) * dt;
  }
  return imu;
}

void BM_MechanizeOneHour200Hz(benchmark::State& state) {
  const graftnav::ImuSeries imu = makeHour();
  graftnav::NavState s0;
  s0.t_s = 456300.0;
  s0.pos = {30.4 * graftnav::kDegToRad, 114.4 * graftnav::kDegToRad, 20.0};
  for (auto _ : state) {
    graftnav::Strapdown sd(s0);
    for (const auto& s : imu) sd.step(s);
    benchmark::DoNotOptimize(sd.state().pos.lat_rad);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(imu.size()));
}
BENCHMARK(BM_MechanizeOneHour200Hz)->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace

BENCHMARK_MAIN();

// Batch factor-graph smoother and sliding window: time versus data length (200 Hz IMU, 1 Hz
// GNSS, 60 s outages every 180 s after 300 s), MEMS-grade errors. The truth is made by
// construction (the test scenario of tests/support/graph_scenario.h): ideal increments mechanized by Strapdown.
//   build-x/bench_fgo --benchmark_filter=Batch/60   (1 h)
#include <benchmark/benchmark.h>

#include <map>
#include <memory>

#include "graph_scenario.h"
#include "graftnav/graph/fgo_solver.h"

namespace {

using namespace graftnav;

const EstimationProblem& problemOfMinutes(int minutes) {
  static std::map<int, std::unique_ptr<EstimationProblem>> cache;
  auto& slot = cache[minutes];
  if (slot) return *slot;
  const test::Scenario sc = test::makeScenario(minutes * 60.0, 200.0, 12.0);
  test::ImuErrors err;
  err.bg_rad_s << 4e-5, -3e-5, 5e-5;
  err.ba_m_s2 << 8e-3, -6e-3, 5e-3;
  err.arw_rad_sqrt_s = 4.4e-5;
  err.vrw_m_s_sqrt_s = 1e-3;
  slot = std::make_unique<EstimationProblem>();
  EstimationProblem& p = *slot;
  p.imu = test::addImuErrors(sc.ideal, err, 1);
  p.lever_arm_b_m << 0.3, -0.2, -1.1;
  p.gnss = test::makeGnss(sc, p.lever_arm_b_m, 1.0, 0.02, 2);
  p.initial = sc.truth.front();
  const double t0 = p.initial.t_s, t1 = sc.truth.back().t_s;
  for (double s = t0 + 300.0; s + 60.0 < t1 - 10.0; s += 180.0) p.outages.push_back({s, s + 60.0});
  p.imu_profile.arw_rad_sqrt_s = err.arw_rad_sqrt_s;
  p.imu_profile.vrw_m_s_sqrt_s = err.vrw_m_s_sqrt_s;
  p.imu_profile.gyro_bias_instability_rad_s = 5e-5;
  p.imu_profile.accel_bias_instability_m_s2 = 1e-2;
  p.initial_sigma << 0.05, 0.05, 0.05, 0.02, 0.02, 0.02, 1e-3, 1e-3, 5e-3;
  return p;
}

void BM_BatchFgo(benchmark::State& state) {
  const int minutes = static_cast<int>(state.range(0));
  const EstimationProblem& p = problemOfMinutes(minutes);
  FgoOptions opt;
  FgoReport rep;
  for (auto _ : state) {
    rep = FgoReport{};
    NavSolution sol = solveBatchFgo(p, opt, &rep);
    benchmark::DoNotOptimize(sol.states.data());
  }
  state.counters["data_min"] = minutes;
  state.counters["nodes"] = rep.nodes;
  state.counters["window_init_s"] = rep.window_time_s;
  state.counters["batch_s"] = rep.batch_time_s;
  state.counters["output_s"] = rep.output_time_s;
  state.counters["iterations"] = rep.iterations;
}
BENCHMARK(BM_BatchFgo)
    ->Arg(15)
    ->Arg(30)
    ->Arg(60)
    ->Arg(120)
    ->Unit(benchmark::kSecond)
    ->Iterations(1);

void BM_WindowFgo(benchmark::State& state) {
  const int minutes = static_cast<int>(state.range(0));
  const EstimationProblem& p = problemOfMinutes(minutes);
  FgoOptions opt;
  FgoReport rep;
  for (auto _ : state) {
    rep = FgoReport{};
    NavSolution sol = solveWindowFgo(p, opt, &rep);
    benchmark::DoNotOptimize(sol.states.data());
  }
  state.counters["data_min"] = minutes;
  state.counters["x_realtime"] = minutes * 60.0 / (rep.window_time_s + rep.output_time_s);
}
BENCHMARK(BM_WindowFgo)->Arg(15)->Arg(60)->Unit(benchmark::kSecond)->Iterations(1);

}  // namespace

BENCHMARK_MAIN();

// Forward EKF and EKF + RTS on 1 h of 200 Hz IMU with 1 Hz GNSS (target: < 3 s for both
// on the 2-core machine). Data: the truth-by-construction drive of the filter tests
// (tests/support/ekf_scenario.h) with tactical-grade errors, generated once in memory.
#include <benchmark/benchmark.h>

#include "ekf_scenario.h"
#include "graftnav/eval/outage_schedule.h"
#include "graftnav/filters/ekf.h"
#include "graftnav/filters/rts_smoother.h"

namespace {

using namespace graftnav;

const EstimationProblem& hourProblem() {
  static const EstimationProblem pr = [] {
    const test::Scenario sc = test::makeDrive(3600.0, 200.0);
    EstimationProblem p;
    p.imu_profile = test::tacticalProfile();
    test::InjectedErrors e;
    e.gyro_bias_rad_s = Eigen::Vector3d(0.4, -0.3, 0.5) * kDegToRad / 3600.0;
    e.accel_bias_m_s2 = Eigen::Vector3d(0.3, -0.4, 0.2) * 1e-3 * 9.80665;
    p.imu = test::corrupt(sc.ideal, e, p.imu_profile, 1);
    p.lever_arm_b_m = Eigen::Vector3d(0.5, 0.0, -1.2);
    p.gnss = test::makeGnss(sc.truth, p.lever_arm_b_m, 200, 0.02, 2);
    p.initial = sc.initial;
    OutageScheduleConfig oc;  // 60 s every 180 s after 300 s
    p.outages = buildOutageWindows(oc, sc.initial.t_s, sc.truth.back().t_s);
    return p;
  }();
  return pr;
}

void BM_EkfForwardOneHour200Hz(benchmark::State& state) {
  const EstimationProblem& pr = hourProblem();
  for (auto _ : state) {
    const NavSolution s = runEkf(pr, EkfOptions{});
    benchmark::DoNotOptimize(s.states.back().pos.lat_rad);
  }
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(pr.imu.size()));
}
BENCHMARK(BM_EkfForwardOneHour200Hz)->Unit(benchmark::kMillisecond)->Iterations(3);

void BM_EkfPlusRtsOneHour200Hz(benchmark::State& state) {
  const EstimationProblem& pr = hourProblem();
  RtsStats stats;
  for (auto _ : state) {
    const NavSolution s = runRts(pr, EkfOptions{}, nullptr, &stats);
    benchmark::DoNotOptimize(s.states.back().pos.lat_rad);
  }
  state.counters["smoother_records"] = static_cast<double>(stats.records);
  state.counters["smoother_MB"] = static_cast<double>(stats.record_bytes) / 1e6;
  state.SetItemsProcessed(state.iterations() * static_cast<int64_t>(pr.imu.size()));
}
BENCHMARK(BM_EkfPlusRtsOneHour200Hz)->Unit(benchmark::kMillisecond)->Iterations(3);

}  // namespace

BENCHMARK_MAIN();

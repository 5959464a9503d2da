// The error evaluation of a solution against its reference, 1 h of 200 Hz epochs both (720 000
// each, coinciding epochs as a simulated case's truth and solution have them): in memory
// (evaluateSolution, which keeps every epoch's error), streamed with one epoch set (as when the
// expected rates decide kAuto), and streamed with both sets (equal expected rates: the choice
// waits for the end).
#include <benchmark/benchmark.h>

#include <cmath>

#include "graftnav/eval/evaluation.h"
#include "graftnav/eval/streamed_evaluation.h"
#include "graftnav/nav/rotation.h"

namespace {

using namespace graftnav;

constexpr double kRateHz = 200.0;
constexpr int kEpochs = 3600 * 200;

NavState state(int k, double err) {
  NavState s;
  s.t_s = 456300.0 + k / kRateHz;
  const double u = k / kRateHz;
  s.pos = {0.53 + 1e-7 * u + err * 1e-9 * u, 2.0 + 2e-7 * u, 20.0 + 0.3 * std::sin(0.05 * u)};
  s.v_n = {10.0 * std::cos(0.02 * u), 5.0 * std::sin(0.02 * u), 0.1 * std::cos(0.3 * u)};
  s.q_nb = quatFromEuler({0.001 * std::sin(7.0 * u), 0.02 * std::cos(3.0 * u) + err * 1e-5,
                          wrapAngle(3.1 + 0.01 * u)});
  return s;
}

struct Data {
  NavSeries reference;
  NavSolution solution;
  std::vector<TimeWindow> outages;
  Data() {
    for (int k = 0; k <= kEpochs; ++k) reference.push_back(state(k, 0.0));
    solution.estimator = "bench";
    for (int k = 1; k <= kEpochs; ++k) {
      solution.states.push_back(state(k, 1.0));
      solution.sigma.push_back(PvaSigma::Constant(1.0));
    }
    for (double t = 300.0; t + 60.0 < 3600.0; t += 180.0)
      outages.push_back({456300.0 + t, 456300.0 + t + 60.0});
  }
};

const Data& data() {
  static const Data d;
  return d;
}

void BM_EvaluateInMemory(benchmark::State& st) {
  const Data& d = data();
  for (auto _ : st) benchmark::DoNotOptimize(evaluateSolution(d.solution, d.reference, d.outages));
  st.SetItemsProcessed(st.iterations() * kEpochs);
}

void streamed(benchmark::State& st, EvaluationEpochs epochs) {
  const Data& d = data();
  EvaluationOptions o;
  o.epochs = epochs;
  for (auto _ : st) {
    StreamedEvaluation se(seriesNavSource(d.reference), d.outages, o, "bench", {kRateHz, kRateHz});
    for (std::size_t i = 0; i < d.solution.states.size(); ++i)
      se.add(d.solution.states[i], &d.solution.sigma[i]);
    benchmark::DoNotOptimize(se.finish());
  }
  st.SetItemsProcessed(st.iterations() * kEpochs);
}

void BM_EvaluateStreamedOneSet(benchmark::State& st) { streamed(st, EvaluationEpochs::kSolution); }
void BM_EvaluateStreamedBothSets(benchmark::State& st) { streamed(st, EvaluationEpochs::kAuto); }

}  // namespace

BENCHMARK(BM_EvaluateInMemory)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_EvaluateStreamedOneSet)->Unit(benchmark::kMillisecond);
BENCHMARK(BM_EvaluateStreamedBothSets)->Unit(benchmark::kMillisecond);
BENCHMARK_MAIN();

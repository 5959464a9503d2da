// The streamed evaluation (a merge-join on time while the solution is written) against the
// in-memory one, number by number and byte by byte: reference gaps, a reference that ends before
// the solution or starts after it, outages at the edges, coinciding and offset time grids, with
// and without sigma, every choice of evaluation epochs.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include "graftnav/eval/errors_csv.h"
#include "graftnav/eval/evaluation.h"
#include "graftnav/eval/evaluation_files.h"
#include "graftnav/eval/streamed_evaluation.h"
#include "graftnav/io/nav_io.h"
#include "graftnav/nav/rotation.h"
#include "test_support.h"

namespace graftnav {
namespace {

namespace fs = std::filesystem;

std::string readFile(const std::string& path) {
  std::ifstream f(path, std::ios::binary);
  std::ostringstream ss;
  ss << f.rdbuf();
  return ss.str();
}

// A smooth drive with wobbling attitude sampled at the given times (week 2100).
NavState stateAt(double t, double wobble) {
  NavState s;
  s.t_s = t;
  s.gnss_week = 2100;
  const double u = t - 1000.0;
  s.pos = {0.53 + 1e-7 * u + 1e-9 * std::sin(0.1 * u), 2.0 + 2e-7 * u,
           20.0 + 0.3 * std::sin(0.05 * u)};
  s.v_n = {10.0 * std::cos(0.02 * u), 5.0 * std::sin(0.02 * u), 0.1 * std::cos(0.3 * u)};
  s.q_nb = quatFromEuler(
      {wobble * std::sin(7.0 * u), 0.02 * std::cos(3.0 * u), wrapAngle(3.1 + 0.01 * u)});
  return s;
}

NavSeries series(double t0, double t1, double rate_hz, double wobble,
                 const std::vector<TimeWindow>& gaps = {}) {
  NavSeries out;
  const auto n = static_cast<long>(std::llround((t1 - t0) * rate_hz));
  for (long i = 0; i <= n; ++i) {
    const double t = t0 + i / rate_hz;
    bool in_gap = false;
    for (const auto& g : gaps) in_gap = in_gap || g.contains(t);
    if (!in_gap) out.push_back(stateAt(t, wobble));
  }
  return out;
}

// A solution: the reference's trajectory plus growing errors, sigma optional.
NavSolution solution(double t0, double t1, double rate_hz, bool with_sigma,
                     const std::vector<TimeWindow>& gaps = {}) {
  NavSolution sol;
  sol.estimator = "test";
  std::mt19937 rng(7);
  std::normal_distribution<double> n01;
  for (NavState s : series(t0, t1, rate_hz, 0.002, gaps)) {
    const double u = s.t_s - t0;
    s.pos.lat_rad += 1e-8 * u + 1e-9 * n01(rng);
    s.pos.h_m += 0.01 * u;
    s.v_n += Eigen::Vector3d(0.01, -0.02, 0.005) * n01(rng);
    s.q_nb = (s.q_nb * quatFromEuler({1e-4 * n01(rng), 1e-4 * n01(rng), 1e-5 * u})).normalized();
    sol.states.push_back(s);
    if (with_sigma) sol.sigma.push_back(PvaSigma::Constant(0.5 + 0.01 * u));
  }
  return sol;
}

bool same(double a, double b) { return std::memcmp(&a, &b, sizeof a) == 0; }
bool same(const Eigen::Vector3d& a, const Eigen::Vector3d& b) {
  return same(a.x(), b.x()) && same(a.y(), b.y()) && same(a.z(), b.z());
}
void expectSame(const DriftStats& a, const DriftStats& b, const char* what) {
  EXPECT_TRUE(same(a.horizontal_m, b.horizontal_m))
      << what << " " << a.horizontal_m << " " << b.horizontal_m;
  EXPECT_TRUE(same(a.vertical_m, b.vertical_m)) << what;
  EXPECT_TRUE(same(a.roll_rad, b.roll_rad)) << what;
  EXPECT_TRUE(same(a.pitch_rad, b.pitch_rad)) << what;
  EXPECT_TRUE(same(a.heading_rad, b.heading_rad)) << what;
}

// Keeps the epochs a streamed evaluation hands its sink.
struct Collected {
  std::vector<std::vector<EpochError>> sets;
  std::vector<bool> committed;
  EpochSinkFactory factory() {
    return [this]() -> std::unique_ptr<EpochErrorSink> {
      struct Sink : EpochErrorSink {
        Collected* c;
        std::size_t i;
        void add(const EpochError& e) override { c->sets[i].push_back(e); }
        void commit() override { c->committed[i] = true; }
      };
      auto s = std::make_unique<Sink>();
      s->c = this;
      s->i = sets.size();
      sets.emplace_back();
      committed.push_back(false);
      return s;
    };
  }
  const std::vector<EpochError>& kept() const {
    for (std::size_t i = 0; i < sets.size(); ++i)
      if (committed[i]) return sets[i];
    throw std::logic_error("no sink committed");
  }
};

// Streamed == in-memory for every field and every epoch, bit for bit.
void expectStreamedEqualsInMemory(const NavSolution& sol, const NavSeries& ref,
                                  const std::vector<TimeWindow>& outages, EvaluationEpochs epochs,
                                  const ExpectedRates& expected = {}) {
  EvaluationOptions o;
  o.epochs = epochs;
  const Evaluation a = evaluateSolution(sol, ref, outages, o);
  Collected c;
  StreamedEvaluation se(seriesNavSource(ref), outages, o, sol.estimator, expected, c.factory());
  const bool has_sigma = sol.sigma.size() == sol.states.size();
  for (std::size_t i = 0; i < sol.states.size(); ++i)
    se.add(sol.states[i], has_sigma ? &sol.sigma[i] : nullptr);
  const Evaluation b = se.finish();
  se.commitEpochs();
  const std::vector<EpochError>& eb = c.kept();
  ASSERT_EQ(a.epochs.size(), eb.size());
  EXPECT_EQ(a.epoch_count, a.epochs.size());
  EXPECT_EQ(b.epoch_count, eb.size());
  EXPECT_TRUE(b.epochs.empty());
  for (std::size_t i = 0; i < eb.size(); ++i) {
    const EpochError &x = a.epochs[i], &y = eb[i];
    ASSERT_TRUE(same(x.t_s, y.t_s) && same(x.pos_ned_m, y.pos_ned_m) &&
                same(x.vel_ned_m_s, y.vel_ned_m_s) && same(x.euler_rad, y.euler_rad) &&
                same(x.att_n_rad, y.att_n_rad) && same(x.nees, y.nees) && x.outage == y.outage)
        << "epoch " << i << " at " << x.t_s;
  }
  expectSame(a.overall_rms, b.overall_rms, "overall");
  expectSame(a.outage_rms, b.outage_rms, "outage");
  expectSame(a.outage_max_rms, b.outage_max_rms, "outage_max");
  ASSERT_EQ(a.outages.size(), b.outages.size());
  for (std::size_t k = 0; k < a.outages.size(); ++k) {
    EXPECT_EQ(a.outages[k].epochs, b.outages[k].epochs);
    EXPECT_TRUE(same(a.outages[k].window.start_s, b.outages[k].window.start_s));
    expectSame(a.outages[k].max, b.outages[k].max, "per-outage max");
  }
  EXPECT_EQ(a.outage_epochs, b.outage_epochs);
  EXPECT_EQ(a.nees_samples, b.nees_samples);
  EXPECT_TRUE(same(a.nees_mean, b.nees_mean));
  EXPECT_TRUE(same(a.nees_band_low, b.nees_band_low));
  EXPECT_TRUE(same(a.nees_band_high, b.nees_band_high));
}

constexpr EvaluationEpochs kAll[] = {EvaluationEpochs::kAuto, EvaluationEpochs::kSolution,
                                     EvaluationEpochs::kReference};

TEST(StreamedEvaluation, EqualsInMemoryOnCoincidingGrids) {
  // 200 Hz both, the same epochs: the kAuto choice turns on rounding; u = 0 and u = 1 brackets.
  const NavSeries ref = series(1000.0, 1060.0, 200.0, 0.001);
  const std::vector<TimeWindow> outages{{1010.0, 1020.0}, {1040.0, 1045.5}};
  for (bool sigma : {true, false})
    for (EvaluationEpochs e : kAll)
      expectStreamedEqualsInMemory(solution(1000.005, 1060.0, 200.0, sigma), ref, outages, e);
}

TEST(StreamedEvaluation, EqualsInMemoryOnOffsetGridsAndSparseReference) {
  const std::vector<TimeWindow> outages{{1005.0, 1015.0}, {1030.0, 1031.0}};
  // A 10 Hz truth against a 50 Hz solution offset by 3 ms, and the other way round.
  for (EvaluationEpochs e : kAll) {
    expectStreamedEqualsInMemory(solution(1000.003, 1040.0, 50.0, true),
                                 series(1000.0, 1040.0, 10.0, 0.001), outages, e);
    expectStreamedEqualsInMemory(solution(1000.003, 1040.0, 10.0, true),
                                 series(1000.0, 1040.0, 50.0, 0.001), outages, e);
  }
}

TEST(StreamedEvaluation, EqualsInMemoryWithReferenceGaps) {
  // Gaps of 0.5 s and of 3 s (600 epochs: the interpolator's far-ahead binary search) in a
  // 200 Hz reference, and a 2 s gap in the solution.
  const NavSeries ref = series(1000.0, 1030.0, 200.0, 0.001, {{1004.0, 1004.5}, {1010.0, 1013.0}});
  const std::vector<TimeWindow> outages{{1003.0, 1012.0}, {1020.0, 1025.0}};
  for (EvaluationEpochs e : kAll) {
    expectStreamedEqualsInMemory(solution(1000.0, 1030.0, 200.0, true), ref, outages, e);
    expectStreamedEqualsInMemory(solution(1000.0, 1030.0, 100.0, true, {{1021.0, 1023.0}}), ref,
                                 outages, e);
  }
}

TEST(StreamedEvaluation, EqualsInMemoryAcrossAJumpOntoACoincidingEpoch) {
  // After a solution gap of more than 64 reference epochs the in-memory interpolator searches
  // (bracket [t, next], u = 0) where a step-by-step walk would bracket [previous, t] with u = 1;
  // with values whose difference is not exact (a + (b - a) != b) the two differ in the last
  // bit. The streamed join must take the same bracket.
  NavSeries ref = series(1000.0, 1010.0, 100.0, 0.001);
  std::mt19937 rng(3);
  std::uniform_real_distribution<double> mag(-9.0, 3.0);
  for (NavState& s : ref) s.v_n = Eigen::Vector3d::Constant(std::pow(10.0, mag(rng)) * 1.2345);
  NavSolution sol = solution(1000.0, 1010.0, 100.0, true, {{1002.0, 1004.0}});
  for (EvaluationEpochs e : kAll) expectStreamedEqualsInMemory(sol, ref, {{1003.0, 1006.0}}, e);
}

TEST(StreamedEvaluation, EqualsInMemoryWhenTheReferenceEndsFirstOrStartsLate) {
  const std::vector<TimeWindow> outages{{1002.0, 1008.0}, {1015.0, 1019.0}};
  for (EvaluationEpochs e : kAll) {
    // The reference ends 10 s before the solution (the last outage is past it).
    expectStreamedEqualsInMemory(solution(1000.0, 1030.0, 100.0, true),
                                 series(1000.0, 1020.0, 100.0, 0.001), outages, e);
    // It starts 5 s after the solution and ends before it.
    expectStreamedEqualsInMemory(solution(1000.0, 1030.0, 100.0, false),
                                 series(1005.0, 1016.0, 20.0, 0.001), outages, e);
    // A one-epoch reference inside the solution.
    expectStreamedEqualsInMemory(solution(1000.0, 1030.0, 100.0, true),
                                 series(1012.0, 1012.0, 1.0, 0.001), outages, e);
  }
}

TEST(StreamedEvaluation, EqualsInMemoryWithOutagesAtTheEdges) {
  // An outage that starts before both series, one that runs past their end, one wholly outside,
  // given out of order.
  const std::vector<TimeWindow> outages{
      {1025.0, 1040.0}, {990.0, 1003.0}, {1050.0, 1060.0}, {1010.0, 1010.0}};
  const NavSeries ref = series(1000.0, 1030.0, 100.0, 0.001);
  for (EvaluationEpochs e : kAll) {
    expectStreamedEqualsInMemory(solution(1000.0, 1030.0, 100.0, true), ref, outages, e);
    expectStreamedEqualsInMemory(solution(1001.0, 1029.0, 200.0, true), ref, outages, e);
  }
}

TEST(StreamedEvaluation, ExpectedRatesEvaluateOneSetWithTheSameNumbers) {
  const std::vector<TimeWindow> outages{{1005.0, 1015.0}};
  const NavSolution sol = solution(1000.0, 1030.0, 100.0, true);
  const NavSeries ref = series(1000.0, 1030.0, 10.0, 0.001);
  expectStreamedEqualsInMemory(sol, ref, outages, EvaluationEpochs::kAuto, {100.0, 10.0});
  StreamedEvaluation one(seriesNavSource(ref), outages, {}, "x", {100.0, 10.0});
  EXPECT_EQ(one.epochSets(), 1);
  StreamedEvaluation two(seriesNavSource(ref), outages, {}, "x", {100.0, 90.0});
  EXPECT_EQ(two.epochSets(), 2);
  // Expected rates that the series contradict are a programming error, named.
  StreamedEvaluation wrong(seriesNavSource(ref), outages, {}, "x", {10.0, 100.0});
  for (std::size_t i = 0; i < sol.states.size(); ++i) wrong.add(sol.states[i], &sol.sigma[i]);
  EXPECT_THROW(wrong.finish(), std::logic_error);
}

TEST(StreamedEvaluation, ThrowsAsInMemoryWhenNothingOverlaps) {
  const NavSeries ref = series(1000.0, 1010.0, 10.0, 0.001);
  const NavSolution late = solution(1020.0, 1030.0, 10.0, true);
  auto message = [](const std::function<void()>& f) {
    try {
      f();
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string("no exception");
  };
  const std::string a = message([&] { evaluateSolution(late, ref, {}); });
  const std::string b =
      message([&] { evaluateSolutionStreamed(late, [&] { return seriesNavSource(ref); }, {}); });
  EXPECT_EQ(a, b);
  EXPECT_NE(a.find("do not overlap"), std::string::npos);
  // A solution epoch before the previous one cannot be joined.
  StreamedEvaluation se(seriesNavSource(ref), {}, {}, "x");
  se.add(ref[5], nullptr);
  EXPECT_THROW(se.add(ref[2], nullptr), std::invalid_argument);
  // Sigma at some epochs only.
  const PvaSigma one = PvaSigma::Ones();
  StreamedEvaluation mixed(seriesNavSource(ref), {}, {}, "x");
  mixed.add(ref[1], &one);
  EXPECT_THROW(mixed.add(ref[2], nullptr), std::invalid_argument);
}

TEST(StreamedEvaluation, ErrorsCsvIsByteIdenticalToTheInMemoryFile) {
  const std::string dir = test::makeTempDir("streamed_eval");
  const NavSeries ref = series(1000.0, 1030.0, 200.0, 0.001, {{1010.0, 1011.0}});
  const NavSolution sol = solution(1000.005, 1030.0, 200.0, true);
  const std::vector<TimeWindow> outages{{1005.0, 1015.0}};
  for (double interval : {0.0, 0.1, 1.0}) {
    const Evaluation a = evaluateSolution(sol, ref, outages);
    writeErrorsCsv(dir + "/a.csv", a, interval);
    const Evaluation b = evaluateSolutionStreamed(
        sol, [&] { return seriesNavSource(ref); }, outages, {},
        [&]() { return std::make_unique<ErrorsCsvWriter>(dir + "/b.csv", interval); });
    EXPECT_EQ(readFile(dir + "/a.csv"), readFile(dir + "/b.csv")) << interval;
    EXPECT_EQ(a.epoch_count, b.epoch_count);
  }
  // Only the kept set's file is written; the other leaves no temporary file behind.
  int files = 0;
  for (const auto& f : fs::directory_iterator(dir)) files += f.is_regular_file();
  EXPECT_EQ(files, 2);
}

TEST(StreamedEvaluation, ReadsTheReferenceFileAsReadNavDoes) {
  const std::string dir = test::makeTempDir("streamed_eval_nav");
  const std::string path = dir + "/truth.nav";
  writeNav(path, series(1000.0, 1020.0, 50.0, 0.001));
  const NavSeries whole = readNav(path);
  NavStreamReader reader(path);
  std::size_t i = 0;
  for (NavState s; reader.next(&s); ++i) {
    ASSERT_LT(i, whole.size());
    ASSERT_TRUE(same(s.t_s, whole[i].t_s) && same(s.pos.lat_rad, whole[i].pos.lat_rad) &&
                same(s.v_n, whole[i].v_n) && s.q_nb.coeffs() == whole[i].q_nb.coeffs());
  }
  EXPECT_EQ(i, whole.size());
  EXPECT_EQ(reader.report().records_kept, static_cast<int>(whole.size()));
  const NavSolution sol = solution(1000.0, 1020.0, 200.0, true);
  const std::vector<TimeWindow> outages{{1005.0, 1012.0}};
  const Evaluation a = evaluateSolution(sol, whole, outages);
  const Evaluation b = evaluateSolutionStreamed(sol, navFileSource(path), outages);
  expectSame(a.outage_rms, b.outage_rms, "from the file");
  EXPECT_TRUE(same(a.nees_mean, b.nees_mean));
}

// Memory: the join holds a window of a few epochs of each series, with or without solution
// sigmas, under kAuto's two epoch sets, and also once the reference has ended before the solution.
TEST(StreamedEvaluation, HoldsAWindowNotTheSeries) {
  for (const bool sigma : {true, false}) {
    for (const double ref_end : {1300.0, 1100.0}) {
      const NavSeries ref = series(1000.0, ref_end, 200.0, 0.0);
      const NavSolution sol = solution(1000.0, 1300.0, 200.0, sigma);
      StreamedEvaluation se(seriesNavSource(ref), {{1050.0, 1110.0}}, EvaluationOptions{},
                            sol.estimator);
      ASSERT_EQ(se.epochSets(), 2);
      std::size_t held = 0;
      for (std::size_t i = 0; i < sol.states.size(); ++i) {
        se.add(sol.states[i], sigma ? &sol.sigma[i] : nullptr);
        held = std::max(held, se.heldEpochs());
      }
      EXPECT_LT(held, 200u) << "sigma " << sigma << ", reference to " << ref_end << " s, "
                            << sol.states.size() << " solution epochs";
      EXPECT_GT(se.finish().epoch_count, 0u);
    }
  }
}

}  // namespace
}  // namespace graftnav

// The evaluate pipeline as streams against the in-memory evaluation for one seed, number by
// number: the reference IMU and REAL read back from spools in odd-sized blocks, each realization
// grafted block by block (a lab record shorter than the field test, so every realization grafts
// its own surrogate, read back from a spool in windows against the held one, with turn-on biases,
// wander and SG#2's dynamic errors), SOL_REF read from a
// spool as each solution's epochs come, against each realization's series grafted whole,
// navigated whole and evaluated by evaluateSolution. SOL_REF has a gap and ends before the
// solution; an outage sits at each edge of the data.
#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "graftnav/eval/evaluation.h"
#include "graftnav/io/imu_recording.h"
#include "graftnav/io/nav_spool.h"
#include "graftnav/sg/evaluate_pipeline.h"

namespace graftnav {
namespace {

constexpr double kT0 = 1000.0, kDt = 0.1, kSpan = 600.0;
constexpr int kEvery = 4;  // the stand-in estimator writes every 4th sample (2.5 Hz)

ImuSeries noiseSeries(int n, double sd, unsigned seed, double t0) {
  std::mt19937_64 rng(seed);
  std::normal_distribution<double> g(0.0, sd);
  ImuSeries s;
  for (int k = 1; k <= n; ++k) {
    ImuSample x;
    x.dt_s = kDt;
    x.t_s = t0 + k * kDt;
    x.dtheta_rad = Eigen::Vector3d(g(rng), g(rng), g(rng)) * kDt;
    x.dvel_m_s = Eigen::Vector3d(g(rng), g(rng), g(rng)) * kDt;
    s.push_back(x);
  }
  return s;
}

// A field IMU that turns and accelerates (SG#2's dynamic errors depend on the rates).
ImuSeries referenceImu() {
  ImuSeries s = noiseSeries(static_cast<int>(kSpan / kDt), 1e-4, 3, kT0);
  for (ImuSample& x : s) {
    x.dtheta_rad.z() += 0.2 * std::sin(0.05 * x.t_s) * kDt;
    x.dvel_m_s.x() += 1.5 * std::cos(0.03 * x.t_s) * kDt;
    x.dvel_m_s.z() -= 9.8 * kDt;
  }
  return s;
}

// 250 s of lab record for a 600 s field test: each realization grafts a surrogate (5000 samples,
// more than one window of a spooled one).
GraftPlan plan() {
  GraftPlan p{BasicErrorSignal(noiseSeries(2500, 1e-3, 11, 0.0)), SensorDynamicFit{},
              SensorDynamicFit{}};
  p.gyro_fit.poly[2] = {0.0, 1.002, 0.05};
  p.gyro_fit.M(0, 2) = 1e-3;
  p.accel_fit.poly[0] = {0.0, 0.999, 1e-3};
  p.accel_fit.static_point = {0.0, 0.0, -9.8};
  return p;
}

// SOL_REF at 1 Hz with a 20-s gap outside the outages, ending 10 s before the solution.
NavSeries solRef() {
  NavSeries r;
  for (int k = 0; k <= static_cast<int>(kSpan) - 10; ++k) {
    if (k > 250 && k < 270) continue;
    NavState s;
    s.t_s = kT0 + k;
    s.pos.lat_rad = 0.5 + 1e-7 * std::sin(0.01 * k);
    s.pos.lon_rad = 2.0;
    s.v_n = {0.1 * k, 0.0, 0.0};
    s.q_nb = Eigen::Quaterniond(Eigen::AngleAxisd(0.001 * k, Eigen::Vector3d::UnitZ()));
    r.push_back(s);
  }
  return r;
}

// The stand-in estimator: its position and heading drift with the running sums of the samples,
// so every sample of every realization reaches the errors; a sigma at every epoch (NEES).
class FakeEstimator {
 public:
  template <typename Emit>
  void add(const ImuSeries& block, const Emit& emit) {
    for (const ImuSample& s : block) {
      gyro_ += s.dtheta_rad.sum();
      accel_ += s.dvel_m_s.x() + s.dvel_m_s.y();
      if (++count_ % kEvery != 0) continue;
      NavState x;
      x.t_s = s.t_s;
      x.pos.lat_rad = 0.5 + accel_ * 1e-8;
      x.pos.lon_rad = 2.0 + gyro_ * 1e-7;
      x.pos.h_m = 10.0 * gyro_;
      x.v_n = {accel_, gyro_, 0.0};
      x.q_nb = Eigen::Quaterniond(Eigen::AngleAxisd(gyro_, Eigen::Vector3d::UnitZ()));
      const PvaSigma sigma = PvaSigma::Constant(0.5 + 1e-3 * static_cast<double>(count_ % 7));
      emit(x, sigma);
    }
  }

 private:
  double gyro_ = 0.0, accel_ = 0.0;
  long count_ = 0;
};

NavSolution navigateHeld(const ImuSeries& imu) {
  NavSolution sol;
  FakeEstimator f;
  f.add(imu, [&sol](const NavState& x, const PvaSigma& s) {
    sol.states.push_back(x);
    sol.sigma.push_back(s);
  });
  return sol;
}

// REAL: the reference IMU with a bias of its own.
ImuSeries realImu() {
  ImuSeries s = referenceImu();
  for (ImuSample& x : s) x.dtheta_rad.x() += 2e-5 * kDt;
  return s;
}

SgEvaluationInputs inputs() {
  SgEvaluationInputs in;
  in.case_name = "/cases/streamed";
  in.tested_profile.gyro_bias_instability_rad_s = 2e-5;
  in.tested_profile.accel_bias_instability_m_s2 = 3e-3;
  in.tested_profile.gyro_bias_repeatability_rad_s = 1e-4;
  in.tested_profile.accel_bias_repeatability_m_s2 = 1e-2;
  in.tested_profile.arw_rad_sqrt_s = 1e-4;
  in.tested_profile.vrw_m_s_sqrt_s = 1e-3;
  in.has_real = true;
  in.real_imu_file = "tested_imu.txt";
  // Outages from 0.5 s after the first sample and up to the last one.
  in.outages.explicit_windows = {
      {kT0 + 0.5, kT0 + 40.0}, {kT0 + 150.0, kT0 + 200.0}, {kT0 + 560.0, kT0 + kSpan}};
  return in;
}

ImuPassFn blocksOf(const ImuSeries& series, std::size_t n) {
  return [series, n](const ImuBlockFn& block) {
    for (std::size_t i = 0; i < series.size(); i += n)
      block(
          ImuSeries(series.begin() + static_cast<std::ptrdiff_t>(i),
                    series.begin() + static_cast<std::ptrdiff_t>(std::min(i + n, series.size()))));
  };
}

// Collects the representative epochs a streamed run hands out, per label.
class EpochCollector final : public EpochErrorSink {
 public:
  EpochCollector(std::map<std::string, std::vector<EpochError>>* out, std::string label)
      : out_(out), label_(std::move(label)) {}
  void add(const EpochError& e) override { epochs_.push_back(e); }
  void commit() override { (*out_)[label_] = epochs_; }

 private:
  std::map<std::string, std::vector<EpochError>>* out_;
  std::string label_;
  std::vector<EpochError> epochs_;
};

void expectSameStats(const DriftStats& a, const DriftStats& b, const std::string& what) {
  for (int i = 0; i < 5; ++i) EXPECT_EQ(asArray(a)[i], asArray(b)[i]) << what << " statistic " << i;
}

void expectSameEpochs(const std::vector<EpochError>& a, const std::vector<EpochError>& b,
                      const std::string& what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  for (std::size_t k = 0; k < a.size(); ++k) {
    ASSERT_EQ(a[k].t_s, b[k].t_s) << what << " epoch " << k;
    ASSERT_EQ(a[k].pos_ned_m, b[k].pos_ned_m) << what << " epoch " << k;
    ASSERT_EQ(a[k].vel_ned_m_s, b[k].vel_ned_m_s) << what << " epoch " << k;
    ASSERT_EQ(a[k].att_n_rad, b[k].att_n_rad) << what << " epoch " << k;
    ASSERT_EQ(a[k].nees, b[k].nees) << what << " epoch " << k;
    ASSERT_EQ(a[k].outage, b[k].outage) << what << " epoch " << k;
  }
}

void expectSameEvaluation(const Evaluation& a, const Evaluation& b, const std::string& what) {
  EXPECT_EQ(a.epoch_count, b.epoch_count) << what;
  expectSameStats(a.overall_rms, b.overall_rms, what + " overall");
  expectSameStats(a.outage_rms, b.outage_rms, what + " outage");
  expectSameStats(a.outage_max_rms, b.outage_max_rms, what + " outage max");
  EXPECT_EQ(a.outage_epochs, b.outage_epochs) << what;
  EXPECT_EQ(a.nees_mean, b.nees_mean) << what;
  EXPECT_EQ(a.nees_samples, b.nees_samples) << what;
  ASSERT_EQ(a.outages.size(), b.outages.size()) << what;
  for (std::size_t i = 0; i < a.outages.size(); ++i) {
    EXPECT_EQ(a.outages[i].epochs, b.outages[i].epochs) << what << " outage " << i;
    expectSameStats(a.outages[i].max, b.outages[i].max, what + " outage max " + std::to_string(i));
  }
}

TEST(StreamedEvaluate, EveryNumberEqualsTheInMemoryEvaluationForASeed) {
  SgEvaluationOptions o;
  o.realizations = 4;
  o.seed = 7;
  o.jobs = 2;
  const ImuSeries ref_imu = referenceImu(), real_imu = realImu();
  const NavSeries sol_ref = solRef();

  SgEvaluationInputs in = inputs();
  in.reference_recording = spooledRecording(blocksOf(ref_imu, 37), 53);
  in.real_recording = spooledRecording(blocksOf(real_imu, 41), 29);
  const SgEvaluationPipeline streamed(o, plan(), in);
  std::unique_ptr<NavSource> ref_source = seriesNavSource(sol_ref);
  const NavSpool spool = spoolNav(*ref_source);
  SolutionReference reference;
  reference.open = spool.opener();
  reference.rate_hz = spool.rateHz();
  reference.description = "spooled truth";
  const SgStreamNavigator navigate = [](const SgImu& imu, const OutageScheduleConfig& schedule,
                                        const SgStartFn& start) {
    SgNavigation nav;
    nav.outages = buildOutageWindows(schedule, imu.imu.beginTime_s(), imu.imu.last.t_s);
    const SgEpochFn epochs = start(nav.outages, 0.0);
    FakeEstimator f;
    imu.imu.pass([&](const ImuSeries& block) {
      f.add(block, [&epochs](const NavState& x, const PvaSigma& s) { epochs(x, &s); });
    });
    return nav;
  };
  std::map<std::string, std::vector<EpochError>> csv_epochs;
  SgRunHooks hooks;
  hooks.epoch_sink = [&csv_epochs](const std::string& label) {
    return std::make_unique<EpochCollector>(&csv_epochs, label);
  };
  const SgEvaluationReport s = streamed.run(reference, navigate, "fake", hooks);

  // In memory: each realization's surrogate held, the realization grafted whole, navigated
  // whole, evaluated by evaluateSolution.
  SgEvaluationInputs held_in = inputs();
  held_in.reference_imu = ref_imu;
  SgEvaluationOptions held_o = o;
  held_o.spool_surrogates = false;
  const SgEvaluationPipeline held(held_o, plan(), held_in);
  const std::vector<TimeWindow> outages =
      buildOutageWindows(inputs().outages, ref_imu.front().t_s - kDt, ref_imu.back().t_s);
  auto evaluate = [&](const ImuSeries& imu) {
    return evaluateSolution(navigateHeld(imu), sol_ref, outages, o.evaluation);
  };
  ASSERT_EQ(s.solutions.size(), 3u);
  for (std::size_t g = 0; g < 2; ++g) {
    const SgSolutionErrors& e = s.solutions[g];
    const SgStrategy strategy = g == 0 ? SgStrategy::kBasic : SgStrategy::kFull;
    ASSERT_EQ(e.draws.size(), 4u);
    for (int k = 0; k < 4; ++k) {
      const ImuSeries grafted = held.graft(strategy, k);
      ASSERT_EQ(grafted.size(), ref_imu.size());
      const Evaluation m = evaluate(grafted);
      expectSameStats(e.draws[k], m.outage_rms, e.label + " draw " + std::to_string(k));
      if (k == 0) {
        expectSameEvaluation(e.evaluation, m, e.label);
        expectSameEpochs(csv_epochs[e.label], m.epochs, e.label);
      }
    }
    EXPECT_NE(e.draws[0].horizontal_m, e.draws[1].horizontal_m);
  }
  const Evaluation real = evaluate(real_imu);
  expectSameEvaluation(s.find("REAL")->evaluation, real, "REAL");
  expectSameStats(s.find("REAL")->err_rms, real.outage_rms, "REAL");
  expectSameEpochs(csv_epochs["REAL"], real.epochs, "REAL");
  EXPECT_NE(s.find("SG1")->err_rms.horizontal_m, s.find("SG2")->err_rms.horizontal_m);
  EXPECT_EQ(s.reference, "spooled truth");
}

// A realization grafted block by block from a spool equals the one grafted whole, sample by
// sample, whatever the block size.
TEST(StreamedEvaluate, AGraftedRecordingEqualsTheSeriesGraftedWhole) {
  SgEvaluationOptions o;
  o.realizations = 3;
  SgEvaluationInputs held_in = inputs();
  held_in.reference_imu = referenceImu();
  SgEvaluationOptions held_o = o;
  held_o.spool_surrogates = false;
  const SgEvaluationPipeline held(held_o, plan(), held_in);
  for (std::size_t block : {1u, 7u, 4096u}) {
    SgEvaluationInputs in = inputs();
    in.reference_recording = spooledRecording(blocksOf(referenceImu(), 13), block);
    const SgEvaluationPipeline streamed(o, plan(), in);
    for (SgStrategy g : {SgStrategy::kBasic, SgStrategy::kFull}) {
      const ImuSeries whole = held.graft(g, 2);
      const ImuRecording r = streamed.graftedRecording(g, 2);
      const ImuSeries blocks = collectRecording(r);
      ASSERT_EQ(blocks.size(), whole.size());
      EXPECT_EQ(r.first.dtheta_rad, whole.front().dtheta_rad);
      EXPECT_EQ(r.last.dvel_m_s, whole.back().dvel_m_s);
      for (std::size_t k = 0; k < whole.size(); ++k) {
        ASSERT_EQ(blocks[k].t_s, whole[k].t_s) << k;
        ASSERT_EQ(blocks[k].dtheta_rad, whole[k].dtheta_rad) << k;
        ASSERT_EQ(blocks[k].dvel_m_s, whole[k].dvel_m_s) << k;
      }
    }
  }
}

}  // namespace
}  // namespace graftnav

// compare on the bundled sample with toy estimators: the streamed runs (solutions spooled, pairs
// joined from the spools) give the numbers of the in-memory runs, and the cross-check takes the
// filter-smoother form exactly for the pair the registry says is a filter and its smoother.
#include <gtest/gtest.h>

#include <cmath>
#include <memory>
#include <vector>

#include "graftnav/navigate/compare_run.h"
#include "test_support.h"
#include "toy_estimators.h"

namespace graftnav {
namespace {

EstimatorRegistry compareRegistry(bool streamed) {
  EstimatorRegistry r;
  r.add(test::toyEntry("filter", 1.6e-10, 0.5, streamed));
  EstimatorEntry smoother = test::toyEntry("smoother", 0.9e-10, 0.3, streamed);
  smoother.smooths = "filter";
  r.add(smoother);
  r.add(test::toyEntry("other", 1.2e-10, 0.4, streamed));
  return r;
}

CompareReport compareSample(bool streamed, const std::vector<std::string>& names) {
  CompareRequest q;
  q.case_dir = test::sourceDir() + "/data/sample_tactical";
  q.imu = "tested";
  q.estimators = names;
  q.outage.start_s = 100.0;
  q.outage.period_s = 120.0;
  q.outage.length_s = 30.0;
  const EstimatorRegistry r = compareRegistry(streamed);
  const CompareInputs in = loadCompareInputs(q, r, RunMessages{});
  EXPECT_EQ(in.stream, streamed);
  EXPECT_EQ(in.p.imu.empty(), streamed);
  return runCompare(q, in, r);
}

TEST(CompareRun, StreamedRunsGiveTheInMemoryNumbers) {
  const std::vector<std::string> names{"filter", "smoother", "other"};
  const CompareReport s = compareSample(true, names), m = compareSample(false, names);
  ASSERT_EQ(s.rows.size(), 3u);
  ASSERT_EQ(s.pairs.size(), 3u);
  for (std::size_t k = 0; k < 3; ++k) {
    EXPECT_EQ(s.rows[k].eval.outage_rms.horizontal_m, m.rows[k].eval.outage_rms.horizontal_m);
    EXPECT_EQ(s.rows[k].eval.overall_rms.heading_rad, m.rows[k].eval.overall_rms.heading_rad);
    EXPECT_EQ(s.rows[k].series.size(), m.rows[k].series.size());
    EXPECT_GT(s.rows[k].eval.outage_rms.horizontal_m, 0.1);
    EXPECT_EQ(s.pairs[k].rms.horizontal_m, m.pairs[k].rms.horizontal_m);
    EXPECT_EQ(s.pairs[k].cross.horizontal.rms_normalized,
              m.pairs[k].cross.horizontal.rms_normalized);
    EXPECT_GT(s.pairs[k].cross.horizontal.epochs, 1000);
  }
  EXPECT_EQ(s.rows[0].series.size(), 870u);  // 1 Hz over the 870-s sample
}

TEST(CompareRun, FilterSmootherFormForTheRegistrysPairOnly) {
  const CompareReport r = compareSample(true, {"smoother", "filter", "other"});
  ASSERT_EQ(r.pairs.size(), 3u);
  EXPECT_EQ(r.pairs[0].a, "smoother");
  EXPECT_EQ(r.pairs[0].cross.form, DifferenceCovariance::kFilterSmoother);
  EXPECT_EQ(r.pairs[1].cross.form, DifferenceCovariance::kIndependent);  // smoother - other
  EXPECT_EQ(r.pairs[2].cross.form, DifferenceCovariance::kIndependent);  // filter - other
  // var(d) = P_filter - P_smoother = 0.5^2 - 0.3^2 per axis: horizontal sigma sqrt(2 * 0.16).
  EXPECT_NEAR(r.pairs[0].cross.horizontal.rms_sigma, std::sqrt(2 * 0.16), 1e-12);
}

TEST(CompareRun, UnknownNamesAndMissingFilesStopBeforeAnyRun) {
  CompareRequest q;
  q.case_dir = test::sourceDir() + "/data/sample_tactical";
  q.imu = "tested";
  q.estimators = {"filter", "ukf"};
  EXPECT_THROW(loadCompareInputs(q, compareRegistry(true), RunMessages{}), std::runtime_error);
  q.estimators = {"filter-noearth"};
  EXPECT_THROW(loadCompareInputs(q, compareRegistry(true), RunMessages{}), std::runtime_error);
}

// "<name>-noearth" exists exactly for an entry whose Earth rotation is optional, and runs that
// estimator with fgo.earth_rotation off.
TEST(CompareRun, NoEarthVariantOnlyForEstimatorsWhoseEarthRotationIsOptional) {
  auto seen = std::make_shared<std::vector<bool>>();  // fgo.earth_rotation of each run
  EstimatorEntry graph = test::toyEntry("graph", 1.2e-10, 0.4, true);
  const StreamingEstimatorFn stream = graph.stream;
  graph.stream = [stream, seen](const EstimationProblem& p, const ImuPassFn& imu,
                                const EstimatorOptions& o, SolutionSink& sink) {
    seen->push_back(o.fgo.earth_rotation);
    return stream(p, imu, o, sink);
  };
  graph.earth_rotation_optional = true;
  EstimatorRegistry r;
  r.add(test::toyEntry("filter", 1.6e-10, 0.5, true));
  r.add(graph);
  EXPECT_EQ(compareEstimatorNamesText(r), "filter, graph, graph-noearth");

  CompareRequest q;
  q.case_dir = test::sourceDir() + "/data/sample_tactical";
  q.imu = "tested";
  q.estimators = {"graph", "graph-noearth"};
  const CompareInputs in = loadCompareInputs(q, r, RunMessages{});
  const CompareReport report = runCompare(q, in, r);
  ASSERT_EQ(report.rows.size(), 2u);
  EXPECT_EQ(report.rows[1].name, "graph-noearth");
  EXPECT_EQ(*seen, (std::vector<bool>{true, false}));

  q.estimators = {"filter-noearth"};
  try {
    loadCompareInputs(q, r, RunMessages{});
    ADD_FAILURE() << "filter-noearth was accepted";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("'filter-noearth' (known: filter, graph, graph-noearth)"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace graftnav

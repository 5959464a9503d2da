// The registry by itself: names in the order added, one entry per name, errors that list the
// known names, and the streamed form only where an estimator has one.
#include <gmock/gmock.h>
#include <gtest/gtest.h>

#include "graftnav/estimation/estimator_registry.h"

namespace graftnav {
namespace {

using ::testing::HasSubstr;

// An estimator that returns the problem's initial state once, tagged with its name.
EstimatorEntry fake(const std::string& name, bool streamed) {
  EstimatorEntry e;
  e.name = name;
  e.description = "fake " + name;
  e.run = [name](const EstimationProblem& p, const EstimatorOptions& o, const ProgressFn& f) {
    if (f) f(1.0);
    NavSolution s;
    s.estimator = name;
    s.states = {p.initial};
    s.gnss_used = o.ekf.max_consecutive_rejections;  // shows which options arrived
    return s;
  };
  if (streamed)
    e.stream = [name](const EstimationProblem& p, const ImuPassFn& imu, const EstimatorOptions&,
                      SolutionSink& sink) {
      std::size_t samples = 0;
      imu([&](const ImuSeries& block) { samples += block.size(); });
      sink.add(p.initial, nullptr, ImuErrorEstimate{});
      NavSolution s;
      s.estimator = name;
      s.gnss_used = static_cast<int>(samples);
      return s;
    };
  return e;
}

TEST(EstimatorRegistry, RunsByNameWithTheGivenOptions) {
  EstimatorRegistry r;
  r.add(fake("a", false));
  r.add(fake("b", true));
  EXPECT_EQ(r.names(), (std::vector<std::string>{"a", "b"}));
  EXPECT_EQ(r.namesText(), "a, b");
  EXPECT_TRUE(r.contains("b"));
  EXPECT_FALSE(r.contains("c"));
  EstimatorOptions o;
  o.ekf.max_consecutive_rejections = 7;
  double progress = 0.0;
  const NavSolution s = r.run("a", EstimationProblem{}, o, [&](double f) { progress = f; });
  EXPECT_EQ(s.estimator, "a");
  EXPECT_EQ(s.gnss_used, 7);
  EXPECT_EQ(progress, 1.0);
}

TEST(EstimatorRegistry, StreamedFormOnlyWhereGiven) {
  EstimatorRegistry r;
  r.add(fake("a", false));
  r.add(fake("b", true));
  EXPECT_FALSE(r.canStream("a"));
  EXPECT_TRUE(r.canStream("b"));
  NavSolution kept;
  NavSolutionSink sink(&kept);
  const ImuPassFn three = [](const ImuBlockFn& block) { block(ImuSeries(3)); };
  const NavSolution s = r.runStreaming("b", EstimationProblem{}, three, EstimatorOptions{}, sink);
  EXPECT_EQ(s.gnss_used, 3);
  EXPECT_EQ(kept.states.size(), 1u);
  EXPECT_THROW(r.runStreaming("a", EstimationProblem{}, three, EstimatorOptions{}, sink),
               std::invalid_argument);
}

TEST(EstimatorRegistry, UnknownDuplicateAndEmptyNamesAreErrors) {
  EstimatorRegistry r;
  r.add(fake("ekf", false));
  r.add(fake("rts", false));
  try {
    r.find("ukf");
    FAIL() << "no throw";
  } catch (const std::invalid_argument& e) {
    EXPECT_THAT(e.what(), HasSubstr("unknown estimator 'ukf' (known: ekf, rts)"));
  }
  EXPECT_THROW(r.canStream("ukf"), std::invalid_argument);
  EXPECT_THROW(r.add(fake("ekf", true)), std::invalid_argument);
  EXPECT_THROW(r.add(fake("", false)), std::invalid_argument);
  EstimatorEntry no_run = fake("x", false);
  no_run.run = {};
  EXPECT_THROW(r.add(no_run), std::invalid_argument);
}

}  // namespace
}  // namespace graftnav

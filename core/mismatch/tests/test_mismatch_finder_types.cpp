#include <gtest/gtest.h>

#include <stdexcept>

#include "graftnav/mismatch/candidate_terms.h"
#include "graftnav/mismatch/diagnosis.h"
#include "graftnav/mismatch/finder_options.h"
#include "graftnav/mismatch/sensor.h"
#include "graftnav/mismatch/term_kind.h"
#include "graftnav/mismatch/term_spec.h"

namespace graftnav {
namespace {

TEST(MismatchSensor, NamesAndTheScopeOfBoth) {
  EXPECT_STREQ(sensorName(Sensor::gyro), "gyro");
  EXPECT_STREQ(sensorName(Sensor::accel), "accel");
  EXPECT_STREQ(scopeName(SensorScope::both), "both");
  for (const Sensor s : kSensors) {
    EXPECT_EQ(sensorOf(scopeOf(s)), s);
    EXPECT_STREQ(scopeName(scopeOf(s)), sensorName(s));
  }
  EXPECT_EQ(firstChannel(Sensor::gyro), 0);
  EXPECT_EQ(firstChannel(Sensor::accel), 3);
  EXPECT_EQ(otherSensor(Sensor::gyro), Sensor::accel);
  EXPECT_THROW(sensorOf(SensorScope::both), std::invalid_argument);
  PerSensor<int> v;
  v[Sensor::accel] = 7;
  EXPECT_EQ(v[Sensor::gyro], 0);
  EXPECT_EQ(v[Sensor::accel], 7);
}

TEST(MismatchTermKind, EveryLibraryTermIsABuiltInRow) {
  // Every term the library builds from a minimal input is a row of the built-in registry, on a
  // scope its row allows, and its key names it as diagnosis.json does.
  RegressorInputs ri;
  const int n = 200;
  ri.reference.grid.bin_s = 0.05;
  ri.reference.grid.count = n;
  ri.reference.omega_rad_s = Eigen::MatrixXd::Random(n, 3);
  ri.reference.f_m_s2 = Eigen::MatrixXd::Random(n, 3);
  ri.reference.temperature_degC = Eigen::VectorXd::Constant(n, 20.0);
  ri.reference.f_within_rms_m_s2 = Eigen::VectorXd::Zero(n);
  ri.time_offset_column = Eigen::MatrixXd::Random(n, kMismatchChannels);
  const std::vector<CandidateTerm> terms = buildCandidateLibrary(ri);
  ASSERT_GT(terms.size(), 5u);
  EXPECT_EQ(terms[0].kind(), TermKind::constant_bias);
  EXPECT_TRUE(terms[0].nuisance());
  for (const CandidateTerm& t : terms) {
    ASSERT_NE(t.spec, nullptr);
    EXPECT_EQ(t.spec, &termSpec(t.kind())) << t.key().text();
    const TermSensors rows = t.spec->sensors;
    if (rows == TermSensors::each_triad)
      EXPECT_TRUE(isSingleSensor(t.sensor)) << t.key().text();
    else
      EXPECT_EQ(index(t.sensor), static_cast<std::size_t>(rows) - 1) << t.key().text();
  }
  EXPECT_EQ(termKey(TermKind::scale_factor, SensorScope::gyro).text(), "scale_factor:gyro");
  EXPECT_EQ(termKey(TermKind::non_orthogonality, SensorScope::accel, TermVariant::symmetric).text(),
            "non_orthogonality:accel:symmetric");
}

TEST(MismatchFinderOptions, DefaultsValidAndEachBadValueNamed) {
  EXPECT_NO_THROW(FinderOptions{}.validate());
  EXPECT_NO_THROW(DiagnoseOptions{}.validate());
  const auto message = [](const FinderOptions& o) {
    try {
      o.validate();
    } catch (const std::invalid_argument& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  FinderOptions o;
  o.lab_gate_sigmas = 0.0;
  EXPECT_NE(message(o).find("lab_gate_sigmas"), std::string::npos);
  o = FinderOptions{};
  o.max_gate_passes = 0;
  EXPECT_NE(message(o).find("max_gate_passes"), std::string::npos);
  o = FinderOptions{};
  o.rotation_rel_change = 1.0;
  EXPECT_NE(message(o).find("rotation_rel_change"), std::string::npos);
  o = FinderOptions{};
  o.min_holdout_bins = 1;
  EXPECT_NE(message(o).find("min_holdout_bins"), std::string::npos);
  DiagnoseOptions d;
  d.finder.pivot_tolerance_s = -1.0;
  EXPECT_THROW(d.validate(), std::invalid_argument);
}

}  // namespace
}  // namespace graftnav

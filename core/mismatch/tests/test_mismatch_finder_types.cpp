#include <gtest/gtest.h>

#include <stdexcept>

#include "graftnav/mismatch/candidate_terms.h"
#include "graftnav/mismatch/diagnosis.h"
#include "graftnav/mismatch/finder_options.h"
#include "graftnav/mismatch/sensor.h"
#include "graftnav/mismatch/term_kind.h"

namespace graftnav {
namespace {

TEST(MismatchSensor, NamesRoundTripAndBothIsNoSingleSensor) {
  for (const Sensor s : kSensors) EXPECT_EQ(sensorNamed(sensorName(s)), s);
  EXPECT_EQ(firstChannel(Sensor::gyro), 0);
  EXPECT_EQ(firstChannel(Sensor::accel), 3);
  EXPECT_EQ(otherSensor(Sensor::gyro), Sensor::accel);
  EXPECT_THROW(sensorNamed("both"), std::invalid_argument);
  PerSensor<int> v;
  v[Sensor::accel] = 7;
  EXPECT_EQ(v[Sensor::gyro], 0);
  EXPECT_EQ(v[Sensor::accel], 7);
}

TEST(MismatchTermKind, EveryLibraryTermHasItsKind) {
  // Every candidate the library builds from a minimal input is a kind of its own (the fixed
  // helper parts aside), so no finder decision falls through to TermKind::other.
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
  EXPECT_EQ(kindOf(terms[0]), TermKind::constant_bias);
  for (const CandidateTerm& t : terms)
    if (!t.fixed) {
      EXPECT_NE(kindOf(t), TermKind::other) << t.key();
    }
  EXPECT_EQ(termKindNamed("scale_factor"), TermKind::scale_factor);
  EXPECT_EQ(termKindNamed("no_such_term"), TermKind::other);
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

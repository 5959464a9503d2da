#include <gtest/gtest.h>

#include <stdexcept>

#include "graftnav/mismatch/candidate_terms.h"
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

}  // namespace
}  // namespace graftnav

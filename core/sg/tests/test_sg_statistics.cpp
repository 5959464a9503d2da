#include <gtest/gtest.h>

#include <cmath>

#include "graftnav/sg/sg_statistics.h"

namespace graftnav {
namespace {

TEST(SgStatistics, DiffReproducesTheSeedsTable2) {
  // Seed Table 2 (POS310): ERR_1, ERR_2, ERR_REAL -> DIFF_1, DIFF_2 (horizontal, heading).
  DriftStats err1, err2, real;
  err1.horizontal_m = 3.758;
  err2.horizontal_m = 4.857;
  real.horizontal_m = 4.688;
  err1.heading_rad = 0.066;
  err2.heading_rad = 0.093;
  real.heading_rad = 0.097;
  const DriftStats d1 = relativeDifference(err1, real);
  const DriftStats d2 = relativeDifference(err2, real);
  EXPECT_NEAR(d1.horizontal_m, 0.1984, 5e-5);
  EXPECT_NEAR(d2.horizontal_m, 0.0360, 5e-5);
  EXPECT_NEAR(d1.heading_rad, 0.3196, 5e-5);
  EXPECT_NEAR(d2.heading_rad, 0.0412, 5e-5);
  // No reference value: NaN, not a number pretending to be one.
  EXPECT_TRUE(std::isnan(d1.vertical_m));
}

TEST(SgStatistics, ArrayOrderIsTheSeedsColumnOrder) {
  const DriftStats s = fromArray({1, 2, 3, 4, 5});
  EXPECT_EQ(s.horizontal_m, 1);
  EXPECT_EQ(s.heading_rad, 5);
  EXPECT_EQ(asArray(s)[2], 3);
  EXPECT_EQ(driftStatNames()[4], "heading_deg");
}

}  // namespace
}  // namespace graftnav

// ImuSampleBuffer keeps the samples by their index in the recording through every way its
// storage moves: compaction when dropping, and compaction instead of growth when full.
#include <gtest/gtest.h>

#include <stdexcept>

#include "graftnav/graph/imu_sample_buffer.h"

namespace graftnav {
namespace {

ImuSample sampleAt(size_t i) {
  ImuSample s;
  s.t_s = 0.005 * static_cast<double>(i + 1);
  s.dt_s = 0.005;
  s.dtheta_rad.setConstant(static_cast<double>(i));
  return s;
}

void expectHeld(const ImuSampleBuffer& b, size_t begin, size_t end) {
  ASSERT_EQ(b.begin(), begin);
  ASSERT_EQ(b.end(), end);
  for (size_t i = begin; i < end; ++i) ASSERT_EQ(b.at(i).dtheta_rad.x(), static_cast<double>(i));
  if (begin > 0) {
    EXPECT_THROW(b.at(begin - 1), std::out_of_range);
  }
  EXPECT_THROW(b.at(end), std::out_of_range);
}

TEST(ImuSampleBuffer, KeepsIndicesThroughEveryCompaction) {
  ImuSampleBuffer b;
  size_t n = 0;
  for (; n < 1024; ++n) b.push(sampleAt(n));
  b.dropBefore(200);  // fewer than kMinCompact dropped: kept in storage
  expectHeld(b, 200, 1024);
  for (; n < 3000; ++n) b.push(sampleAt(n));  // full with 200 dropped: compacted, not grown
  expectHeld(b, 200, 3000);
  b.dropBefore(2990);
  for (; n < 20000; ++n) {  // long runs held with drops in between (an outage, then GNSS)
    b.push(sampleAt(n));
    if (n % 5000 == 0) b.dropBefore(n - 4500);
  }
  expectHeld(b, 15000 - 4500, 20000);
  b.dropBefore(19999);
  expectHeld(b, 19999, 20000);
}

}  // namespace
}  // namespace graftnav

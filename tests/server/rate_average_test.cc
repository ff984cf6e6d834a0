// The frame rates status reports: averaged over intervals, so jitter does not inflate them.
#include "server/pipeline/rate_average.h"

#include <gtest/gtest.h>

namespace omniview {
namespace {

TEST(RateAverage, JitterDoesNotInflateTheRate) {
  // 20 Hz on average, delivered unevenly (10 ms, 90 ms, ...). Averaging 1/dt instead would
  // settle near (100 + 11.1) / 2 = 55 Hz: the overshoot status showed.
  double mean = 0, hz = 0;
  for (int i = 0; i < 400; ++i) hz = add_interval(mean, i % 2 ? 0.090 : 0.010, 0.1);
  EXPECT_NEAR(hz, 20, 1.5);
}

TEST(RateAverage, SteadyRateAndNoInterval) {
  double mean = 0;
  EXPECT_DOUBLE_EQ(add_interval(mean, 0, 0.2), 0);  // nothing measured yet
  EXPECT_DOUBLE_EQ(add_interval(mean, 0.1, 0.2), 10);
  for (int i = 0; i < 50; ++i) add_interval(mean, 0.1, 0.2);
  EXPECT_NEAR(add_interval(mean, 0, 0.2), 10, 1e-9);  // a zero interval changes nothing
}

}  // namespace
}  // namespace omniview

// UpperMedian against medians worked out by hand.
#include "core/math/statistics.h"

#include <gtest/gtest.h>

#include <cmath>
#include <limits>

namespace nrsfm {
namespace {

TEST(UpperMedianTest, OddCountIsTheMiddleValue) {
  EXPECT_EQ(UpperMedian({5.0, -1.0, 3.0}, 0.0), 3.0);
  EXPECT_EQ(UpperMedian({7.0}, 0.0), 7.0);
}

TEST(UpperMedianTest, EvenCountIsTheLargerMiddleValue) {
  // Sorted 1, 2, 4, 9: index 2.
  EXPECT_EQ(UpperMedian({9.0, 1.0, 4.0, 2.0}, 0.0), 4.0);
  EXPECT_EQ(UpperMedian({2.0, 2.0}, 0.0), 2.0);
}

TEST(UpperMedianTest, EmptyGivesTheCallersValue) {
  EXPECT_EQ(UpperMedian({}, -1.0), -1.0);
  EXPECT_TRUE(
      std::isnan(UpperMedian({}, std::numeric_limits<double>::quiet_NaN())));
}

}  // namespace
}  // namespace nrsfm

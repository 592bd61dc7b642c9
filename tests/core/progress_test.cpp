// progress_text against hand-computed rates and remaining times.

#include <gtest/gtest.h>

#include "hazmap/core/progress.hpp"

namespace hazmap {
namespace {

TEST(Progress, RateAndTimeLeftFromTheMeanSoFar) {
  // 3 of 30 in 6 s: 0.5 frames/s, 27 frames left -> 54 s.
  EXPECT_EQ(progress_text(3, 30, 6.0), "3/30, 0.50 frames/s, 54 s left");
  // 1 of 100 in 7.2 s: 0.139 frames/s, 99 left -> 712.8 s = 11 min 53 s.
  EXPECT_EQ(progress_text(1, 100, 7.2), "1/100, 0.14 frames/s, 11 min 53 s left");
  // Slow: 1 of 40 cases in 100 s -> 0.010/s, 3900 s = 1 h 05 min.
  EXPECT_EQ(progress_text(1, 40, 100.0, "cases"), "1/40, 0.010 cases/s, 1 h 05 min left");
  EXPECT_EQ(progress_text(200, 400, 8.0), "200/400, 25 frames/s, 8.0 s left");
}

TEST(Progress, TheLastStepSaysTheTotalTime) {
  EXPECT_EQ(progress_text(30, 30, 58.0), "30/30, 0.52 frames/s, 58 s in all");
}

TEST(Progress, NothingToEstimateYet) {
  EXPECT_EQ(progress_text(0, 30, 5.0), "0/30");
  EXPECT_EQ(progress_text(2, 30, 0.0), "2/30");
  EXPECT_EQ(human_duration(-1.0), "?");
  EXPECT_EQ(human_duration(59.4), "59 s");
  EXPECT_EQ(human_duration(0.33), "0.3 s");
  EXPECT_EQ(human_duration(9.96), "10 s");
  EXPECT_EQ(human_duration(60.0), "1 min 00 s");
  EXPECT_EQ(human_duration(7260.0), "2 h 01 min");
}

}  // namespace
}  // namespace hazmap

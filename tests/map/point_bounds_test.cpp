// PointBounds (map/internal/point_bounds.hpp): the vector-lane box against std::min and
// std::max point after point, at every length around the lane steps, with NaN and
// infinite coordinates.

#include "hazmap/map/internal/point_bounds.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>
#include <vector>

#include <gtest/gtest.h>

namespace hazmap {
namespace {

TEST(PointBounds, EqualsTheScalarMinimumAndMaximumAtEveryLength) {
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<float> u(-50.0f, 50.0f);
  const float nan = std::numeric_limits<float>::quiet_NaN();
  const float inf = std::numeric_limits<float>::infinity();
  for (int n = 0; n <= 70; ++n)
    for (int variant = 0; variant < 4; ++variant) {
      std::vector<float> x(n), y(n);
      for (int i = 0; i < n; ++i) {
        x[i] = u(rng);
        y[i] = u(rng);
        if (variant == 1 && i % 3 == 0) x[i] = nan;             // skipped, not propagated
        if (variant == 2 && i % 5 == 1) y[i] = (i % 2) ? inf : -inf;
        if (variant == 3) x[i] = y[i] = nan;                    // nothing finite
      }
      // Start from a box that an earlier chunk left (the stack grows it chunk by chunk).
      PointBounds box;
      box.lo_x = 1.0f, box.hi_x = 2.0f, box.lo_y = -3.0f, box.hi_y = 4.0f;
      float lo_x = box.lo_x, hi_x = box.hi_x, lo_y = box.lo_y, hi_y = box.hi_y;
      for (int i = 0; i < n; ++i) {
        lo_x = std::min(lo_x, x[i]);
        hi_x = std::max(hi_x, x[i]);
        lo_y = std::min(lo_y, y[i]);
        hi_y = std::max(hi_y, y[i]);
      }
      box.extend(x.data(), y.data(), n);
      EXPECT_EQ(box.lo_x, lo_x) << n << " " << variant;
      EXPECT_EQ(box.hi_x, hi_x) << n << " " << variant;
      EXPECT_EQ(box.lo_y, lo_y) << n << " " << variant;
      EXPECT_EQ(box.hi_y, hi_y) << n << " " << variant;
    }
  // A fresh box over nothing stays empty (+inf, -inf).
  PointBounds empty;
  empty.extend(nullptr, nullptr, 0);
  EXPECT_EQ(empty.lo_x, std::numeric_limits<float>::infinity());
  EXPECT_EQ(empty.hi_y, -std::numeric_limits<float>::infinity());
}

}  // namespace
}  // namespace hazmap

// The pieces of the incremental hazard stage (SPEC 8.6): dirty regions, grid shifts and
// the roughness filter on a region.

#include "hazmap/hazard/dirty_region.hpp"

#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "hazmap/hazard/roughness_filter.hpp"
#include "hazmap/map/dense_grid.hpp"

namespace hazmap {
namespace {

TEST(DirtyRegion, OverlappingRectanglesMergeAndDisjointOnesStay) {
  DirtyRegion r;
  r.add({0, 2, 0, 2});
  r.add({10, 12, 10, 12});
  EXPECT_EQ(r.size(), 2);
  r.add({1, 3, 1, 3});  // overlaps the first: its hull
  EXPECT_EQ(r.size(), 2);
  EXPECT_TRUE(r.contains(2, 2));
  EXPECT_EQ(r.area(), 9 + 4);
  r.add({});  // empty: nothing
  EXPECT_EQ(r.size(), 2);
  r.dilate(4, 20, 20);  // the hulls now overlap: one rectangle, cut to the grid
  ASSERT_EQ(r.size(), 1);
  EXPECT_TRUE(r[0] == (GridRect{0, 16, 0, 16}));
}

TEST(DirtyRegion, BeyondCapacityRectanglesMergeButCoverEverything) {
  DirtyRegion r;
  for (int k = 0; k < 3 * DirtyRegion::kCapacity; ++k) r.add({3 * k, 3 * k + 1, 0, 1});
  EXPECT_LE(r.size(), DirtyRegion::kCapacity);
  for (int k = 0; k < 3 * DirtyRegion::kCapacity; ++k) EXPECT_TRUE(r.contains(3 * k, 0)) << k;
  for (int i = 0; i < r.size(); ++i)
    for (int j = i + 1; j < r.size(); ++j) EXPECT_FALSE(r[i].intersects(r[j]));
}

TEST(DenseGridShift, KeptCellsMoveAndNewOnesAreFilled) {
  DenseGrid g;
  g.reset(4, 5, 1.0, 0, 0, 0.0f);
  for (int row = 0; row < 4; ++row)
    for (int col = 0; col < 5; ++col) g.at(row, col) = float(10 * row + col);
  for (int drow : {-2, 0, 1, 3})
    for (int dcol : {-4, -1, 0, 2}) {
      DenseGrid s = g;
      s.shift(drow, dcol, -1.0f);
      for (int row = 0; row < 4; ++row)
        for (int col = 0; col < 5; ++col) {
          const int r0 = row + drow, c0 = col + dcol;
          const float want = (r0 >= 0 && r0 < 4 && c0 >= 0 && c0 < 5) ? g.at(r0, c0) : -1.0f;
          EXPECT_EQ(s.at(row, col), want) << drow << " " << dcol << " at " << row << "," << col;
        }
    }
}

TEST(RoughnessFilterRegion, EqualsTheWholeGridOnTheRegion) {
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> u(0.0f, 1.0f);
  DenseGrid h, v;
  h.reset(40, 37, 0.01, 0, 0, 0.0f);
  v.reset(40, 37, 0.01, 0, 0, 0.0f);
  for (size_t i = 0; i < h.values.size(); ++i) {
    // Quantised heights: ties between extremes, whose variance must come from the same cell.
    h.values[i] = u(rng) < 0.3f ? std::numeric_limits<float>::quiet_NaN() : std::round(u(rng) * 8) / 100;
    v.values[i] = u(rng) * 1e-4f;
  }
  for (int kernel : {3, 5, 7}) {
    RoughnessFilter whole, part;
    DenseGrid rw, sw, fw, rp, sp, fp;
    whole.compute(h, v, kernel, rw, sw, fw);
    part.compute(h, v, kernel, rp, sp, fp);  // sizes the outputs
    const float sentinel = -7.0f;
    for (DenseGrid* g : {&rp, &sp, &fp}) std::fill(g->values.begin(), g->values.end(), sentinel);
    const GridRect region{1, 9, 30, 37};  // touches the edge and the kernel-off-layer band
    part.compute(h, v, kernel, region, rp, sp, fp);
    for (int row = 0; row < h.rows; ++row)
      for (int col = 0; col < h.cols; ++col) {
        const size_t i = static_cast<size_t>(row) * h.cols + col;
        if (!region.contains(row, col)) {
          EXPECT_EQ(rp.values[i], sentinel);  // untouched
          continue;
        }
        auto same = [](float a, float b) { return (std::isnan(a) && std::isnan(b)) || a == b; };
        EXPECT_TRUE(same(rp.values[i], rw.values[i])) << kernel << " " << row << "," << col;
        EXPECT_TRUE(same(sp.values[i], sw.values[i])) << kernel << " " << row << "," << col;
        EXPECT_TRUE(same(fp.values[i], fw.values[i])) << kernel << " " << row << "," << col;
      }
  }
}

}  // namespace
}  // namespace hazmap

// KnownTerrain: the finest layer that knows answers, CCM planes are followed, unseen cells
// next to seen ones take the highest seen top within the fill distance (against a
// brute-force search), and the block bounds never undercut the cells they cover.

#include "hazmap/map/known_terrain.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

#include <gtest/gtest.h>

#include "hazmap/core/error.hpp"

namespace hazmap {
namespace {

constexpr float kNaN = std::numeric_limits<float>::quiet_NaN();

TEST(KnownTerrain, HeightComesFromTheFinestLayerThatKnows) {
  // 1 cm layer over [0, 0.2)^2 at 0.01 m with a hole; 4 cm layer over [0, 0.4)^2 with a
  // tilted plane (dz/dx 0.5) at 0.2 m, variance 4e-4.
  DenseGrid fine_h, fine_v, none;
  fine_h.reset(20, 20, 0.01, 0.1, 0.1, 0.01f);
  fine_v.reset(20, 20, 0.01, 0.1, 0.1, 1e-6f);
  fine_h.at(10, 10) = kNaN;  // the cell x in [0.10, 0.11), y in [0.09, 0.10)
  DenseGrid coarse_h, coarse_v, sx, sy;
  coarse_h.reset(10, 10, 0.04, 0.2, 0.2, 0.2f);
  coarse_v.reset(10, 10, 0.04, 0.2, 0.2, 4e-4f);
  sx.reset(10, 10, 0.04, 0.2, 0.2, 0.5f);
  sy.reset(10, 10, 0.04, 0.2, 0.2, 0.0f);
  KnownTerrain t;
  EXPECT_TRUE(t.empty());
  t.add_layer(fine_h, fine_v, none, none);
  t.add_layer(coarse_h, coarse_v, sx, sy);
  EXPECT_DOUBLE_EQ(t.finest_resolution_m(), 0.01);
  double h = 0, var = 0;
  ASSERT_TRUE(t.height_at(0.055, 0.155, &h, &var));
  EXPECT_NEAR(h, 0.01, 1e-7);
  EXPECT_NEAR(var, 1e-6, 1e-12);
  // In the hole: the coarse cell x in [0.08, 0.12), centre 0.10, its plane at x = 0.105.
  ASSERT_TRUE(t.height_at(0.105, 0.095, &h, &var));
  EXPECT_NEAR(h, 0.2 + 0.5 * 0.005, 1e-7);
  EXPECT_NEAR(var, 4e-4, 1e-10);
  // Beyond the fine layer, inside the coarse one; beyond both.
  ASSERT_TRUE(t.height_at(0.3, 0.3, &h, &var));
  EXPECT_NEAR(h, 0.2 + 0.5 * (0.3 - 0.30), 1e-6);
  EXPECT_FALSE(t.height_at(0.5, 0.1, &h, &var));
  // NaN slopes: the cell height.
  sx.values.assign(sx.values.size(), kNaN);
  ASSERT_TRUE(t.height_at(0.105, 0.095, &h, &var));
  EXPECT_NEAR(h, 0.2, 1e-7);
  // Grids of another size are refused.
  DenseGrid odd;
  odd.reset(3, 3, 0.04, 0.0, 0.0, 0.0f);
  EXPECT_THROW(t.add_layer(coarse_h, odd, none, none), Error);
  t.clear();
  EXPECT_TRUE(t.empty());
  EXPECT_FALSE(t.prepared());
}

// A 1 cm map of level ground (known at 0) with a 10 cm block and an unseen band beside it
// and an unseen region away from everything: prepare_near_field's assumed heights equal
// the highest known top within the fill distance, cell by cell.
TEST(KnownTerrain, UnseenCellsTakeTheHighestSeenTopWithinTheFillDistance) {
  DenseGrid h, v, none;
  h.reset(40, 40, 0.01, 0.2, 0.2, 0.0f);  // x, y in [0, 0.4)
  v.reset(40, 40, 0.01, 0.2, 0.2, 1e-6f);
  for (int r = 10; r < 20; ++r)
    for (int c = 10; c < 20; ++c) h.at(r, c) = 0.1f;  // the block
  for (int r = 10; r < 20; ++r)
    for (int c = 20; c < 28; ++c) h.at(r, c) = kNaN;  // unseen beside it
  for (int r = 30; r < 40; ++r)
    for (int c = 30; c < 40; ++c) h.at(r, c) = kNaN;  // unseen, 4+ cells from the block
  KnownTerrain t;
  t.add_layer(h, v, none, none);
  t.prepare_near_field(0.0, 0.0, 0.399, 0.399, 0.025, 3.0);  // 2.5 cm: 3 cells
  ASSERT_TRUE(t.prepared());
  EXPECT_NEAR(t.max_top(), 0.1 + 3 * 1e-3, 1e-6);
  EXPECT_NEAR(t.max_unseen_height(), 0.1, 1e-6);
  int filled = 0;
  for (int r = 0; r < 40; ++r)
    for (int c = 0; c < 40; ++c) {
      const double x = h.x_of_col(c), y = h.y_of_row(r);
      float want = -std::numeric_limits<float>::infinity();
      if (std::isnan(h.at(r, c)))
        for (int rr = std::max(0, r - 3); rr <= std::min(39, r + 3); ++rr)
          for (int cc = std::max(0, c - 3); cc <= std::min(39, c + 3); ++cc)
            if (!std::isnan(h.at(rr, cc))) want = std::max(want, h.at(rr, cc));
      double got = 0;
      const bool has = t.unseen_height_at(x, y, &got);
      ASSERT_EQ(has, std::isfinite(want)) << r << "," << c;
      if (has) {
        EXPECT_NEAR(got, want, 1e-7) << r << "," << c;
        ++filled;
      }
    }
  // The band's cells within 3 of the block or the ground around it (all but its middle
  // 2 x 4), and the unseen corner region's cells within 3 of the ground (the grid ends at
  // its far sides).
  EXPECT_EQ(filled, (10 * 8 - 2 * 4) + (10 * 10 - 7 * 7));
  double top = 0;
  ASSERT_TRUE(t.unseen_height_at(0.225, 0.255, &top));  // column 22, row 14
  EXPECT_NEAR(top, 0.1, 1e-7);
  EXPECT_FALSE(t.unseen_height_at(0.355, 0.055, &top));  // deep in the unseen region
  // A fill distance of 0 assumes nothing.
  t.prepare_near_field(0.0, 0.0, 0.399, 0.399, 0.0, 3.0);
  EXPECT_FALSE(t.unseen_height_at(0.225, 0.255, &top));
  EXPECT_EQ(t.max_unseen_height(), -std::numeric_limits<double>::infinity());
}

TEST(KnownTerrain, BlockLevelsBoundEveryCellTheyCover) {
  // Random heights and variances, some unseen cells; every box's levels are at least the
  // brute-force maxima over the cells it touches.
  std::mt19937 rng(7);
  std::uniform_real_distribution<float> height(-0.05f, 0.15f), unit(0.0f, 1.0f);
  DenseGrid h, v, none;
  h.reset(50, 50, 0.01, 0.25, 0.25, 0.0f);
  v.reset(50, 50, 0.01, 0.25, 0.25, 0.0f);
  for (float& x : h.values) x = unit(rng) < 0.2f ? kNaN : height(rng);
  for (float& x : v.values) x = 1e-5f * unit(rng);
  KnownTerrain t;
  t.add_layer(h, v, none, none);
  t.prepare_near_field(0.0, 0.0, 0.5, 0.5, 0.02, 3.0);
  std::uniform_real_distribution<double> pos(0.0, 0.499);
  for (int k = 0; k < 500; ++k) {
    const double x0 = pos(rng), x1 = pos(rng), y0 = pos(rng), y1 = pos(rng);
    const KnownTerrain::Levels levels = t.max_levels_in(x0, y0, x1, y1);
    double top = -1e9, unseen = -1e9;
    for (int r = 0; r < 50; ++r)
      for (int c = 0; c < 50; ++c) {
        const double x = h.x_of_col(c), y = h.y_of_row(r);
        if (std::abs(x - 0.5 * (x0 + x1)) > 0.5 * std::abs(x1 - x0) + 0.005 ||
            std::abs(y - 0.5 * (y0 + y1)) > 0.5 * std::abs(y1 - y0) + 0.005)
          continue;
        double hh = 0, var = 0;
        if (t.height_at(x, y, &hh, &var)) top = std::max(top, hh + 3 * std::sqrt(var));
        if (t.unseen_height_at(x, y, &hh)) unseen = std::max(unseen, hh);
      }
    EXPECT_GE(levels.top_m, top - 1e-6) << k;
    EXPECT_GE(levels.unseen_m, unseen - 1e-6) << k;
    EXPECT_LE(levels.top_m, t.max_top() + 1e-6);  // blocks hold floats
  }
}

}  // namespace
}  // namespace hazmap

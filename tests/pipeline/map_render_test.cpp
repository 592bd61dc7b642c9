// PNG panels: the robust colour range against a sorted copy, the scale bar's 1-2-5
// choice, and what a person sees: a wild cell no longer flattens the height colours, the
// robot marker leaves the cell under it visible, every panel has its labelled footer.

#include <algorithm>
#include <cmath>
#include <set>
#include <vector>

#include <gtest/gtest.h>

#include "hazmap/pipeline/map_render.hpp"

namespace hazmap {
namespace {

DenseGrid grid(int n, double resolution, float fill) {
  DenseGrid g;
  g.reset(n, n, resolution, 0.0, 0.0, fill);
  return g;
}

TEST(MapRender, RobustRangeIsTheNearestRankPercentiles) {
  DenseGrid g = grid(20, 0.01, NAN);
  std::vector<float> known;
  for (int i = 0; i < 301; ++i) {  // 301 known cells in a scrambled order, the rest NaN
    const float v = static_cast<float>((i * 37) % 301) * 0.001f;
    g.values[static_cast<size_t>(i)] = v;
    known.push_back(v);
  }
  g.values[350] = 5.0f;  // one wild cell
  known.push_back(5.0f);
  std::sort(known.begin(), known.end());
  const HeightRange r = robust_height_range(g, 2.0);
  ASSERT_TRUE(r.any);
  const double n1 = static_cast<double>(known.size() - 1);
  EXPECT_EQ(r.lo, known[static_cast<size_t>(std::lround(0.02 * n1))]);
  EXPECT_EQ(r.hi, known[static_cast<size_t>(std::lround(0.98 * n1))]);
  EXPECT_EQ(r.min, known.front());
  EXPECT_EQ(r.max, 5.0f);
  EXPECT_LT(r.hi, 0.3);  // the wild cell is outside the coloured range
  const HeightRange all = robust_height_range(g, 0.0);
  EXPECT_EQ(all.lo, all.min);
  EXPECT_EQ(all.hi, all.max);
  EXPECT_FALSE(robust_height_range(grid(4, 0.01, NAN), 2.0).any);
}

TEST(MapRender, ScaleBarIsOneTwoOrFiveUnderAQuarterOfTheWidth) {
  EXPECT_DOUBLE_EQ(scale_bar_length_m(1.28), 0.2);
  EXPECT_DOUBLE_EQ(scale_bar_length_m(2.56), 0.5);
  EXPECT_DOUBLE_EQ(scale_bar_length_m(5.12), 1.0);
  EXPECT_DOUBLE_EQ(scale_bar_length_m(10.24), 2.0);
  EXPECT_DOUBLE_EQ(scale_bar_length_m(4.0), 1.0);  // exactly a quarter
  EXPECT_DOUBLE_EQ(scale_bar_length_m(0.0), 0.0);
}

/// Distinct colours among the map pixels of the known cells (rows/cols < n*k).
std::size_t colours_in(const cv::Mat& image, int map_px) {
  std::set<int> seen;
  for (int r = 0; r < map_px; ++r)
    for (int c = 0; c < map_px; ++c) {
      const cv::Vec3b p = image.at<cv::Vec3b>(r, c);
      seen.insert(p[0] << 16 | p[1] << 8 | p[2]);
    }
  return seen.size();
}

TEST(MapRender, OneWildCellDoesNotFlattenTheHeightColours) {
  // A 10 cm ramp over 64 columns and one cell at +10 m (a stereo outlier).
  DenseGrid g = grid(64, 0.01, 0.0f);
  for (int r = 0; r < 64; ++r)
    for (int c = 0; c < 64; ++c)
      g.values[static_cast<size_t>(r * 64 + c)] = 0.1f * static_cast<float>(c) / 63.0f;
  g.values[0] = 10.0f;
  const RobotMarker away{100.0, 100.0};  // outside the map
  const cv::Mat robust = render_height(g, 256, away, "L0 test", 2.0);
  const cv::Mat full = render_height(g, 256, away, "L0 test", 0.0);
  const int map_px = 256;  // 64 cells x 4 px
  EXPECT_GT(colours_in(robust, map_px), 40u);
  // The ramp is 1 % of the full range: 4 of 256 levels, plus the wild cell's colour.
  EXPECT_LE(colours_in(full, map_px), 5u);
  // Below the map: the footer (title, extent, note) and nothing else is taller.
  EXPECT_GT(robust.rows, map_px);
}

TEST(MapRender, TheRobotMarkerIsHollowAndTheFooterIsLabelled) {
  DenseGrid g = grid(64, 0.02, 1.0f);  // all traversable, 1.28 m
  const RobotMarker robot{0.0, 0.0, 0.0};
  const cv::Mat image = render_hazard(g, 320, robot, "L0 kalman hazard");
  const int k = 5, map_px = 64 * k;  // ceil(320 / 64)
  ASSERT_EQ(image.cols, map_px);
  ASSERT_GT(image.rows, map_px);
  const cv::Vec3b traversable(70, 170, 40);
  // The cell under the robot keeps its colour; the ring (radius 5 px) is white.
  const auto bright = [&](int r, int c) {
    const cv::Vec3b p = image.at<cv::Vec3b>(r, c);
    return std::min({p[0], p[1], p[2]}) > 200;
  };
  EXPECT_EQ(image.at<cv::Vec3b>(map_px / 2, map_px / 2), traversable);
  int ring = 0;
  for (int d = 3; d <= 7; ++d) ring += bright(map_px / 2 + d, map_px / 2);
  EXPECT_GT(ring, 0);
  // The heading tick points along +x (to the right) beyond the ring, not to the left.
  int right = 0, left = 0;
  for (int d = 7; d <= 10; ++d) {
    right += bright(map_px / 2, map_px / 2 + d);
    left += bright(map_px / 2, map_px / 2 - d);
  }
  EXPECT_GT(right, 0);
  EXPECT_EQ(left, 0);
  // The footer holds light text on the dark background.
  int text_px = 0;
  for (int r = map_px; r < image.rows; ++r)
    for (int c = 0; c < image.cols; ++c) text_px += image.at<cv::Vec3b>(r, c)[1] > 150;
  EXPECT_GT(text_px, 200);
}

}  // namespace
}  // namespace hazmap

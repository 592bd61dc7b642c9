// PNG panels: the robust colour range against a sorted copy, the scale bar's 1-2-5
// choice, and what a person sees: a wild cell no longer flattens the height colours, the
// robot marker leaves the cell under it visible, every panel has its labelled footer, the
// axis glyph sits in its corner and covers nothing else, a fixed map side pads a panel.

#include <algorithm>
#include <cmath>
#include <set>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/imgcodecs.hpp>

#include "hazmap/io/images.hpp"
#include "hazmap/pipeline/map_render.hpp"
#include "test_support.hpp"

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

/// Distinct colours among the map pixels of the known cells (rows/cols < n*k), the axis
/// glyph left out.
std::size_t colours_in(const cv::Mat& image, int map_px) {
  std::set<int> seen;
  const cv::Rect glyph = axis_glyph_box({map_px, map_px});
  for (int r = 0; r < map_px; ++r)
    for (int c = 0; c < map_px; ++c) {
      if (glyph.contains({c, r})) continue;
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

/// A grid of pseudo-random classes (unknown, traversable, hazard).
DenseGrid random_classes(int n, double resolution) {
  DenseGrid g = grid(n, resolution, 0.0f);
  unsigned state = 12345u;
  for (float& v : g.values) {
    state = state * 1103515245u + 12345u;
    v = static_cast<float>((state >> 16) % 3u);
  }
  return g;
}

cv::Vec3b palette(float v) {  // BGR, as the header's RGB
  return v == 2.0f ? cv::Vec3b(40, 40, 220) : v == 1.0f ? cv::Vec3b(70, 170, 40) : cv::Vec3b(90, 90, 90);
}

bool white(const cv::Vec3b& p) { return std::min({p[0], p[1], p[2]}) > 200; }

/// The longest run of white pixels inside `box` along rows (`horizontal`) or columns:
/// its length and where it starts (x, y).
std::pair<int, cv::Point> longest_white_run(const cv::Mat& image, const cv::Rect& box, bool horizontal) {
  int best = 0;
  cv::Point at;
  const int lines = horizontal ? box.height : box.width, along = horizontal ? box.width : box.height;
  for (int l = 0; l < lines; ++l) {
    int run = 0;
    for (int a = 0; a < along; ++a) {
      const cv::Point p = horizontal ? cv::Point(box.x + a, box.y + l) : cv::Point(box.x + l, box.y + a);
      run = white(image.at<cv::Vec3b>(p)) ? run + 1 : 0;
      if (run > best) {
        best = run;
        at = horizontal ? cv::Point(p.x - run + 1, p.y) : cv::Point(p.x, p.y - run + 1);
      }
    }
  }
  return {best, at};
}

TEST(MapRender, TheAxisGlyphSitsInTheCornerAndLeavesEveryOtherCellItsColour) {
  // 128 cells of random classes, 4 px each; the robot outside the map.
  const DenseGrid g = random_classes(128, 0.01);
  const RobotMarker away{100.0, 100.0, 0.0};
  testing::TempDir dir;
  write_png(dir / "hazard.png", render_hazard(g, 512, away, "L0 kalman hazard"));
  const cv::Mat image = cv::imread((dir / "hazard.png").string(), cv::IMREAD_COLOR);
  const int k = 4, map_px = 128 * k;
  ASSERT_EQ(image.cols, map_px);
  const cv::Rect box = axis_glyph_box({map_px, map_px});
  ASSERT_FALSE(box.empty());
  // The bottom-left corner, small: under 2 % of the map.
  EXPECT_LE(box.x, 4);
  EXPECT_GE(box.y + box.height, map_px - 4);
  EXPECT_LE(box.y + box.height, map_px);
  EXPECT_LT(box.area(), map_px * map_px / 50);
  // Outside the glyph's box every map pixel is its cell's palette colour, read back from
  // the written PNG.
  int changed = 0;
  for (int r = 0; r < map_px; ++r)
    for (int c = 0; c < map_px; ++c)
      if (!box.contains({c, r}) &&
          image.at<cv::Vec3b>(r, c) != palette(g.values[static_cast<size_t>((r / k) * 128 + c / k)]))
        ++changed;
  EXPECT_EQ(changed, 0);
  // Inside it: two white arrows. The longest white row is the x arrow: at the bottom,
  // from the left; the longest white column is the y arrow: at the left, up from the
  // bottom, where the x arrow starts.
  const auto [x_len, x_at] = longest_white_run(image, box, true);
  const auto [y_len, y_at] = longest_white_run(image, box, false);
  EXPECT_GE(x_len, 14);
  EXPECT_GE(y_len, 14);
  EXPECT_GT(x_at.y, box.y + box.height / 2) << "x arrow in the lower half";
  EXPECT_LT(x_at.x, box.x + box.width / 4) << "x arrow from the left";
  EXPECT_LT(y_at.x, box.x + box.width / 4) << "y arrow at the left";
  EXPECT_NEAR(y_at.y + y_len - 1, x_at.y, 3) << "the y arrow rises from the x arrow's row";
  EXPECT_NEAR(y_at.x, x_at.x, 3) << "both arrows from one origin";

  // The height panel carries it too, in its map part (the colour bar is to the right).
  DenseGrid h = grid(128, 0.01, 0.0f);
  const cv::Mat height = render_height(h, 512, away, "L0", 2.0);
  int glyph_white = 0;
  for (int r = box.y; r < box.y + box.height; ++r)
    for (int c = box.x; c < box.x + box.width; ++c) glyph_white += white(height.at<cv::Vec3b>(r, c));
  EXPECT_GT(glyph_white, 2 * 14);
  // A map too small to hold it gets none.
  EXPECT_TRUE(axis_glyph_box({40, 40}).empty());
  const cv::Mat tiny = render_hazard(grid(10, 0.01, 1.0f), 40, away, "tiny");
  for (int r = 0; r < 40; ++r)
    for (int c = 0; c < 40; ++c) ASSERT_EQ(tiny.at<cv::Vec3b>(r, c), palette(1.0f)) << r << ", " << c;
}

TEST(MapRender, AFixedMapSideCentresWholePixelCellsOnTheBackground) {
  // 42 cells in 336 px: 8 px each, no border; 32 cells: 10 px each, 8 px of background
  // around them; the footer's scale bar and the glyph follow the padded map.
  const RobotMarker away{100.0, 100.0};
  EXPECT_EQ(map_side_px(grid(42, 0.04, 1.0f), 320, 320), 336);  // ceil(320 / 42) = 8
  EXPECT_EQ(map_side_px(grid(32, 0.08, 1.0f), 320, 320), 320);
  EXPECT_EQ(map_side_px(grid(512, 0.01, 1.0f), 320, 320), 512);  // 2 x 2 cells per pixel, 2 px
  const DenseGrid g = random_classes(32, 0.08);
  const cv::Mat panel = render_hazard(g, 320, away, "L1 ccm hazard", 320, 336);
  ASSERT_EQ(panel.cols, 336);
  const cv::Vec3b background(30, 30, 30);
  const cv::Rect glyph = axis_glyph_box({336, 336});
  int wrong = 0;
  for (int r = 0; r < 336; ++r)
    for (int c = 0; c < 336; ++c) {
      if (glyph.contains({c, r})) continue;
      const bool inside = r >= 8 && r < 328 && c >= 8 && c < 328;
      const cv::Vec3b want =
          inside ? palette(g.values[static_cast<size_t>(((r - 8) / 10) * 32 + (c - 8) / 10)]) : background;
      wrong += panel.at<cv::Vec3b>(r, c) != want;
    }
  EXPECT_EQ(wrong, 0);
  const cv::Mat h = render_height(grid(32, 0.08, 0.0f), 320, away, "L1 ccm", 2.0, 320, 336);
  EXPECT_EQ(h.at<cv::Vec3b>(4, 4), background);
  EXPECT_EQ(h.at<cv::Vec3b>(168, 168), h.at<cv::Vec3b>(10, 10));  // one flat height
  EXPECT_NE(h.at<cv::Vec3b>(168, 168), background);
}

}  // namespace
}  // namespace hazmap

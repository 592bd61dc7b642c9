// stereo.match_left_border: OpenCV's StereoBM and StereoSGBM leave the left image's first
// min_disparity + num_disparities columns blank. With the key the matcher pads both images
// and matches them. Checked on a pair whose disparity is known exactly: a textured surface
// whose disparity grows down the image as the ground's does (integer per row), with
// left-only texture where the left camera sees past the right image's edge.

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "hazmap/stereo/disparity.hpp"

namespace hazmap {
namespace {

constexpr int kRows = 160, kCols = 360, kNumDisparities = 112, kBlock = 11;

/// Disparity of row y: 16 px at the top to 55 px at the bottom, like ground seen from above.
int true_disparity(int y) { return 16 + y / 4; }

/// Random 3 x 3 px blobs (a spread of 60 DN around 128).
cv::Mat blobs(int rows, int cols, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_int_distribution<int> grey(68, 188);
  cv::Mat img(rows, cols, CV_8UC1);
  for (int y = 0; y < rows; y += 3)
    for (int x = 0; x < cols; x += 3) {
      const int v = grey(rng);
      for (int yy = y; yy < std::min(y + 3, rows); ++yy)
        for (int xx = x; xx < std::min(x + 3, cols); ++xx)
          img.at<std::uint8_t>(yy, xx) = static_cast<std::uint8_t>(v);
    }
  return img;
}

struct Pair {
  cv::Mat left, right;
};

/// right(x, y) = texture; left(x, y) = right(x - d(y), y) where that lies in the right
/// image, else texture only the left camera sees (another random pattern).
Pair pair() {
  Pair p;
  p.right = blobs(kRows, kCols, 11);
  const cv::Mat left_only = blobs(kRows, kCols, 12);
  p.left.create(kRows, kCols, CV_8UC1);
  for (int y = 0; y < kRows; ++y)
    for (int x = 0; x < kCols; ++x) {
      const int xr = x - true_disparity(y);
      p.left.at<std::uint8_t>(y, x) = xr >= 0 ? p.right.at<std::uint8_t>(y, xr) : left_only.at<std::uint8_t>(y, x);
    }
  return p;
}

StereoConfig config(StereoMatcher matcher, bool match_left_border) {
  StereoConfig c;
  c.matcher = matcher;
  c.num_disparities = kNumDisparities;
  c.block_size = kBlock;
  c.disp12_max_diff = 1;
  c.match_left_border = match_left_border;
  return c;
}

cv::Mat disparity(const StereoConfig& c, const Pair& p) {
  DisparityMatcher m(c);
  cv::Mat d;
  m.compute(p.left, p.right, d);
  return d;
}

class LeftBorder : public ::testing::TestWithParam<StereoMatcher> {};

/// Share of valid pixels within 1 px and within 0.25 px of the true disparity.
struct Accuracy {
  int valid = 0, within_1px = 0, within_quarter = 0;
  void add(short v, int truth) {
    if (v <= 0) return;
    const double e = std::abs(v / 16.0 - truth);
    ++valid;
    within_1px += e <= 1.0;
    within_quarter += e <= 0.25;
  }
  double share_1px() const { return double(within_1px) / valid; }
  double share_quarter() const { return double(within_quarter) / valid; }
};

TEST_P(LeftBorder, OffLeavesTheBandBlankOnMatchesItAsTheRest) {
  const Pair p = pair();
  const cv::Mat off = disparity(config(GetParam(), false), p);
  const cv::Mat on = disparity(config(GetParam(), true), p);
  ASSERT_EQ(on.size(), p.left.size());
  ASSERT_EQ(on.type(), CV_16SC1);
  const int half = kBlock / 2;
  int band_pixels = 0, same = 0, inner = 0;
  Accuracy band, rest;
  for (int y = half; y < kRows - half; ++y) {
    const int d = true_disparity(y);
    for (int x = 0; x < kNumDisparities; ++x) {
      EXPECT_LE(off.at<short>(y, x), 0) << "OpenCV's blank band, " << x << ", " << y;
      const short v = on.at<short>(y, x);
      // Within a window of the right image's edge (left-only texture included): no match.
      if (x < d + kBlock) {
        EXPECT_LE(v, 0) << "too near the right image's edge: " << x << ", " << y << " d " << v / 16.0;
        continue;
      }
      ++band_pixels;
      band.add(v, d);
    }
    // Past the band both searches see the same windows: the same disparities (the
    // speckle filter and the left-right check may differ within a few windows of the seam).
    for (int x = kNumDisparities + 3 * kBlock; x < kCols - half; ++x) {
      ++inner;
      same += on.at<short>(y, x) == off.at<short>(y, x);
      rest.add(off.at<short>(y, x), d);
    }
  }
  std::cout << enum_name(GetParam()) << ": band " << band.valid << " of " << band_pixels
            << " valid, " << 100 * band.share_1px() << " % within 1 px, "
            << 100 * band.share_quarter() << " % within 0.25 px; the rest "
            << 100 * rest.share_1px() << " / " << 100 * rest.share_quarter() << " %\n";
  // Matched nearly everywhere a window to spare allows, as well as the rest of the image:
  // within 1 px almost always, and within 0.25 px (sub-pixel bias on integer shifts of a
  // blob texture) about as often as past the band.
  EXPECT_GE(band.valid, 0.95 * band_pixels);
  EXPECT_GE(band.share_1px(), 0.99);
  EXPECT_GE(band.share_quarter(), rest.share_quarter() - 0.05);
  EXPECT_GE(same, 0.999 * inner) << same << " of " << inner;
}

INSTANTIATE_TEST_SUITE_P(Matchers, LeftBorder,
                         ::testing::Values(StereoMatcher::bm, StereoMatcher::sgbm),
                         [](const ::testing::TestParamInfo<StereoMatcher>& param) {
                           return std::string(enum_name(param.param));
                         });

}  // namespace
}  // namespace hazmap

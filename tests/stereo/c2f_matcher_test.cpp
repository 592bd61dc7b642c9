// The coarse-to-fine census matcher (stereo/c2f_matcher.hpp) against independent
// computations: a brute-force census + winner-takes-all, pairs with known disparities,
// the scalar kernels against the AVX2 ones, and a gain / offset change of one image.

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <random>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgproc.hpp>

#include "hazmap/core/error.hpp"
#include "hazmap/stereo/c2f_matcher.hpp"

namespace hazmap {
namespace {

/// Smooth random texture: white noise blurred (so that pyramid levels keep texture).
cv::Mat texture(cv::Size size, unsigned seed, double blur = 1.2) {
  cv::Mat noise(size, CV_8UC1);
  cv::RNG rng(seed);
  rng.fill(noise, cv::RNG::UNIFORM, 0, 256);
  cv::Mat smooth;
  cv::GaussianBlur(noise, smooth, cv::Size(0, 0), blur);
  cv::normalize(smooth, smooth, 0, 255, cv::NORM_MINMAX);
  return smooth;
}

C2fConfig plain_config() {
  C2fConfig c;
  c.levels = 3;
  c.radius = 2;
  c.census_width = 9;
  c.census_height = 7;
  c.p1 = 8;
  c.p2 = 48;
  c.paths = 4;
  c.lr_max_diff = 1;
  c.uniqueness = 5;
  return c;
}

// Census of one pixel, written out plainly: clamped coordinates, row-major bit order.
std::uint64_t census_at(const cv::Mat& img, int x, int y, int cw, int ch) {
  std::uint64_t code = 0;
  const int c = img.at<std::uint8_t>(y, x);
  for (int dy = -ch / 2; dy <= ch / 2; ++dy)
    for (int dx = -cw / 2; dx <= cw / 2; ++dx) {
      if (dx == 0 && dy == 0) continue;
      const int yy = std::clamp(y + dy, 0, img.rows - 1);
      const int xx = std::clamp(x + dx, 0, img.cols - 1);
      code = (code << 1) | (img.at<std::uint8_t>(yy, xx) < c ? 1u : 0u);
    }
  return code;
}

// With P1 = P2 = 0 the aggregation adds nothing (every path cost is the pixel's own
// cost), so one level without gates is census + winner-takes-all: computed here by brute
// force, with the same parabola, and compared pixel by pixel.
TEST(C2fMatcher, OneLevelWithoutPenaltiesIsBruteForceCensusWinnerTakesAll) {
  const cv::Size size(96, 40);
  const cv::Mat left = texture(size, 11, 0.8);
  const cv::Mat right = texture(size, 12, 0.8);  // unrelated: every cost matters
  C2fConfig c = plain_config();
  c.levels = 1;
  c.p1 = c.p2 = 0;
  c.lr_max_diff = -1;
  c.uniqueness = 0;
  c.census_width = 5;
  c.census_height = 5;
  const int lo = 0, hi = 24;
  C2fMatcher matcher(c, lo, hi, size, 0, 0, C2fKernels::scalar);
  cv::Mat disp;
  matcher.compute(left, right, disp);
  ASSERT_EQ(disp.type(), CV_16SC1);

  int compared = 0;
  for (int y = 0; y < size.height; ++y)
    for (int x = 0; x < size.width; ++x) {
      const std::uint64_t cl = census_at(left, x, y, 5, 5);
      std::vector<int> cost(hi - lo);
      for (int d = lo; d < hi; ++d)
        cost[static_cast<size_t>(d - lo)] =
            x - d >= 0 ? __builtin_popcountll(cl ^ census_at(right, x - d, y, 5, 5)) : 24;
      const int kb = static_cast<int>(std::min_element(cost.begin(), cost.end()) - cost.begin());
      if (x - lo - kb < 0) {
        EXPECT_LT(disp.at<std::int16_t>(y, x), 0);
        continue;
      }
      double d = lo + kb;
      if (kb > 0 && kb < hi - lo - 1) {
        const int a = cost[static_cast<size_t>(kb - 1)], b = cost[static_cast<size_t>(kb)],
                  e = cost[static_cast<size_t>(kb + 1)];
        if (a + e - 2 * b > 0) d += (a - e) / (2.0 * (a + e - 2 * b));
      }
      ASSERT_EQ(disp.at<std::int16_t>(y, x), static_cast<int>(std::lround(16 * d)))
          << "at " << x << ", " << y;
      ++compared;
    }
  EXPECT_GT(compared, size.area() * 3 / 4);
}

// A fronto-parallel plane at 17 px, and a square at 31 px in front of a plane at 13 px:
// integer shifts, so the exact disparity costs zero. c2f over three levels finds it
// within half a pixel at >= 98.5 % of the pixels away from the borders and the square's
// edges (measured: 99.8 % plane, 98.9 % step); the parabola through census costs, which
// are not symmetric about the match, moves it by less than 0.15 px on average there
// (measured 0.11).
TEST(C2fMatcher, FindsKnownPlanesAndAStepExactly) {
  const cv::Size size(240, 160);
  const cv::Mat wide = texture(cv::Size(size.width + 64, size.height), 5);
  const cv::Mat left = wide(cv::Rect(0, 0, size.width, size.height)).clone();
  for (const bool step : {false, true}) {
    // Disparity of each right pixel, then of each left pixel (the square occludes).
    cv::Mat truth_left(size, CV_32S, cv::Scalar(step ? 13 : 17));
    const cv::Rect square(110, 50, 60, 60);
    if (step) truth_left(square).setTo(31);
    // Build the right image by forward warping the left: nearer pixels win.
    cv::Mat right(size, CV_8UC1, cv::Scalar(0));
    cv::Mat zbuf(size, CV_32S, cv::Scalar(-1));
    for (int y = 0; y < size.height; ++y)
      for (int x = 0; x < size.width + 64; ++x) {
        // Left pixel x (beyond the image: the background's texture continues).
        const int d = x < size.width ? truth_left.at<int>(y, x) : (step ? 13 : 17);
        const int xr = x - d;
        if (xr < 0 || xr >= size.width) continue;
        if (d > zbuf.at<int>(y, xr)) {
          zbuf.at<int>(y, xr) = d;
          right.at<std::uint8_t>(y, xr) = wide.at<std::uint8_t>(y, x);
        }
      }
    C2fMatcher matcher(plain_config(), 0, 48, size, 0, 0);
    cv::Mat disp;
    matcher.compute(left, right, disp);
    int checked = 0, exact = 0;
    double abs_error = 0;
    for (int y = 8; y < size.height - 8; ++y)
      for (int x = 40; x < size.width - 8; ++x) {
        bool near_edge = false;
        if (step) {
          cv::Rect grown(square.x - 8, square.y - 8, square.width + 16, square.height + 16);
          cv::Rect inner(square.x + 6, square.y + 6, square.width - 12, square.height - 12);
          near_edge = grown.contains({x, y}) && !inner.contains({x, y});
          // The background the square hides in the right image.
          near_edge = near_edge || (y >= square.y && y < square.y + square.height &&
                                    x >= square.x - 31 && x < square.x + 8);
        }
        if (near_edge) continue;
        ++checked;
        const double error = disp.at<std::int16_t>(y, x) / 16.0 - truth_left.at<int>(y, x);
        if (std::abs(error) >= 0.5) continue;
        ++exact;
        abs_error += std::abs(error);
      }
    EXPECT_GT(checked, 10000);
    EXPECT_GE(exact, checked * 985 / 1000) << (step ? "step" : "plane") << ": " << exact
                                           << " of " << checked;
    EXPECT_LT(abs_error / exact, 0.15) << (step ? "step" : "plane");
  }
}

// The AVX2 kernels compute the same integers as the scalar ones: equal disparities,
// whatever the levels, paths and seeding.
TEST(C2fMatcher, Avx2KernelsEqualTheScalarReference) {
  const cv::Size size(203, 131);  // odd sizes: uneven pyramid levels
  const cv::Mat wide = texture(cv::Size(size.width + 40, size.height), 21);
  const cv::Mat left = wide(cv::Rect(0, 0, size.width, size.height)).clone();
  cv::Mat right = wide(cv::Rect(20, 0, size.width, size.height)).clone();
  // Untextured patches: holes the fine levels must handle.
  right(cv::Rect(60, 40, 30, 30)).setTo(128);
  cv::Mat noise(size, CV_8UC1);
  cv::randn(noise, 0, 6);
  cv::add(right, noise, right);
  for (const int paths : {4, 8})
    for (const bool fill : {false, true})
      for (const int levels : {1, 3}) {
        C2fConfig c = plain_config();
        c.paths = paths;
        c.fill_unseeded = fill;
        c.levels = levels;
        C2fMatcher scalar(c, 0, 64, size, 50, 1, C2fKernels::scalar);
        C2fMatcher fast(c, 0, 64, size, 50, 1, C2fKernels::best);
        if (!fast.uses_avx2()) GTEST_SKIP() << "no AVX2 on this CPU";
        cv::Mat a, b;
        scalar.compute(left, right, a);
        fast.compute(left, right, b);
        EXPECT_EQ(cv::countNonZero(a != b), 0) << paths << " paths, fill " << fill << ", "
                                               << levels << " levels";
        EXPECT_GT(cv::countNonZero(a > 0), size.area() / 2);
      }
}

// The same for every kernel a level can use: the 8-lane narrow passes (radius 1-3,
// windows of 3-7 disparities, costs computed in the row pass), the 16-lane step (radius
// 7: 15), and census windows from 5 x 3 to 9 x 7 (the AVX2 census works in 32-pixel
// chunks: 203 columns leave a tail at every level). Disparities and confidences equal.
TEST(C2fMatcher, Avx2KernelsEqualTheScalarReferenceForEveryWindow) {
  const cv::Size size(203, 97);
  const cv::Mat wide = texture(cv::Size(size.width + 40, size.height), 33);
  const cv::Mat left = wide(cv::Rect(0, 0, size.width, size.height)).clone();
  cv::Mat right = wide(cv::Rect(17, 0, size.width, size.height)).clone();
  right(cv::Rect(100, 30, 25, 20)).setTo(90);
  cv::Mat noise(size, CV_8UC1);
  cv::randn(noise, 0, 8);
  cv::add(right, noise, right);
  struct Case { int radius, cw, ch; };
  for (const Case k : {Case{1, 9, 7}, Case{2, 5, 3}, Case{3, 5, 5}, Case{7, 7, 3}}) {
    C2fConfig c = plain_config();
    c.radius = k.radius;
    c.census_width = k.cw;
    c.census_height = k.ch;
    c.levels = 3;
    C2fMatcher scalar(c, 0, 48, size, 0, 0, C2fKernels::scalar);
    C2fMatcher fast(c, 0, 48, size, 0, 0, C2fKernels::best);
    if (!fast.uses_avx2()) GTEST_SKIP() << "no AVX2 on this CPU";
    cv::Mat a, b;
    scalar.compute(left, right, a);
    fast.compute(left, right, b);
    EXPECT_EQ(cv::countNonZero(a != b), 0) << "radius " << k.radius << ", census " << k.cw
                                           << " x " << k.ch;
    EXPECT_EQ(cv::countNonZero(scalar.confidence() != fast.confidence()), 0);
    EXPECT_EQ(scalar.valid_by_level(), fast.valid_by_level());
    // Something to compare: the finest level keeps over a quarter of the pixels (radius
    // 1 the fewest: 31 %).
    EXPECT_GT(scalar.valid_by_level()[0], static_cast<size_t>(size.area() / 4))
        << "radius " << k.radius << ", census " << k.cw << " x " << k.ch;
  }
}

// Census compares pixels with their neighbours only: a right image at 0.6 x + 20 DN
// matches the same. Rounding 0.6 x merges neighbouring grey values, which flips the bits
// of equal pairs; a contrasty texture keeps that rare. BM and SGBM (SAD on the
// x-Sobel pre-filter, BT on it) are reported beside.
TEST(C2fMatcher, GainAndOffsetOfOneImageLeaveDisparitiesAlmostUnchanged) {
  const cv::Size size(320, 200);
  const cv::Mat wide = texture(cv::Size(size.width + 60, size.height), 31, 1.5);
  const cv::Mat left = wide(cv::Rect(0, 0, size.width, size.height)).clone();
  // A slanted plane: disparity 20 at the top to 36 at the bottom (per row, integer).
  cv::Mat right(size, CV_8UC1);
  for (int y = 0; y < size.height; ++y) {
    const int d = 20 + 16 * y / size.height;
    wide(cv::Rect(d, y, size.width, 1)).copyTo(right.row(y));
  }
  cv::Mat dim;
  right.convertTo(dim, CV_8U, 0.6, 20);

  auto changed_share = [&](const cv::Mat& a, const cv::Mat& b, int invalid) {
    int valid = 0, changed = 0;
    for (int y = 0; y < a.rows; ++y)
      for (int x = 48; x < a.cols; ++x) {
        const int u = a.at<std::int16_t>(y, x), v = b.at<std::int16_t>(y, x);
        if (u <= invalid && v <= invalid) continue;
        ++valid;
        changed += (u <= invalid) != (v <= invalid) || std::abs(u - v) > 4;  // > 1/4 px
      }
    return valid ? static_cast<double>(changed) / valid : 1.0;
  };
  C2fMatcher c2f(plain_config(), 0, 64, size, 0, 0);
  cv::Mat a, b;
  c2f.compute(left, right, a);
  c2f.compute(left, dim, b);
  const double c2f_change = changed_share(a, b, -16);
  EXPECT_LT(c2f_change, 0.01);

  auto bm = cv::StereoBM::create(64, 11);
  auto sgbm = cv::StereoSGBM::create(0, 64, 5, 8 * 25, 32 * 25, 1, 31, 10, 0, 0,
                                     cv::StereoSGBM::MODE_HH);
  cv::Mat ba, bb, sa, sb;
  bm->compute(left, right, ba);
  bm->compute(left, dim, bb);
  sgbm->compute(left, right, sa);
  sgbm->compute(left, dim, sb);
  std::printf("right at 0.6 x + 20: pixels whose disparity changed by > 1/4 px or validity: "
              "c2f %.2f %%, BM %.2f %%, SGBM %.2f %%\n",
              100 * c2f_change, 100 * changed_share(ba, bb, -16),
              100 * changed_share(sa, sb, -16));
}

TEST(C2fMatcher, RejectsARangeOrPyramidThatCannotWork) {
  EXPECT_THROW(C2fMatcher(plain_config(), 10, 11, cv::Size(100, 100), 0, 0), Error);
  C2fConfig deep = plain_config();
  deep.levels = 6;
  EXPECT_THROW(C2fMatcher(deep, 0, 32, cv::Size(100, 100), 0, 0), Error);
}

}  // namespace
}  // namespace hazmap

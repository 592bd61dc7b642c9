// SupportCheck against a per-pixel reference of the rule, and on a drawn scene: ground,
// a rock standing on it and a blob floating above far ground.

#include "hazmap/stereo/support_check.hpp"

#include <random>

#include <gtest/gtest.h>

#include "hazmap/core/error.hpp"

namespace hazmap {
namespace {

constexpr int kInvalid = -16;  // min_disparity 0: OpenCV marks invalid pixels with -16

/// The rule, pixel by pixel: samples at k * spacing rows below (k = 1..8, within
/// `rows`), farther when d16 < floor(d16_pixel (1 - tol) - 16 margin).
cv::Mat reference_mask(const cv::Mat& d, int rows, double tol, double margin_px) {
  cv::Mat removed(d.size(), CV_8U, cv::Scalar(0));
  const int spacing = std::max(1, rows / SupportCheck::kSamples);
  for (int v = 0; v < d.rows; ++v)
    for (int u = 0; u < d.cols; ++u) {
      const int dv = d.at<int16_t>(v, u);
      if (dv <= 0) continue;
      const double thr = std::floor(dv * (1.0 - tol) - 16.0 * margin_px);
      int valid = 0, far = 0;
      for (int k = 1; k <= SupportCheck::kSamples; ++k) {
        const int r = v + k * spacing;
        if (r >= d.rows || k * spacing > rows) break;
        const int db = d.at<int16_t>(r, u);
        if (db <= 0) continue;
        ++valid;
        far += db < thr;
      }
      removed.at<uint8_t>(v, u) = valid >= SupportCheck::kMinValidBelow && 2 * far > valid;
    }
  return removed;
}

TEST(SupportCheck, EqualsThePerPixelRuleOnRandomDisparities) {
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> disp(-16, 160 * 16), hole(0, 9);
  cv::Mat d(120, 90, CV_16S);
  for (int v = 0; v < d.rows; ++v)
    for (int u = 0; u < d.cols; ++u) d.at<int16_t>(v, u) = int16_t(hole(rng) == 0 ? kInvalid : disp(rng));
  for (int rows : {8, 20, 32, 200}) {
    const cv::Mat want = reference_mask(d, rows, 0.25, 1.0);
    cv::Mat got = d.clone();
    SupportCheck check(rows, 0.25, 1.0);
    const std::size_t removed = check.apply(got, 0);
    EXPECT_EQ(removed, std::size_t(cv::countNonZero(want))) << rows;
    EXPECT_GT(removed, 0u) << rows;
    for (int v = 0; v < d.rows; ++v)
      for (int u = 0; u < d.cols; ++u)
        ASSERT_EQ(got.at<int16_t>(v, u), want.at<uint8_t>(v, u) ? kInvalid : d.at<int16_t>(v, u))
            << rows << " at " << v << "," << u;
  }
}

TEST(SupportCheck, RemovesAFloatingBlobAndKeepsGroundAndARockStandingOnIt) {
  // Ground: disparity grows downwards (d = 0.3 v px, none above row 40). A rock: a face
  // of constant disparity 60 px over rows 170-199 at columns 20-39, standing where the
  // ground's disparity reaches 60 px (row 200). A blob: 150 px over rows 50-57, columns
  // 60-71, above ground seen at 15-20 px.
  cv::Mat d(260, 100, CV_16S, cv::Scalar(kInvalid));
  for (int v = 40; v < d.rows; ++v)
    for (int u = 0; u < d.cols; ++u) d.at<int16_t>(v, u) = int16_t(std::lround(16 * 0.3 * v));
  for (int v = 170; v < 200; ++v)
    for (int u = 20; u < 40; ++u) d.at<int16_t>(v, u) = 60 * 16;
  for (int v = 50; v < 58; ++v)
    for (int u = 60; u < 72; ++u) d.at<int16_t>(v, u) = 150 * 16;
  cv::Mat out = d.clone();
  SupportCheck check(32, 0.25, 1.0);
  EXPECT_EQ(check.apply(out, 0), 8u * 12u);
  for (int v = 0; v < d.rows; ++v)
    for (int u = 0; u < d.cols; ++u) {
      const bool blob = v >= 50 && v < 58 && u >= 60 && u < 72;
      EXPECT_EQ(out.at<int16_t>(v, u), blob ? kInvalid : d.at<int16_t>(v, u)) << v << "," << u;
    }
  // Off: nothing changes.
  cv::Mat untouched = d.clone();
  SupportCheck off(0, 0.25, 1.0);
  EXPECT_FALSE(off.enabled());
  EXPECT_EQ(off.apply(untouched, 0), 0u);
  EXPECT_EQ(cv::countNonZero(untouched != d), 0);
  EXPECT_THROW(SupportCheck(-1, 0.25, 1.0), Error);
  EXPECT_THROW(SupportCheck(8, 1.0, 1.0), Error);
}

}  // namespace
}  // namespace hazmap

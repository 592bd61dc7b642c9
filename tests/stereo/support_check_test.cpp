// SupportCheck against a per-pixel reference of the rule, and on a drawn scene: ground,
// a rock standing on it and a blob floating above far ground.

#include "hazmap/stereo/support_check.hpp"

#include <random>

#include <opencv2/core/utility.hpp>

#include <gtest/gtest.h>

#include "hazmap/core/error.hpp"

namespace hazmap {
namespace {

constexpr int kInvalid = -16;  // min_disparity 0: OpenCV marks invalid pixels with -16

/// The rule, pixel by pixel: samples at k * spacing rows below (k = 1..8, within
/// `rows`), farther when d16 < floor(d16_pixel (1 - tol) - 16 margin); valid: d16 > 0 and
/// d16 > invalid_below.
cv::Mat reference_mask(const cv::Mat& d, int rows, double tol, double margin_px,
                       int invalid_below = 0) {
  const int valid_above = std::max(invalid_below, 0);
  cv::Mat removed(d.size(), CV_8U, cv::Scalar(0));
  const int spacing = std::max(1, rows / SupportCheck::kSamples);
  for (int v = 0; v < d.rows; ++v)
    for (int u = 0; u < d.cols; ++u) {
      const int dv = d.at<int16_t>(v, u);
      if (dv <= valid_above) continue;
      const double thr = std::floor(dv * (1.0 - tol) - 16.0 * margin_px);
      int valid = 0, far = 0;
      for (int k = 1; k <= SupportCheck::kSamples; ++k) {
        const int r = v + k * spacing;
        if (r >= d.rows || k * spacing > rows) break;
        const int db = d.at<int16_t>(r, u);
        if (db <= valid_above) continue;
        ++valid;
        far += db < thr;
      }
      removed.at<uint8_t>(v, u) = valid >= SupportCheck::kMinValidBelow && 2 * far > valid;
    }
  return removed;
}

TEST(SupportCheck, EqualsThePerPixelRuleOnRandomDisparities) {
  // Row strips run in parallel and decide from the unchanged image: the result must be the
  // rule's, on every thread count, for spans shorter than the 8 samples (spacing 1), spans
  // past the image's bottom, another invalid marker, and one checker reused across sizes.
  std::mt19937 rng(7);
  std::uniform_int_distribution<int> disp(-16, 160 * 16), hole(0, 9);
  const int threads = cv::getNumThreads();
  for (const cv::Size size : {cv::Size(90, 120), cv::Size(37, 61)}) {
    cv::Mat d(size, CV_16S);
    for (int v = 0; v < d.rows; ++v)
      for (int u = 0; u < d.cols; ++u)
        d.at<int16_t>(v, u) = int16_t(hole(rng) == 0 ? kInvalid : disp(rng));
    for (const int invalid_below : {0, 48})
      for (const int t : {1, threads}) {
        cv::setNumThreads(t);
        for (int rows : {3, 5, 8, 20, 32, 200}) {
          const cv::Mat want = reference_mask(d, rows, 0.25, 1.0, invalid_below);
          cv::Mat got = d.clone();
          SupportCheck check(rows, 0.25, 1.0);
          const std::size_t removed = check.apply(got, invalid_below);
          EXPECT_EQ(removed, std::size_t(cv::countNonZero(want))) << rows;
          // Fewer than kMinValidBelow samples fit (short spans, the small image's 200 rows):
          // never evidence. Otherwise the random image has unsupported pixels.
          if (rows >= SupportCheck::kMinValidBelow && d.rows >= 100) {
            EXPECT_GT(removed, 0u) << rows;
          }
          const auto marked = int16_t(invalid_below - 16);
          for (int v = 0; v < d.rows; ++v)
            for (int u = 0; u < d.cols; ++u)
              ASSERT_EQ(got.at<int16_t>(v, u), want.at<uint8_t>(v, u) ? marked : d.at<int16_t>(v, u))
                  << rows << " at " << v << "," << u << ", " << t << " threads";
        }
      }
  }
  cv::setNumThreads(threads);
  // One checker over two sizes in turn keeps giving the rule's result.
  cv::Mat big(120, 90, CV_16S), small(61, 37, CV_16S);
  for (cv::Mat* m : {&big, &small})
    for (int v = 0; v < m->rows; ++v)
      for (int u = 0; u < m->cols; ++u)
        m->at<int16_t>(v, u) = int16_t(hole(rng) == 0 ? kInvalid : disp(rng));
  SupportCheck reused(20, 0.25, 1.0);
  for (const cv::Mat* m : {&big, &small, &big}) {
    cv::Mat got = m->clone();
    reused.apply(got, 0);
    const cv::Mat want = reference_mask(*m, 20, 0.25, 1.0);
    cv::Mat expected = m->clone();
    expected.setTo(kInvalid, want);
    EXPECT_EQ(cv::countNonZero(got != expected), 0);
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

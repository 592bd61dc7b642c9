// SpeckleFilter against OpenCV's single-threaded cv::filterSpeckles (a flood fill, an
// independent implementation), pixel for pixel, and on drawn cases whose answer is known.

#include "hazmap/stereo/speckle_filter.hpp"

#include <random>

#include <opencv2/calib3d.hpp>
#include <opencv2/core/utility.hpp>

#include <gtest/gtest.h>

#include "hazmap/core/error.hpp"

namespace hazmap {
namespace {

constexpr int kInvalid = -16;

/// Patches of random level (so components of every size occur), small noise inside a
/// patch, and holes.
cv::Mat random_disparity(cv::Size size, std::mt19937& rng, int patch, int noise, int hole_in) {
  std::uniform_int_distribution<int> level(0, 40), jitter(-noise, noise), hole(0, hole_in - 1);
  cv::Mat levels((size.height + patch - 1) / patch + 1, (size.width + patch - 1) / patch + 1,
                 CV_32S);
  for (int y = 0; y < levels.rows; ++y)
    for (int x = 0; x < levels.cols; ++x) levels.at<int>(y, x) = 16 * level(rng);
  cv::Mat d(size, CV_16S);
  for (int y = 0; y < d.rows; ++y)
    for (int x = 0; x < d.cols; ++x)
      d.at<std::int16_t>(y, x) = static_cast<std::int16_t>(
          hole(rng) == 0 ? kInvalid : levels.at<int>(y / patch, x / patch) + jitter(rng));
  return d;
}

void expect_equal(const cv::Mat& a, const cv::Mat& b, const std::string& what) {
  ASSERT_EQ(a.size(), b.size()) << what;
  EXPECT_EQ(cv::countNonZero(a != b), 0) << what;
}

TEST(SpeckleFilter, EqualsOpenCvsFilterOnRandomDisparities) {
  // Strips are labelled in parallel and joined at their borders: the result must be
  // OpenCV's on every thread count (strips 2 x threads), for images narrower, shorter
  // and taller than the strips, one filter reused across sizes.
  std::mt19937 rng(11);
  const int threads = cv::getNumThreads();
  SpeckleFilter filter;
  int cleared_total = 0;
  for (const cv::Size size : {cv::Size(1, 1), cv::Size(57, 1), cv::Size(1, 43), cv::Size(7, 3),
                              cv::Size(200, 150), cv::Size(641, 480), cv::Size(31, 300)})
    for (const int patch : {1, 3, 12})
      for (const int t : {1, 3, threads}) {
        cv::setNumThreads(t);
        const cv::Mat d = random_disparity(size, rng, patch, 20, 7);
        for (const int max_size : {0, 1, 25, 400})
          for (const int max_diff : {0, 16, 32}) {
            cv::Mat expected = d.clone(), got = d.clone(), buffer;
            cv::filterSpeckles(expected, kInvalid, max_size, max_diff, buffer);
            filter.apply(got, kInvalid, max_size, max_diff);
            expect_equal(got, expected,
                         cv::format("%dx%d patch %d threads %d size %d diff %d", size.width,
                                    size.height, patch, t, max_size, max_diff));
            cleared_total += cv::countNonZero(got != d);
          }
      }
  cv::setNumThreads(threads);
  EXPECT_GT(cleared_total, 100000);  // the cases do clear pixels
}

TEST(SpeckleFilter, ComponentsWindingThroughEveryStripAreCountedWhole) {
  // A serpentine one pixel wide crosses every strip border many times: its size is the
  // sum over all strips. It survives a window one below its size and is cleared at it.
  const int threads = cv::getNumThreads();
  cv::Mat d(61, 40, CV_16S, cv::Scalar(kInvalid));
  int pixels = 0;
  for (int x = 0; x < d.cols; x += 2) {
    for (int y = 0; y < d.rows; ++y, ++pixels) d.at<std::int16_t>(y, x) = 160;
    const int turn = (x / 2) % 2 == 0 ? d.rows - 1 : 0;
    if (x + 1 < d.cols) {
      d.at<std::int16_t>(turn, x + 1) = 160;
      ++pixels;
    }
  }
  SpeckleFilter filter;
  for (const int t : {1, 2, 8}) {
    cv::setNumThreads(t);
    cv::Mat kept = d.clone(), cleared = d.clone();
    filter.apply(kept, kInvalid, pixels - 1, 0);
    filter.apply(cleared, kInvalid, pixels, 0);
    EXPECT_EQ(cv::countNonZero(kept != d), 0) << "threads " << t;
    EXPECT_EQ(cv::countNonZero(cleared == kInvalid), d.rows * d.cols) << "threads " << t;
  }
  cv::setNumThreads(threads);
}

TEST(SpeckleFilter, JoinsFourNeighboursWithinTheRangeOnly) {
  // Two 2 x 2 blocks touching at a corner are two components of 4 (no diagonal join);
  // a step of exactly max_diff joins, one more does not.
  cv::Mat d(6, 6, CV_16S, cv::Scalar(kInvalid));
  d(cv::Rect(0, 0, 2, 2)).setTo(100);
  d(cv::Rect(2, 2, 2, 2)).setTo(100);
  SpeckleFilter filter;
  cv::Mat a = d.clone();
  filter.apply(a, kInvalid, 4, 1000);
  EXPECT_EQ(cv::countNonZero(a == kInvalid), 36);
  cv::Mat b = d.clone();
  filter.apply(b, kInvalid, 3, 1000);
  EXPECT_EQ(cv::countNonZero(b != d), 0);

  cv::Mat row(1, 8, CV_16S, cv::Scalar(0));
  row(cv::Rect(4, 0, 4, 1)).setTo(32);  // a step of 32 between columns 3 and 4
  cv::Mat joined = row.clone(), split = row.clone();
  filter.apply(joined, kInvalid, 4, 32);
  filter.apply(split, kInvalid, 4, 31);
  EXPECT_EQ(cv::countNonZero(joined != row), 0);
  EXPECT_EQ(cv::countNonZero(split == kInvalid), 8);
}

TEST(SpeckleFilter, RejectsAnotherImageType) {
  SpeckleFilter filter;
  cv::Mat d(4, 4, CV_32F, cv::Scalar(1));
  EXPECT_THROW(filter.apply(d, kInvalid, 10, 16), Error);
}

}  // namespace
}  // namespace hazmap

// stereo.min_texture_snr: the image-noise estimate against known Gaussian noise, and the
// gate on a pair of halves, one noise only and one textured.

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include <opencv2/imgproc.hpp>

#include "hazmap/stereo/texture_gate.hpp"

namespace hazmap {
namespace {

/// Smooth shading (a plane plus a gentle quadratic) plus Gaussian noise sigma, rounded.
cv::Mat shaded(int rows, int cols, double sigma, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> noise(0.0, sigma);
  cv::Mat img(rows, cols, CV_8UC1);
  for (int y = 0; y < rows; ++y)
    for (int x = 0; x < cols; ++x) {
      const double base = 90 + 0.1 * x + 0.05 * y + 1e-4 * (x - cols / 2.0) * (x - cols / 2.0);
      img.at<std::uint8_t>(y, x) = cv::saturate_cast<std::uint8_t>(base + noise(rng));
    }
  return img;
}

TEST(TextureGate, NoiseEstimateMatchesTheGaussianNoiseAdded) {
  for (double sigma : {1.0, 2.0, 4.0}) {
    // Rounding adds a uniform +-0.5 DN: variance 1/12.
    const double want = std::sqrt(sigma * sigma + 1.0 / 12.0);
    EXPECT_NEAR(image_noise_dn(shaded(240, 320, sigma, 3)), want, 0.05 * want) << sigma;
  }
  EXPECT_LT(image_noise_dn(shaded(240, 320, 0.0, 3)), 0.5);  // shading alone: rounding only
  EXPECT_EQ(image_noise_dn(cv::Mat(2, 2, CV_8UC1, cv::Scalar(7))), 0.0);
}

TEST(TextureGate, DropsNoiseOnlyWindowsAndKeepsTexturedOnes) {
  // Left half: flat grey plus noise 3 DN. Right half: a random texture of 8 px blobs with
  // a 20 DN spread, plus the same noise.
  const int rows = 120, cols = 240;
  cv::Mat img = shaded(rows, cols, 3.0, 5);
  std::mt19937 rng(9);
  std::normal_distribution<double> blob(0.0, 20.0);
  for (int y = 0; y < rows; y += 8)
    for (int x = cols / 2; x < cols; x += 8) {
      const double v = blob(rng);
      for (int yy = y; yy < std::min(y + 8, rows); ++yy)
        for (int xx = x; xx < std::min(x + 8, cols); ++xx)
          img.at<std::uint8_t>(yy, xx) = cv::saturate_cast<std::uint8_t>(img.at<std::uint8_t>(yy, xx) + v);
    }
  const short valid = 16 * 20, invalid = 0;
  cv::Mat disparity(rows, cols, CV_16SC1, cv::Scalar(valid));

  TextureGate off(0.0, cv::Size(9, 7));
  EXPECT_FALSE(off.enabled());
  off.apply(img, disparity, invalid);
  EXPECT_EQ(cv::countNonZero(disparity != valid), 0);

  TextureGate gate(1.0, cv::Size(9, 7));
  const double noise = gate.apply(img, disparity, invalid);
  EXPECT_GT(noise, 3.0);  // the textured half raises the estimate, within reason
  EXPECT_LT(noise, 6.0);
  // Away from the seam and the edges (a window reaching across the seam sees texture).
  const cv::Rect flat(8, 8, cols / 2 - 16, rows - 16), textured(cols / 2 + 8, 8, cols / 2 - 16, rows - 16);
  EXPECT_EQ(cv::countNonZero(disparity(flat) != invalid), 0);
  // Where two neighbouring blobs happen to be alike a window can be flat: most are not.
  EXPECT_GE(cv::countNonZero(disparity(textured) == valid), int(0.85 * textured.area()));
  // Every decision against the window's variance computed directly (cv::meanStdDev).
  const double limit = noise * noise * 2.0;
  int checked = 0;
  for (int y = 3; y < rows - 3; ++y)
    for (int x = 4; x < cols - 4; ++x) {
      cv::Scalar mean, stddev;
      cv::meanStdDev(img(cv::Rect(x - 4, y - 3, 9, 7)), mean, stddev);
      const double variance = stddev[0] * stddev[0];
      if (std::abs(variance - limit) < 1e-6 * limit) continue;  // at the threshold: rounding
      EXPECT_EQ(disparity.at<short>(y, x) == valid, variance >= limit) << x << ", " << y;
      ++checked;
    }
  EXPECT_GT(checked, (rows - 6) * (cols - 8) - 10);
  // Already invalid stays so.
  cv::Mat again = disparity.clone();
  gate.apply(img, again, invalid);
  EXPECT_EQ(cv::countNonZero(again != disparity), 0);
}

TEST(TextureGate, RejectsMismatchedInput) {
  TextureGate gate(1.0, cv::Size(5, 5));
  cv::Mat img(10, 10, CV_8UC1, cv::Scalar(0)), disparity(10, 12, CV_16SC1, cv::Scalar(0));
  EXPECT_ANY_THROW(gate.apply(img, disparity, 0));
}

}  // namespace
}  // namespace hazmap

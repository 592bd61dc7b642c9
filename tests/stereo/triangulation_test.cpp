// Real OpenCV matching on real PNG files: a textured fronto-parallel plane at a known
// sub-pixel disparity must come back at its depth.

#include <algorithm>

#include <opencv2/imgcodecs.hpp>
#include <opencv2/imgproc.hpp>

#include <gtest/gtest.h>

#include "hazmap/camera/rectifier.hpp"
#include "hazmap/io/images.hpp"
#include "hazmap/stereo/disparity.hpp"
#include "hazmap/stereo/point_cloud_builder.hpp"
#include "stereo/stereo_scene.hpp"
#include "test_support.hpp"

namespace hazmap {
namespace {

/// Smooth random texture (blurred noise at two scales), 8 bit.
cv::Mat texture(int w, int h, int seed) {
  cv::Mat out;
  testing::smooth_texture(w, h, seed).convertTo(out, CV_8U);
  return out;
}

StereoCalibration rectified_calibration(int w, int h, double f, double b) {
  StereoCalibration c;
  c.image_width = w;
  c.image_height = h;
  c.left.K << f, 0, (w - 1) / 2.0, 0, f, (h - 1) / 2.0, 0, 0, 1;
  c.right.K = c.left.K;
  c.T = Eigen::Vector3d(-b, 0, 0);
  c.rectified = true;
  return c;
}

class FrontoParallelPlane : public ::testing::TestWithParam<double> {};

TEST_P(FrontoParallelPlane, DepthRecoveredWithinOnePercent) {
  const double disparity_px = GetParam();
  const int w = 320, h = 240;
  const double f = 300.0, b = 0.05;
  testing::TempDir dir;
  // The right camera sees the plane's texture shifted left by the disparity.
  const cv::Mat left = texture(w + 64, h, 7);
  cv::Mat right;
  const cv::Mat shift = (cv::Mat_<double>(2, 3) << 1, 0, -disparity_px, 0, 1, 0);
  cv::warpAffine(left, right, shift, left.size(), cv::INTER_CUBIC, cv::BORDER_REFLECT);
  cv::imwrite((dir / "l.png").string(), left(cv::Rect(0, 0, w, h)));
  cv::imwrite((dir / "r.png").string(), right(cv::Rect(0, 0, w, h)));

  StereoConfig stereo;
  stereo.num_disparities = 64;
  stereo.block_size = 11;
  stereo.z_min_m = 0.01;
  stereo.z_max_m = 100;
  SensorConfig sensor;
  const StereoCalibration calib = rectified_calibration(w, h, f, b);
  Rectifier rectifier(calib, 0.0);
  DisparityMatcher matcher(stereo);
  PointCloudBuilder builder(stereo, sensor, rectifier.geometry(), rectifier.R1(), Pose3d::Identity(),
                            rectifier.valid_roi());
  cv::Mat l8, r8, rl, rr, disp;
  to_gray8(read_image(dir / "l.png"), l8);
  to_gray8(read_image(dir / "r.png"), r8);
  rectifier.rectify(l8, r8, rl, rr);
  matcher.compute(rl, rr, disp);
  PointCloud cloud;
  builder.build(disp, matcher.invalid_below(), Pose3d::Identity(), cloud);
  ASSERT_GT(cloud.size(), static_cast<size_t>(w * h / 2));  // dense on a textured plane
  std::vector<float> z;
  for (const auto& m : cloud) z.push_back(m.p_W.z());
  std::nth_element(z.begin(), z.begin() + z.size() / 2, z.end());
  const double expected = f * b / disparity_px;
  EXPECT_NEAR(z[z.size() / 2], expected, 0.01 * expected);
  // The covariance attached is the axis model at that depth.
  const auto& m = cloud[cloud.size() / 2];
  const double zd = m.p_W.z();
  EXPECT_NEAR(m.cov_zz, std::pow(zd * zd * 0.25 / (f * b), 2), 1e-6 * m.cov_zz);
}

INSTANTIATE_TEST_SUITE_P(Disparities, FrontoParallelPlane, ::testing::Values(6.5, 12.25, 30.75));

}  // namespace
}  // namespace hazmap

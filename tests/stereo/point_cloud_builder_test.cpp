// PointCloudBuilder against a slow per-pixel reference: which pixels give points
// (valid disparity, stride grid, valid rectified regions of both cameras, stereo.roi,
// depth gate) and the exact point and covariance each one gives.

#include <cmath>
#include <set>
#include <string>
#include <utility>

#include <gtest/gtest.h>

#include "hazmap/stereo/point_cloud_builder.hpp"

namespace hazmap {
namespace {

const StereoGeometry kGeometry{100.0, 0.1, 31.5, 23.5};  // f B = 10 px m

/// Disparity varying by column: Z = 10 / d from 10 px (1 m) up to 10 + 0.25 * 63 px,
/// with an invalid pixel every 7th.
cv::Mat synthetic_disparity() {
  cv::Mat d(48, 64, CV_16S);
  for (int v = 0; v < d.rows; ++v)
    for (int u = 0; u < d.cols; ++u)
      d.at<int16_t>(v, u) = (u + 3 * v) % 7 == 0 ? -16 : static_cast<int16_t>(160 + 4 * u);
  return d;
}

TEST(PointCloudBuilder, KeepsExactlyThePixelsItShould) {
  StereoConfig stereo;
  stereo.stride = 3;
  stereo.roi_px = {10, 5, 45, 20};
  stereo.z_min_m = 0.5;
  stereo.z_max_m = 0.8;  // d in [12.5, 20] px: u in [10, 40]
  SensorConfig sensor;
  const cv::Rect left_valid(2, 0, 50, 40), right_valid(8, 3, 56, 45);
  const PointCloudBuilder builder(stereo, sensor, kGeometry, Eigen::Matrix3d::Identity(),
                                  Pose3d::Identity(), left_valid, right_valid);
  const cv::Mat disparity = synthetic_disparity();
  PointCloud cloud;
  std::vector<cv::Point> pixels;
  builder.build(disparity, 0, Pose3d::Identity(), cloud, pixels);

  // Reference: every pixel tested on its own.
  const cv::Rect region = left_valid & cv::Rect(10, 5, 45, 20);
  EXPECT_EQ(builder.region(), region);
  std::set<std::pair<int, int>> expected;
  for (int v = 0; v < disparity.rows; ++v)
    for (int u = 0; u < disparity.cols; ++u) {
      const int d16 = disparity.at<int16_t>(v, u);
      const double d = d16 / 16.0, z = 10.0 / d;
      const bool on_grid = (u - region.x) % 3 == 0 && (v - region.y) % 3 == 0;
      if (region.contains({u, v}) && on_grid && d16 > 0 && z >= 0.5 && z <= 0.8 &&
          u - d >= right_valid.x && u - d <= right_valid.br().x - 1 && v >= right_valid.y &&
          v < right_valid.br().y)
        expected.insert({u, v});
    }
  ASSERT_GT(expected.size(), 20u);
  std::set<std::pair<int, int>> got;
  for (const auto& p : pixels) got.insert({p.x, p.y});
  EXPECT_EQ(got, expected);
  ASSERT_EQ(cloud.size(), pixels.size());
  // The overload without pixels gives the same cloud.
  PointCloud again;
  builder.build(disparity, 0, Pose3d::Identity(), again);
  ASSERT_EQ(again.size(), cloud.size());
  for (size_t i = 0; i < cloud.size(); ++i) EXPECT_EQ(again[i].p_W, cloud[i].p_W);
}

TEST(PointCloudBuilder, InvalidBelowFollowsMinDisparity) {
  StereoConfig stereo;
  stereo.z_min_m = 0.01;
  stereo.z_max_m = 100;
  SensorConfig sensor;
  const PointCloudBuilder builder(stereo, sensor, kGeometry, Eigen::Matrix3d::Identity(),
                                  Pose3d::Identity(), cv::Rect(0, 0, 64, 48));
  cv::Mat d(48, 64, CV_16S, cv::Scalar(16 * 4));  // exactly min_disparity 4: invalid
  d.at<int16_t>(10, 20) = 16 * 4 + 1;             // just above: valid
  PointCloud cloud;
  builder.build(d, 16 * 4, Pose3d::Identity(), cloud);
  ASSERT_EQ(cloud.size(), 1u);
  EXPECT_NEAR(cloud[0].p_W.z(), 10.0 / (4 + 1.0 / 16), 1e-6);
}

TEST(PointCloudBuilder, PointAndRayCovarianceGoThroughR1AndTheBodyPose) {
  StereoConfig stereo;
  stereo.z_min_m = 0.01;
  stereo.z_max_m = 100;
  for (const std::string model : {"axis", "ray"}) {
    SensorConfig sensor;
    sensor.model = *enum_value<SensorModel>(model);
    const Eigen::Matrix3d R1 =
        Eigen::AngleAxisd(0.05, Eigen::Vector3d(0.3, -1, 0.2).normalized()).toRotationMatrix();
    Pose3d T_B_C = Pose3d::Identity();
    T_B_C.linear() = rotation_from_rpy(-M_PI / 2, 0.3, -M_PI / 2);
    T_B_C.translation() = Eigen::Vector3d(0.1, 0.02, 0.3);
    Pose3d T_W_B = Pose3d::Identity();
    T_W_B.linear() = rotation_from_rpy(0.02, -0.01, 1.2);
    T_W_B.translation() = Eigen::Vector3d(3, -2, 0.5);
    const PointCloudBuilder builder(stereo, sensor, kGeometry, R1, T_B_C, cv::Rect(0, 0, 64, 48));
    cv::Mat d(48, 64, CV_16S, cv::Scalar(-16));
    d.at<int16_t>(30, 12) = 16 * 20 + 5;
    PointCloud cloud;
    builder.build(d, 0, T_W_B, cloud);
    ASSERT_EQ(cloud.size(), 1u);
    const double disp = 20 + 5.0 / 16;
    const Eigen::Matrix3d R_W_Cr = T_W_B.linear() * T_B_C.linear() * R1.transpose();
    const Eigen::Vector3d p_W = T_W_B * (T_B_C * (R1.transpose() * triangulate(kGeometry, 12, 30, disp)));
    EXPECT_LT((cloud[0].p_W.cast<double>() - p_W).norm(), 1e-6);
    // The reference rotates the camera-frame covariance with two matrix products (the
    // builder uses the closed form a I + (b - a) c c^T for the axis model).
    const Eigen::Matrix3d cov_C = model == "axis"
                                      ? covariance_axis(kGeometry, triangulate(kGeometry, 12, 30, disp).z(), 0.5, 0.25)
                                      : covariance_ray(kGeometry, 12, 30, disp, 0.5, 0.25);
    const Eigen::Matrix3d cov = R_W_Cr * cov_C * R_W_Cr.transpose();
    const float got[6] = {cloud[0].cov_xx, cloud[0].cov_xy, cloud[0].cov_xz,
                          cloud[0].cov_yy, cloud[0].cov_yz, cloud[0].cov_zz};
    const double want[6] = {cov(0, 0), cov(0, 1), cov(0, 2), cov(1, 1), cov(1, 2), cov(2, 2)};
    for (int i = 0; i < 6; ++i) EXPECT_NEAR(got[i], want[i], 1e-6 * cov.norm()) << i;
  }
}

// SPEC 3.3: a point more than max_below_ground below the body's wheel plane (z_B = 0) is
// dropped and counted. A camera 0.3 m up looking forward and down, the body tilted and
// displaced in W: each pixel's z_B computed here from p_W through T_W_B^-1.
TEST(PointCloudBuilder, DropsAndCountsPointsFarBelowTheWheelPlane) {
  StereoConfig stereo;
  stereo.z_min_m = 0.01;
  stereo.z_max_m = 100;
  stereo.max_below_ground_m = 0.5;
  stereo.max_depression_slope_deg = 90.0;  // this test: the depth limit alone
  SensorConfig sensor;
  Pose3d T_B_C = Pose3d::Identity();
  T_B_C.linear() = rotation_from_rpy(-M_PI / 2 - 0.4, 0.0, -M_PI / 2);  // forward, 23 deg down
  T_B_C.translation() = Eigen::Vector3d(0.1, 0.0, 0.3);
  Pose3d T_W_B = Pose3d::Identity();
  T_W_B.linear() = rotation_from_rpy(0.1, -0.15, 0.7);
  T_W_B.translation() = Eigen::Vector3d(2, 1, -0.4);
  const Eigen::Matrix3d R1 =
      Eigen::AngleAxisd(0.03, Eigen::Vector3d(1, 0.5, 0.2).normalized()).toRotationMatrix();
  // Disparities from 1 to 16 px by column: Z from 10 m to 0.6 m, so that rays below the
  // horizon end far below the ground at small disparities.
  cv::Mat d(48, 64, CV_16S);
  for (int v = 0; v < d.rows; ++v)
    for (int u = 0; u < d.cols; ++u) d.at<int16_t>(v, u) = static_cast<int16_t>(16 + 4 * u);
  std::size_t expected_dropped = 0, expected_kept = 0;
  for (int v = 0; v < d.rows; ++v)
    for (int u = 0; u < d.cols; ++u) {
      const Eigen::Vector3d p_W =
          T_W_B * (T_B_C * (R1.transpose() * triangulate(kGeometry, u, v, d.at<int16_t>(v, u) / 16.0)));
      const double z_B = (T_W_B.inverse() * p_W).z();
      ASSERT_GT(std::abs(z_B + 0.5), 1e-9);  // no pixel on the threshold
      (z_B < -0.5 ? expected_dropped : expected_kept)++;
    }
  ASSERT_GT(expected_dropped, 200u);
  ASSERT_GT(expected_kept, 200u);
  const PointCloudBuilder builder(stereo, sensor, kGeometry, R1, T_B_C, cv::Rect(0, 0, 64, 48));
  PointCloud cloud;
  EXPECT_EQ(builder.build(d, 0, T_W_B, cloud), expected_dropped);
  ASSERT_EQ(cloud.size(), expected_kept);
  const Pose3d T_B_W = T_W_B.inverse();
  for (const Measurement& m : cloud) EXPECT_GE((T_B_W * m.p_W.cast<double>()).z(), -0.5 - 1e-5);
  // <= 0 disables the check: every pixel gives a point, none counted.
  stereo.max_below_ground_m = 0.0;
  const PointCloudBuilder open(stereo, sensor, kGeometry, R1, T_B_C, cv::Rect(0, 0, 64, 48));
  EXPECT_EQ(open.build(d, 0, T_W_B, cloud), 0u);
  EXPECT_EQ(cloud.size(), expected_kept + expected_dropped);
}

// Ours: below the tolerance, a point seen along a ray descending steeper than
// max_depression_slope_deg is dropped too (it could only be seen down a steeper wall).
// Each pixel's z_B and descent angle computed here from the body-frame camera centre
// and point.
TEST(PointCloudBuilder, DropsPointsBelowTheToleranceAlongSteepRays) {
  StereoConfig stereo;
  stereo.z_min_m = 0.01;
  stereo.z_max_m = 100;
  stereo.max_below_ground_m = 0.5;
  stereo.below_ground_tolerance_m = 0.05;
  stereo.max_depression_slope_deg = 45.0;
  SensorConfig sensor;
  Pose3d T_B_C = Pose3d::Identity();
  T_B_C.linear() = rotation_from_rpy(-M_PI / 2 - 0.6, 0.0, -M_PI / 2);  // 34 deg down
  T_B_C.translation() = Eigen::Vector3d(0.0, 0.02, 0.15);
  Pose3d T_W_B = Pose3d::Identity();
  T_W_B.linear() = rotation_from_rpy(0.05, -0.1, 0.3);
  T_W_B.translation() = Eigen::Vector3d(1, -2, 0.2);
  const Eigen::Matrix3d R1 = Eigen::Matrix3d::Identity();
  // Disparities 2 ... 65 px by column: Z from 5 m to 0.15 m.
  cv::Mat d(48, 64, CV_16S);
  for (int v = 0; v < d.rows; ++v)
    for (int u = 0; u < d.cols; ++u) d.at<int16_t>(v, u) = static_cast<int16_t>(32 + 16 * u);
  std::size_t steep = 0, deep = 0, kept = 0;
  const Eigen::Vector3d camera_B = T_B_C.translation();
  for (int v = 0; v < d.rows; ++v)
    for (int u = 0; u < d.cols; ++u) {
      const Eigen::Vector3d p_B = T_B_C * triangulate(kGeometry, u, v, d.at<int16_t>(v, u) / 16.0);
      const Eigen::Vector3d ray = p_B - camera_B;
      const double descent_deg = std::atan2(-ray.z(), ray.head<2>().norm()) * 180.0 / M_PI;
      ASSERT_GT(std::abs(descent_deg - 45.0), 1e-6);
      ASSERT_GT(std::abs(p_B.z() + 0.05), 1e-9);
      if (p_B.z() < -0.5) ++deep;
      else if (p_B.z() < -0.05 && descent_deg > 45.0) ++steep;
      else ++kept;
    }
  ASSERT_GT(steep, 100u);
  ASSERT_GT(kept, 100u);
  const PointCloudBuilder builder(stereo, sensor, kGeometry, R1, T_B_C, cv::Rect(0, 0, 64, 48));
  PointCloud cloud;
  EXPECT_EQ(builder.build(d, 0, T_W_B, cloud), steep + deep);
  EXPECT_EQ(cloud.size(), kept);
  // 90 deg turns the ray rule off (the depth limit stays).
  stereo.max_depression_slope_deg = 90.0;
  const PointCloudBuilder depth_only(stereo, sensor, kGeometry, R1, T_B_C, cv::Rect(0, 0, 64, 48));
  EXPECT_EQ(depth_only.build(d, 0, T_W_B, cloud), deep);
  EXPECT_EQ(cloud.size(), kept + steep);
}

// Issue 24: a stride near INT_MAX with a region starting at x >= 1 overflowed `u += step`
// (undefined; a segfault in Release). Each row and column of the region now gives its first
// pixel only.
TEST(PointCloudBuilder, HugeStrideTakesTheRegionsFirstPixelWithoutOverflow) {
  StereoConfig stereo;
  stereo.stride = 2147483647;
  stereo.roi_px = {1, 2, 60, 40};
  stereo.z_min_m = 0.1;
  stereo.z_max_m = 100.0;
  SensorConfig sensor;
  const PointCloudBuilder builder(stereo, sensor, kGeometry, Eigen::Matrix3d::Identity(),
                                  Pose3d::Identity(), cv::Rect(0, 0, 64, 48));
  cv::Mat disparity(48, 64, CV_16S, cv::Scalar(160));
  PointCloud cloud;
  std::vector<cv::Point> pixels;
  builder.build(disparity, 0, Pose3d::Identity(), cloud, pixels);
  ASSERT_EQ(pixels.size(), 1u);
  EXPECT_EQ(pixels[0], cv::Point(1, 2));
  EXPECT_EQ(cloud.size(), 1u);
}

}  // namespace
}  // namespace hazmap

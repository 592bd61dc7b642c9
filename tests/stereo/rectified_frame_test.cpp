// R1 (SPEC 1, 3): a raw, distorted stereo pair whose right camera is turned against the
// left one. Rectification rotates the left camera too (by R1), so points triangulated
// in the rectified frame C' must be rotated back (p_C = R1^T p_C') before the camera's
// body pose applies. Level ground must come out level; without R1 it tilts.

#include <cstdio>

#include <gtest/gtest.h>

#include <opencv2/calib3d.hpp>
#include <opencv2/imgcodecs.hpp>

#include "hazmap/camera/rectifier.hpp"
#include "hazmap/io/images.hpp"
#include "hazmap/stereo/stereo_front_end.hpp"
#include "stereo/stereo_scene.hpp"
#include "test_support.hpp"

namespace hazmap {
namespace {

constexpr double kLevelToleranceDeg = 0.2;
constexpr double kHeightToleranceM = 0.003;  // ground 0.7..3 m away: 0.1..0.4 % of range

Eigen::Matrix3d rot(double deg, const Eigen::Vector3d& axis) {
  return Eigen::AngleAxisd(deg * M_PI / 180.0, axis).toRotationMatrix();
}

/// Distorted pair, right camera turned by ~4.5 deg and offset in y and z; left camera
/// 0.5 m above ground, looking along body x, pitched down 35 deg.
StereoCalibration turned_rig() {
  StereoCalibration c;
  c.image_width = 640;
  c.image_height = 480;
  c.left.K << 450, 0, 325.3, 0, 451, 236.8, 0, 0, 1;
  c.right.K << 455, 0, 316.1, 0, 454, 243.2, 0, 0, 1;
  c.left.D = {-0.20, 0.05, 0.0010, -0.0005, 0.0};
  c.right.D = {-0.18, 0.04, -0.0008, 0.0006, 0.0};
  c.R = rot(1.0, Eigen::Vector3d::UnitZ()) * rot(-4.0, Eigen::Vector3d::UnitY()) *
        rot(2.0, Eigen::Vector3d::UnitX());
  c.T = Eigen::Vector3d(-0.10, 0.003, -0.002);
  c.T_B_C.linear() = rot(35.0, Eigen::Vector3d::UnitY()) * rotation_from_rpy(-M_PI / 2, 0, -M_PI / 2);
  c.T_B_C.translation() = Eigen::Vector3d(0, 0, 0.5);
  return c;
}

Pose3d body_pose() {
  Pose3d T_W_B = Pose3d::Identity();
  T_W_B.linear() = rot(30.0, Eigen::Vector3d::UnitZ());
  T_W_B.translation() = Eigen::Vector3d(1.0, 2.0, 0.0);
  return T_W_B;
}

/// Pose of the right camera in W: x_right = R x_left + T.
Pose3d right_camera_pose(const StereoCalibration& c, const Pose3d& T_W_CL) {
  Pose3d T_CR_CL = Pose3d::Identity();
  T_CR_CL.linear() = c.R;
  T_CR_CL.translation() = c.T;
  return T_W_CL * T_CR_CL.inverse();
}

TEST(RectifiedFrame, RectifiedPointsShareARowAndTriangulateExactly) {
  // Pure geometry, no matching: project ground points into both raw images, map them
  // through the rectifier: same row, disparity f B / z' with z' the depth in C'.
  const StereoCalibration c = turned_rig();
  const Rectifier rectifier(c, 0.0);
  const Pose3d T_W_CL = body_pose() * c.T_B_C;
  const Pose3d T_W_CR = right_camera_pose(c, T_W_CL);
  std::vector<cv::Point3f> ground_CL, ground_CR;
  for (double x = 0.8; x < 3.0; x += 0.3)
    for (double y = -0.6; y <= 0.6; y += 0.3) {
      const Eigen::Vector3d p_W = body_pose() * Eigen::Vector3d(x, y, 0.0);
      const Eigen::Vector3d l = T_W_CL.inverse() * p_W, r = T_W_CR.inverse() * p_W;
      ground_CL.emplace_back(static_cast<float>(l.x()), static_cast<float>(l.y()), static_cast<float>(l.z()));
      ground_CR.emplace_back(static_cast<float>(r.x()), static_cast<float>(r.y()), static_cast<float>(r.z()));
    }
  auto project = [](const CameraIntrinsics& cam, const std::vector<cv::Point3f>& p) {
    cv::Mat K(3, 3, CV_64F);
    for (int i = 0; i < 9; ++i) K.at<double>(i / 3, i % 3) = cam.K(i / 3, i % 3);
    std::vector<cv::Point2f> px;
    cv::projectPoints(p, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), K, cam.D, px);
    return px;
  };
  std::vector<cv::Point2f> left, right;
  rectifier.rectify_points(StereoSide::left, project(c.left, ground_CL), left);
  rectifier.rectify_points(StereoSide::right, project(c.right, ground_CR), right);
  const StereoGeometry& g = rectifier.geometry();
  EXPECT_NEAR(g.baseline_m, c.T.norm(), 1e-9);
  for (size_t i = 0; i < left.size(); ++i) {
    EXPECT_NEAR(left[i].y, right[i].y, 1e-3) << i;
    const Eigen::Vector3d p_Cr =
        rectifier.R1() * Eigen::Vector3d(ground_CL[i].x, ground_CL[i].y, ground_CL[i].z);
    const double d = left[i].x - right[i].x;
    EXPECT_NEAR(d, g.focal_px * g.baseline_m / p_Cr.z(), 2e-3) << i;
    // Triangulating the rectified pixel gives back the point in C' (1e-5 relative,
    // float pixels), hence p_C = R1^T p_C'.
    const Eigen::Vector3d back = triangulate(g, left[i].x, left[i].y, d);
    EXPECT_LT((back - p_Cr).norm(), 1e-5 * p_Cr.norm() + 2e-6) << i;
  }
}

TEST(RectifiedFrame, LevelGroundStaysLevelOnlyWithR1) {
  const StereoCalibration c = turned_rig();
  const Pose3d T_W_B = body_pose();
  const Pose3d T_W_CL = T_W_B * c.T_B_C;
  testing::TexturedPlane ground;  // z = 0 in W, textured at ~1 texel per pixel at 1.5 m
  ground.texture = testing::smooth_texture(3000, 3000, 5);
  ground.texels_per_m = 250.0;
  ground.origin_W = T_W_B * Eigen::Vector3d(2.0, 0.0, 0.0);
  const cv::Size size(c.image_width, c.image_height);
  testing::TempDir dir;
  cv::imwrite((dir / "l.png").string(), testing::render_plane(ground, c.left, T_W_CL, size));
  cv::imwrite((dir / "r.png").string(),
              testing::render_plane(ground, c.right, right_camera_pose(c, T_W_CL), size));

  StereoConfig stereo;
  stereo.num_disparities = 128;  // the image bottom sees ground at z = 0.5 m: d = 92 px
  stereo.z_min_m = 0.1;
  stereo.z_max_m = 2.5;
  SensorConfig sensor;
  StereoFrontEnd front_end(stereo, sensor, c);
  front_end.process(read_image(dir / "l.png"), read_image(dir / "r.png"), T_W_B);
  const double r1_angle_deg =
      Eigen::AngleAxisd(front_end.rectifier().R1()).angle() * 180.0 / M_PI;
  ASSERT_GT(r1_angle_deg, 1.0) << "the rig must need a real rectifying rotation";
  ASSERT_GT(front_end.cloud().size(), 100000u);

  const Eigen::Vector3d up = Eigen::Vector3d::UnitZ();
  const testing::PlaneFit fit =
      testing::fit_dominant_plane(testing::positions(front_end.cloud()), 0.01, up);
  EXPECT_GT(fit.points, front_end.cloud().size() * 95 / 100);
  EXPECT_LT(testing::angle_deg(fit.normal, up), kLevelToleranceDeg);
  EXPECT_NEAR(fit.offset, 0.0, kHeightToleranceM);

  // The same disparities with R1 forgotten: the ground tilts by about R1's angle.
  const Rectifier& rect = front_end.rectifier();
  const PointCloudBuilder without_r1(stereo, sensor, rect.geometry(), Eigen::Matrix3d::Identity(),
                                     c.T_B_C, rect.valid_roi());
  PointCloud wrong;
  without_r1.build(front_end.disparity_x16(), front_end.matcher().invalid_below(), T_W_B, wrong);
  const testing::PlaneFit tilted = testing::fit_dominant_plane(testing::positions(wrong), 0.01, up);
  EXPECT_GT(testing::angle_deg(tilted.normal, up), 5 * kLevelToleranceDeg);
  std::printf("[ measured ] R1 %.2f deg; with R1: tilt %.3f deg, height %+.2f mm, std %.2f mm; "
              "without R1: tilt %.2f deg\n",
              r1_angle_deg, testing::angle_deg(fit.normal, up), 1e3 * fit.offset,
              1e3 * fit.residual_std, testing::angle_deg(tilted.normal, up));
}

}  // namespace
}  // namespace hazmap

// Exact planes through the real front end: ray-cast textured planes at known depth and
// tilt, seen by an ideal rectified pair (written as PNGs and read back), must come back
// from StereoBM / StereoSGBM + triangulation as the same plane.

#include <cstdio>

#include <gtest/gtest.h>

#include <opencv2/imgcodecs.hpp>

#include "hazmap/io/images.hpp"
#include "hazmap/stereo/stereo_front_end.hpp"
#include "stereo/stereo_scene.hpp"
#include "test_support.hpp"

namespace hazmap {
namespace {

constexpr double kDepthTolerance = 0.005;  // relative, along the optical axis
constexpr double kTiltToleranceDeg = 0.2;

struct PlaneCase {
  const char* matcher;
  double depth_m;
  double tilt_deg;
  bool about_x;  ///< tilt about the camera x axis (ground-like) or y axis (wall-like)
};

void PrintTo(const PlaneCase& c, std::ostream* os) {
  *os << c.matcher << " Z " << c.depth_m << " m tilt " << c.tilt_deg << " deg about "
      << (c.about_x ? "x" : "y");
}

class ExactPlane : public ::testing::TestWithParam<PlaneCase> {};

TEST_P(ExactPlane, DepthAndTiltRecovered) {
  const PlaneCase pc = GetParam();
  const int w = 640, h = 480;
  const double f = 500.0, b = 0.10;
  StereoCalibration calib;
  calib.image_width = w;
  calib.image_height = h;
  calib.left.K << f, 0, (w - 1) / 2.0, 0, f, (h - 1) / 2.0, 0, 0, 1;
  calib.right.K = calib.left.K;
  calib.T = Eigen::Vector3d(-b, 0, 0);
  calib.rectified = true;

  // World = left camera frame. The plane passes through (0, 0, Z) and is turned by the
  // tilt so that its far side is the top (about x) or the right (about y) of the view.
  const double tilt = pc.tilt_deg * M_PI / 180.0;
  const Eigen::Matrix3d rot =
      Eigen::AngleAxisd(pc.about_x ? tilt : -tilt,
                        pc.about_x ? Eigen::Vector3d::UnitX() : Eigen::Vector3d::UnitY())
          .toRotationMatrix();
  testing::TexturedPlane plane;
  plane.origin_W = Eigen::Vector3d(0, 0, pc.depth_m);
  plane.e1_W = rot * Eigen::Vector3d::UnitX();
  plane.e2_W = rot * Eigen::Vector3d::UnitY();
  plane.texture = testing::smooth_texture(3000, 3000, 11);
  plane.texels_per_m = 0.8 * f / pc.depth_m;  // texels a little larger than pixels

  Pose3d T_W_CR = Pose3d::Identity();
  T_W_CR.translation() = Eigen::Vector3d(b, 0, 0);
  testing::TempDir dir;
  cv::imwrite((dir / "l.png").string(),
              testing::render_plane(plane, calib.left, Pose3d::Identity(), {w, h}));
  cv::imwrite((dir / "r.png").string(), testing::render_plane(plane, calib.right, T_W_CR, {w, h}));

  StereoConfig stereo;
  stereo.matcher = *enum_value<StereoMatcher>(pc.matcher);
  stereo.num_disparities = 96;
  stereo.z_min_m = 0.1;
  stereo.z_max_m = 20.0;
  SensorConfig sensor;
  StereoFrontEnd front_end(stereo, sensor, calib);
  front_end.process(read_image(dir / "l.png"), read_image(dir / "r.png"), Pose3d::Identity());
  const PointCloud& cloud = front_end.cloud();
  ASSERT_GT(cloud.size(), static_cast<size_t>(w * h / 2)) << "a textured plane matches densely";

  const testing::PlaneFit fit =
      testing::fit_dominant_plane(testing::positions(cloud), 0.01 * pc.depth_m, -Eigen::Vector3d::UnitZ());
  EXPECT_GT(fit.points, cloud.size() * 95 / 100) << "nearly every point on the plane";
  const Eigen::Vector3d true_normal = -(rot * Eigen::Vector3d::UnitZ());
  const double axis_depth = fit.offset / fit.normal.z();
  EXPECT_NEAR(axis_depth, pc.depth_m, kDepthTolerance * pc.depth_m);
  EXPECT_LT(testing::angle_deg(fit.normal, true_normal), kTiltToleranceDeg);
  std::printf("[ measured ] depth error %+.3f %%, tilt error %.3f deg, %zu points, plane std %.2f mm\n",
              100.0 * (axis_depth - pc.depth_m) / pc.depth_m,
              testing::angle_deg(fit.normal, true_normal), cloud.size(), 1e3 * fit.residual_std);
}

INSTANTIATE_TEST_SUITE_P(
    Planes, ExactPlane,
    ::testing::Values(PlaneCase{"bm", 1.0, 0.0, true}, PlaneCase{"bm", 1.5, 30.0, true},
                      PlaneCase{"bm", 2.0, 50.0, true}, PlaneCase{"bm", 1.5, 35.0, false},
                      PlaneCase{"sgbm", 1.0, 0.0, true}, PlaneCase{"sgbm", 1.5, 30.0, true},
                      PlaneCase{"sgbm", 2.0, 50.0, true}, PlaneCase{"sgbm", 1.5, 35.0, false}));

}  // namespace
}  // namespace hazmap

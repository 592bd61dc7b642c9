// The simulator's lens model agrees with OpenCV's: forward distortion with
// cv::projectPoints, and the round trip through cv::undistortPoints, so that images
// rendered through it are undone by the project's rectifier.

#include "hazmap/sim/camera_model.hpp"

#include <random>
#include <vector>

#include <gtest/gtest.h>
#include <opencv2/calib3d.hpp>

#include "hazmap/sim/simulate.hpp"
#include "hazmap/sim/terrain.hpp"

namespace hazmap::sim {
namespace {

constexpr double kPixelTolerancePx = 1e-9;     // forward model vs OpenCV
constexpr double kNormalisedTolerance = 1e-12; // our Newton inverse
// cv::undistortPoints iterates a fixed point; with 200 iterations it reaches ~1e-10.
constexpr double kOpenCvInverseTolerance = 1e-9;

PinholeCamera distorted_camera() {
  PinholeCamera camera = make_cadre_rig(1.0).camera;
  camera.distortion = RigErrors::typical_distortion();
  return camera;
}

cv::Mat K_of(const PinholeCamera& c) {
  return (cv::Mat_<double>(3, 3) << c.fx_px, 0, c.cx_px, 0, c.fy_px, c.cy_px, 0, 0, 1);
}

cv::Mat D_of(const PinholeCamera& c) {
  return (cv::Mat_<double>(1, 5) << c.distortion[0], c.distortion[1], c.distortion[2],
          c.distortion[3], c.distortion[4]);
}

// Normalised points covering the whole 1600 x 1300 image and a little beyond.
std::vector<Eigen::Vector2d> sample_points() {
  std::mt19937_64 rng(5);
  std::vector<Eigen::Vector2d> points;
  for (int i = 0; i < 500; ++i) {
    points.emplace_back(2.5 * unit_double(rng()) - 1.25, 2.0 * unit_double(rng()) - 1.0);
  }
  return points;
}

TEST(CameraModel, ProjectionMatchesOpenCv) {
  const PinholeCamera camera = distorted_camera();
  std::vector<cv::Point3d> object;
  for (const Eigen::Vector2d& xy : sample_points()) object.emplace_back(xy.x(), xy.y(), 1.0);
  std::vector<cv::Point2d> image;
  cv::projectPoints(object, cv::Vec3d(0, 0, 0), cv::Vec3d(0, 0, 0), K_of(camera), D_of(camera), image);
  for (std::size_t i = 0; i < object.size(); ++i) {
    const Eigen::Vector2d uv =
        camera.project(Eigen::Vector3d(object[i].x, object[i].y, 1.0) * 2.5);  // any depth
    EXPECT_NEAR(uv.x(), image[i].x, kPixelTolerancePx);
    EXPECT_NEAR(uv.y(), image[i].y, kPixelTolerancePx);
  }
}

TEST(CameraModel, RoundTripThroughUndistortPoints) {
  const PinholeCamera camera = distorted_camera();
  std::vector<cv::Point2d> pixels;
  std::vector<Eigen::Vector2d> normalised;
  for (const Eigen::Vector2d& xy : sample_points()) {
    const Eigen::Vector2d uv = camera.project(Eigen::Vector3d(xy.x(), xy.y(), 1.0));
    pixels.emplace_back(uv.x(), uv.y());
    normalised.push_back(xy);
    // Our inverse: the ray through that pixel is the one we projected.
    const Eigen::Vector3d ray = camera.ray_C(uv.x(), uv.y());
    EXPECT_NEAR(ray.x(), xy.x(), kNormalisedTolerance);
    EXPECT_NEAR(ray.y(), xy.y(), kNormalisedTolerance);
    EXPECT_EQ(ray.z(), 1.0);
  }
  // OpenCV's inverse gives the same normalised coordinates.
  std::vector<cv::Point2d> undistorted;
  cv::undistortPoints(pixels, undistorted, K_of(camera), D_of(camera), cv::noArray(), cv::noArray(),
                      cv::TermCriteria(cv::TermCriteria::COUNT | cv::TermCriteria::EPS, 200, 1e-15));
  for (std::size_t i = 0; i < pixels.size(); ++i) {
    EXPECT_NEAR(undistorted[i].x, normalised[i].x(), kOpenCvInverseTolerance);
    EXPECT_NEAR(undistorted[i].y, normalised[i].y(), kOpenCvInverseTolerance);
  }
}

TEST(CameraModel, DistortionIsVisibleAtTheEdgesOnly) {
  const PinholeCamera camera = distorted_camera();
  PinholeCamera ideal = camera;
  ideal.distortion = {0, 0, 0, 0, 0};
  EXPECT_FALSE(ideal.distorted());
  // At the principal point only the tangential terms act: well below a pixel.
  const Eigen::Vector3d centre(0.0, 0.0, 1.0);
  EXPECT_LT((camera.project(centre) - ideal.project(centre)).norm(), 1e-9);
  // At the left image edge (x = -1.19, y = 0) the barrel distortion pulls points in by
  // 1 - (1 + k1 x^2 + k2 x^4) = 8.9 % of their radius (71 px at full size); p2 adds
  // 3 p2 x^2 along x, p1 adds p1 x^2 along y.
  const Eigen::Vector3d edge = ideal.ray_C(0.0, camera.cy_px);
  const double x = edge.x();
  const double radial_px = x * camera.fx_px * (-0.08 * x * x + 0.012 * x * x * x * x);
  const Eigen::Vector2d shift = camera.project(edge) - ideal.project(edge);
  EXPECT_NEAR(shift.x(), radial_px + camera.fx_px * 3.0 * -3e-4 * x * x, 1e-9);
  EXPECT_NEAR(shift.y(), camera.fy_px * 4e-4 * x * x, 1e-9);
  EXPECT_NEAR(radial_px, 71.0, 1.0);
}

}  // namespace
}  // namespace hazmap::sim

// fit_ground_plane against the plane the points were drawn from: noisy inliers with
// depth-like covariances, plus outliers a real frame has (a box on the ground, a wall).

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "hazmap/stereo/ground_plane_fit.hpp"

namespace hazmap {
namespace {

constexpr double kDeg = 180.0 / 3.14159265358979323846;

Measurement point(const Eigen::Vector3d& p, double sigma) {
  Measurement m{};
  m.p_W = p.cast<float>();
  m.cov_xx = m.cov_yy = m.cov_zz = static_cast<float>(sigma * sigma);
  m.cov_xy = m.cov_xz = m.cov_yz = 0.0f;
  return m;
}

/// Points on n.(p - p0) = 0 over [0, 3] x [-1.5, 1.5] (then lifted onto the plane), with
/// noise growing with x as stereo depth noise does; a 40 x 40 x 20 cm box and a wall
/// hold `outlier_share` of the points.
PointCloud scene(const Eigen::Vector3d& n, const Eigen::Vector3d& p0, double outlier_share,
                 std::uint32_t seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> ux(0.2, 3.0), uy(-1.5, 1.5), u01(0.0, 1.0);
  std::normal_distribution<double> gauss(0.0, 1.0);
  PointCloud cloud;
  for (int i = 0; i < 20000; ++i) {
    const double x = ux(rng), y = uy(rng);
    // On the plane: solve n.(p - p0) = 0 for z.
    auto plane_z = [&](double px, double py) {
      return p0.z() - (n.x() * (px - p0.x()) + n.y() * (py - p0.y())) / n.z();
    };
    const Eigen::Vector3d on_plane(x, y, plane_z(x, y));
    if (u01(rng) < outlier_share) {
      if (u01(rng) < 0.5) {  // box top, 20 cm above the plane
        const double bx = 1.0 + 0.4 * u01(rng), by = 0.4 * u01(rng);
        cloud.push_back(point(Eigen::Vector3d(bx, by, plane_z(bx, by) + 0.2), 0.003));
      } else {  // a wall at x = 3.2
        cloud.push_back(point(Eigen::Vector3d(3.2, y, plane_z(3.2, y) + 2.0 * u01(rng)), 0.02));
      }
      continue;
    }
    const double sigma = 0.002 * x * x;  // Z^2-like growth, 2 mm at 1 m
    cloud.push_back(point(on_plane + n * sigma * gauss(rng), sigma));
  }
  return cloud;
}

TEST(GroundPlaneFit, RecoversATiltedPlaneAmongOutliers) {
  const Eigen::Vector3d n = Eigen::Vector3d(0.12, -0.05, 1.0).normalized();  // 7.4 deg
  const Eigen::Vector3d p0(1.0, 0.0, -0.3);
  const PointCloud cloud = scene(n, p0, 0.35, 7);
  const Eigen::Vector3d camera(0.0, 0.0, 0.5);
  const GroundPlane g = fit_ground_plane(cloud, camera);
  ASSERT_TRUE(g.found);
  // Normal within 0.2 deg, oriented towards the camera above the plane.
  EXPECT_LT(std::acos(std::min(1.0, g.normal.dot(n))) * kDeg, 0.2);
  EXPECT_NEAR(g.tilt_deg(Eigen::Vector3d::UnitZ()), std::acos(n.z()) * kDeg, 0.2);
  // The camera's height above the plane, against the analytic distance: 1 mm.
  EXPECT_NEAR(g.height_of(camera), n.dot(camera - p0), 1e-3);
  EXPECT_NEAR(g.height_of(p0), 0.0, 1e-3);
  // 65 % of the points are on the plane; the box top (3 mm sigma, 20 cm up) is not.
  EXPECT_NEAR(g.inlier_share, 0.65, 0.05);
  EXPECT_EQ(g.points_used, 20000u);
}

TEST(GroundPlaneFit, IsDeterministicAndOrientedByTheViewpoint) {
  const Eigen::Vector3d n = Eigen::Vector3d::UnitZ();
  const PointCloud cloud = scene(n, Eigen::Vector3d::Zero(), 0.2, 11);
  const GroundPlane a = fit_ground_plane(cloud, Eigen::Vector3d(0, 0, 1));
  const GroundPlane b = fit_ground_plane(cloud, Eigen::Vector3d(0, 0, 1));
  EXPECT_EQ(a.normal, b.normal);
  EXPECT_EQ(a.point, b.point);
  EXPECT_GT(a.normal.z(), 0.99);
  // Seen from below, the normal points down and the tilt reads 180 deg.
  const GroundPlane below = fit_ground_plane(cloud, Eigen::Vector3d(0, 0, -1));
  EXPECT_LT(below.normal.z(), -0.99);
  EXPECT_GT(below.tilt_deg(Eigen::Vector3d::UnitZ()), 179.0);
}

TEST(GroundPlaneFit, NotFoundWithoutAPlane) {
  EXPECT_FALSE(fit_ground_plane({}, Eigen::Vector3d::Zero()).found);
  PointCloud two = {point({0, 0, 0}, 0.01), point({1, 0, 0}, 0.01)};
  EXPECT_FALSE(fit_ground_plane(two, Eigen::Vector3d::UnitZ()).found);
  // 50 points exactly on a plane: too few to call it the ground.
  PointCloud few;
  for (int i = 0; i < 50; ++i) few.push_back(point({0.1 * i, 0.37 * (i % 7), 0.0}, 0.01));
  EXPECT_FALSE(fit_ground_plane(few, Eigen::Vector3d::UnitZ()).found);
  for (int i = 50; i < 250; ++i) few.push_back(point({0.1 * i, 0.37 * (i % 7), 0.0}, 0.01));
  EXPECT_TRUE(fit_ground_plane(few, Eigen::Vector3d::UnitZ()).found);
  // A ball of points: no plane holds 20 % of them within 3 sigma.
  std::mt19937 rng(3);
  std::normal_distribution<double> gauss(0.0, 1.0);
  PointCloud ball;
  for (int i = 0; i < 5000; ++i)
    ball.push_back(point(Eigen::Vector3d(gauss(rng), gauss(rng), gauss(rng)), 0.001));
  EXPECT_FALSE(fit_ground_plane(ball, Eigen::Vector3d(0, 0, 10)).found);
}

}  // namespace
}  // namespace hazmap

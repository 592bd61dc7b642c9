#include "hazmap/stereo/sensor_model.hpp"

#include <random>

#include <gtest/gtest.h>

namespace hazmap {
namespace {

const StereoGeometry kCadre{671.0, 0.05, 799.5, 649.5};

TEST(SensorModel, TriangulationInvertsProjection) {
  // Project known points, triangulate from (u, v, d) and compare (relative 1e-12).
  for (const Eigen::Vector3d& p : {Eigen::Vector3d(0.1, 0.05, 0.5), Eigen::Vector3d(-1.0, 0.3, 4.0),
                                  Eigen::Vector3d(0.0, -0.2, 9.0)}) {
    const double u = kCadre.focal_px * p.x() / p.z() + kCadre.cx_px;
    const double v = kCadre.focal_px * p.y() / p.z() + kCadre.cy_px;
    const double d = kCadre.focal_px * kCadre.baseline_m / p.z();
    EXPECT_LT((triangulate(kCadre, u, v, d) - p).norm(), 1e-12 * p.norm());
  }
}

TEST(SensorModel, AxisCovarianceIsTheSpecFormula) {
  const double z = 2.0, p = 0.5, m = 0.25;
  const Eigen::Matrix3d cov = covariance_axis(kCadre, z, p, m);
  const double lateral = p * z / kCadre.focal_px;
  const double depth = z * z * m / (kCadre.focal_px * kCadre.baseline_m);
  EXPECT_DOUBLE_EQ(cov(0, 0), lateral * lateral);
  EXPECT_DOUBLE_EQ(cov(1, 1), lateral * lateral);
  EXPECT_DOUBLE_EQ(cov(2, 2), depth * depth);
  EXPECT_EQ(cov(0, 1), 0.0);
  EXPECT_EQ(cov(0, 2), 0.0);
  EXPECT_EQ(cov(1, 2), 0.0);
}

TEST(SensorModel, RayCovarianceMatchesMonteCarloPropagation) {
  // 1e5 samples of pixel and disparity noise pushed through triangulation; the
  // first-order covariance agrees within 5 % per significant entry.
  const double u = 1200, v = 1100, d = 40, p = 0.5, m = 0.25;
  const Eigen::Matrix3d analytic = covariance_ray(kCadre, u, v, d, p, m);
  std::mt19937_64 rng(42);
  std::normal_distribution<double> np(0.0, p), nm(0.0, m);
  const int n = 100000;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  std::vector<Eigen::Vector3d> samples(n);
  for (auto& s : samples) {
    s = triangulate(kCadre, u + np(rng), v + np(rng), d + nm(rng));
    mean += s;
  }
  mean /= n;
  Eigen::Matrix3d mc = Eigen::Matrix3d::Zero();
  for (const auto& s : samples) mc += (s - mean) * (s - mean).transpose();
  mc /= n;
  for (int r = 0; r < 3; ++r)
    for (int c = 0; c < 3; ++c)
      EXPECT_NEAR(mc(r, c), analytic(r, c), 0.05 * std::sqrt(analytic(r, r) * analytic(c, c)))
          << r << "," << c;
}

}  // namespace
}  // namespace hazmap

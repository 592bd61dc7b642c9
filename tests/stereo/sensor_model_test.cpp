#include "hazmap/stereo/sensor_model.hpp"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

#include "hazmap/core/types.hpp"
#include "hazmap/map/map_points.hpp"

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

namespace hazmap {
namespace {

Measurement with_covariance(const Eigen::Matrix3d& cov) {
  Measurement m{};
  m.cov_xx = static_cast<float>(cov(0, 0));
  m.cov_xy = static_cast<float>(cov(0, 1));
  m.cov_xz = static_cast<float>(cov(0, 2));
  m.cov_yy = static_cast<float>(cov(1, 1));
  m.cov_yz = static_cast<float>(cov(1, 2));
  m.cov_zz = static_cast<float>(cov(2, 2));
  return m;
}

TEST(CcmWeight, ConstantTraceAndDeterminantOfTheWorldCovariance) {
  // A near CADRE point (ray model, ~0.2 m away) rotated into a world frame: a full,
  // tiny covariance whose determinant (~1e-23 m^6) underflows in float arithmetic.
  const Eigen::Matrix3d R = rotation_from_rpy(0.3, -0.5, 1.1);
  const Eigen::Matrix3d cov = R * covariance_ray(kCadre, 1200, 1100, 160, 0.5, 0.25) * R.transpose();
  const Measurement m = with_covariance(cov);
  // Reference from the float-stored entries, as the map sees them.
  Eigen::Matrix3d stored;
  stored << m.cov_xx, m.cov_xy, m.cov_xz, m.cov_xy, m.cov_yy, m.cov_yz, m.cov_xz, m.cov_yz, m.cov_zz;
  EXPECT_EQ(ccm_weight(CcmWeighting::constant, m), 1.0f);
  EXPECT_NEAR(ccm_weight(CcmWeighting::trace, m), 1.0 / stored.trace(), 1e-6 / stored.trace());
  const double det = stored.determinant();
  ASSERT_GT(det, 0.0);
  ASSERT_LT(det, 1e-20);
  EXPECT_NEAR(ccm_weight(CcmWeighting::det, m), 1.0 / det, 1e-5 / det);
}

TEST(CcmWeight, SingularCovarianceGivesAnInfiniteWeight) {
  // Without pointing error the covariance is rank 1: det weighting is then refused by
  // validate() (tests/io/config_test.cpp); trace stays finite.
  Measurement m = with_covariance(Eigen::Vector3d(0.0, 0.0, 1e-6).asDiagonal());
  EXPECT_EQ(ccm_weight(CcmWeighting::constant, m), 1.0f);
  EXPECT_FLOAT_EQ(ccm_weight(CcmWeighting::trace, m), 1e6f);
  EXPECT_TRUE(std::isinf(ccm_weight(CcmWeighting::det, m)));
}

}  // namespace
}  // namespace hazmap

// MapPoints: the frame's points as the map reads them, against the Measurement records
// they come from.

#include "hazmap/map/map_points.hpp"

#include <algorithm>
#include <cmath>

#include <Eigen/Eigenvalues>
#include <gtest/gtest.h>

namespace hazmap {
namespace {

PointCloud sample_cloud(int n) {
  PointCloud cloud(static_cast<std::size_t>(n));
  for (int i = 0; i < n; ++i) {
    Measurement& m = cloud[static_cast<std::size_t>(i)];
    m.p_W = Eigen::Vector3f(0.01f * float(i), -0.02f * float(i), 0.5f + 0.001f * float(i));
    m.cov_xx = 1e-6f * float(1 + i % 5);
    m.cov_yy = 1e-6f * float(1 + i % 7);
    m.cov_zz = 4e-6f * float(1 + i % 3);
    m.cov_xy = m.cov_xz = m.cov_yz = 0.0f;
  }
  return cloud;
}

// A ray's covariance, long along the ray, seen at any heading: the gate's variance is the
// long axis (an eigen-decomposition by Eigen), whatever the heading.
TEST(MapPoints, LateralVarianceIsTheMajorAxisAtAnyHeading) {
  PointCloud cloud;
  const double along = 4e-4, across = 1e-6;  // 2 cm along the ray, 1 mm across
  for (int i = 0; i < 16; ++i) {
    const double a = i * M_PI / 16;
    Eigen::Matrix2d R;
    R << std::cos(a), -std::sin(a), std::sin(a), std::cos(a);
    const Eigen::Matrix2d S = R * Eigen::Vector2d(along, across).asDiagonal() * R.transpose();
    Measurement m{};
    m.p_W = Eigen::Vector3f(1.0f, 0.0f, 0.0f);
    m.cov_xx = float(S(0, 0));
    m.cov_yy = float(S(1, 1));
    m.cov_xy = float(S(0, 1));
    m.cov_zz = 1e-6f;
    cloud.push_back(m);
  }
  const MapPoints points(cloud, CcmWeighting::constant);
  const PointChunk c = points.chunk(0, 16);
  for (int i = 0; i < 16; ++i) {
    const Measurement& m = cloud[static_cast<std::size_t>(i)];
    Eigen::Matrix2d S;
    S << m.cov_xx, m.cov_xy, m.cov_xy, m.cov_yy;
    const double major = Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(S).eigenvalues()(1);
    EXPECT_NEAR(c.lateral_var[i], major, 1e-6 * major) << i;
    EXPECT_NEAR(c.lateral_var[i], along, 1e-5 * along) << i;
  }
}

TEST(MapPoints, ColumnsAndWeightsMatchTheRecords) {
  const PointCloud cloud = sample_cloud(2500);
  for (CcmWeighting weighting : {CcmWeighting::constant, CcmWeighting::trace, CcmWeighting::det}) {
    const MapPoints points(cloud, weighting);
    ASSERT_EQ(points.size(), 2500);
    for (int begin : {0, 1024, 2048}) {
      const int count = std::min(PointChunk::kCapacity, points.size() - begin);
      const PointChunk c = points.chunk(begin, count);
      ASSERT_EQ(c.size, count);
      // Constant weighting: CCM layers may skip the weights (all 1).
      EXPECT_EQ(c.unit_ccm_weight, weighting == CcmWeighting::constant);
      for (int k = 0; k < count; ++k) {
        const Measurement& m = cloud[static_cast<std::size_t>(begin + k)];
        ASSERT_EQ(c.x[k], m.p_W.x());
        ASSERT_EQ(c.y[k], m.p_W.y());
        ASSERT_EQ(c.z[k], m.p_W.z());
        ASSERT_FLOAT_EQ(c.inv_var_z[k], float(1.0 / double(m.cov_zz)));
        ASSERT_FLOAT_EQ(c.lateral_var[k], std::max(m.cov_xx, m.cov_yy));  // diagonal here
        ASSERT_EQ(c.var_z[k], m.cov_zz);
        // Diagonal covariance: trace and det by hand.
        const double xx = m.cov_xx, yy = m.cov_yy, zz = m.cov_zz;
        const double want = weighting == CcmWeighting::constant ? 1.0
                            : weighting == CcmWeighting::trace  ? 1.0 / (xx + yy + zz)
                                                                : 1.0 / (xx * yy * zz);
        ASSERT_NEAR(c.ccm_weight[k], want, 1e-6 * want);
      }
      // Vector loops may read kPad lanes past the last point.
      volatile float past = c.z[count + PointChunk::kPad - 1];
      (void)past;
    }
  }
}

TEST(MapPoints, ASmallerFrameReusesTheBuffers) {
  MapPoints points(sample_cloud(3000));
  const float* before = points.chunk(0, 1).x;
  points.assign(sample_cloud(10), CcmWeighting::constant);
  EXPECT_EQ(points.size(), 10);
  EXPECT_EQ(points.chunk(0, 1).x, before);
  EXPECT_EQ(points.chunk(9, 1).x[0], 0.01f * 9.0f);
}

}  // namespace
}  // namespace hazmap

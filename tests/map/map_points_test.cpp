// MapPoints: the frame's points as the map reads them, against the Measurement records
// they come from.

#include "hazmap/map/map_points.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <random>

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

// assign() converts four records at a time in vector lanes and the rest one by one: both
// must give, bit for bit, the per-point formulas (the same float operations in the same
// order), at every length around the four-point step and at any offset of the tail.
TEST(MapPoints, FourAtATimeGivesThePerPointFormulasBitForBit) {
  std::mt19937_64 rng(17);
  std::uniform_real_distribution<float> pos(-20.0f, 20.0f), var(1e-7f, 1e-2f), cov(-1.0f, 1.0f);
  for (int n : {0, 1, 2, 3, 4, 5, 7, 8, 9, 1023, 1024, 1025, 2050}) {
    PointCloud cloud(static_cast<std::size_t>(n));
    for (Measurement& m : cloud) {
      m.p_W = Eigen::Vector3f(pos(rng), pos(rng), pos(rng));
      m.cov_xx = var(rng);
      m.cov_yy = var(rng);
      m.cov_zz = var(rng);
      // |xy| < sqrt(xx yy): a positive definite covariance, at any heading.
      m.cov_xy = 0.99f * cov(rng) * std::sqrt(m.cov_xx * m.cov_yy);
      m.cov_xz = cov(rng) * 1e-4f;
      m.cov_yz = cov(rng) * 1e-4f;
    }
    const MapPoints points(cloud, CcmWeighting::constant);
    ASSERT_EQ(points.size(), n);
    const PointChunk c = points.chunk(0, 0);  // the arrays from the first point on
    for (int i = 0; i < n; ++i) {
      const Measurement& m = cloud[static_cast<std::size_t>(i)];
      const float half_sum = 0.5f * (m.cov_xx + m.cov_yy), half_gap = 0.5f * (m.cov_xx - m.cov_yy);
      const float lateral = half_sum + std::sqrt(half_gap * half_gap + m.cov_xy * m.cov_xy);
      const float inv = 1.0f / m.cov_zz;
      ASSERT_EQ(c.x[i], m.p_W.x()) << n << " " << i;
      ASSERT_EQ(c.y[i], m.p_W.y()) << n << " " << i;
      ASSERT_EQ(c.z[i], m.p_W.z()) << n << " " << i;
      ASSERT_EQ(c.var_z[i], m.cov_zz) << n << " " << i;
      ASSERT_EQ(std::memcmp(&c.inv_var_z[i], &inv, sizeof inv), 0) << n << " " << i;
      ASSERT_EQ(std::memcmp(&c.lateral_var[i], &lateral, sizeof lateral), 0) << n << " " << i;
      ASSERT_EQ(c.ccm_weight[i], 1.0f);
      // And the major axis it stands for, from an independent eigen-decomposition.
      Eigen::Matrix2d S;
      S << m.cov_xx, m.cov_xy, m.cov_xy, m.cov_yy;
      const double major = Eigen::SelfAdjointEigenSolver<Eigen::Matrix2d>(S).eigenvalues()(1);
      ASSERT_NEAR(c.lateral_var[i], major, 1e-6 * major) << n << " " << i;
    }
  }
}

// Constant weights are written only where the array does not hold 1 already: across
// frames of every size and weighting (and the direct producer's fill), each frame's
// weights are still its own.
TEST(MapPoints, WeightsAreEachFramesOwnAcrossSizesAndWeightings) {
  MapPoints points;
  const struct {
    int n;
    CcmWeighting weighting;
    bool direct;  ///< begin_fill / end_fill instead of assign
  } frames[] = {{3000, CcmWeighting::constant, false}, {1000, CcmWeighting::constant, false},
                {4000, CcmWeighting::constant, false}, {2000, CcmWeighting::trace, false},
                {3000, CcmWeighting::constant, false}, {2500, CcmWeighting::det, true},
                {2600, CcmWeighting::constant, true},  {5000, CcmWeighting::constant, false}};
  for (const auto& f : frames) {
    const PointCloud cloud = sample_cloud(f.n);
    if (f.direct) {
      const MapPoints::Fill fill = points.begin_fill(static_cast<std::size_t>(f.n));
      for (int i = 0; i < f.n; ++i) {
        const Measurement& m = cloud[static_cast<std::size_t>(i)];
        fill.x[i] = m.p_W.x();
        fill.y[i] = m.p_W.y();
        fill.z[i] = m.p_W.z();
        fill.inv_var_z[i] = 1.0f / m.cov_zz;
        fill.var_z[i] = m.cov_zz;
        fill.lateral_var[i] = m.cov_xx;
        fill.ccm_weight[i] = ccm_weight(f.weighting, m);  // 1 when constant
      }
      points.end_fill(f.n, f.weighting == CcmWeighting::constant);
    } else {
      points.assign(cloud, f.weighting);
    }
    ASSERT_EQ(points.size(), f.n);
    const PointChunk c = points.chunk(0, 0);
    for (int i = 0; i < f.n; ++i)
      ASSERT_EQ(c.ccm_weight[i], ccm_weight(f.weighting, cloud[static_cast<std::size_t>(i)]))
          << f.n << " " << i;
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

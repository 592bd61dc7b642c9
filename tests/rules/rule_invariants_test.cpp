// One invariant suite for the fusing rules: the incremental float32 state equals an
// independent batch computation in double over the same points, whether the points
// arrive one per frame (the SPEC 6 recursion) or many per frame (the per-frame merge).

#include <random>

#include <gtest/gtest.h>

#include "hazmap/rules/ccm.hpp"
#include "hazmap/rules/kalman.hpp"
#include "hazmap/rules/omg.hpp"

namespace hazmap {
namespace {

struct Point {
  double x, y, z, w;  // cell-centric x, y [m]; z [m]; weight (1/vm or CCM weight)
};

std::vector<Point> random_cell_points(std::mt19937_64& rng, int n, double cell_m, double z0,
                                      double spread_m) {
  std::uniform_real_distribution<double> u(-0.5, 0.5), wdist(0.5, 2.0);
  std::normal_distribution<double> nz(0.0, spread_m);
  std::vector<Point> pts(n);
  for (auto& p : pts) {
    p.x = u(rng) * cell_m;
    p.y = u(rng) * cell_m;
    p.z = z0 + 0.3 * p.x - 0.2 * p.y + nz(rng);
    p.w = wdist(rng) / (spread_m * spread_m);
  }
  return pts;
}

/// Feeds points as frames of random sizes through Rule::merge_frame, exactly as a
/// RollingLayer does (x, y in cell units, z relative to the accumulator's reference).
template <class Rule>
typename Rule::Cell fuse(const typename Rule::Config& cfg, const std::vector<Point>& pts,
                         double cell_m, std::mt19937_64& rng, int max_per_frame) {
  typename Rule::Cell cell;
  std::uniform_int_distribution<int> frame_size(1, max_per_frame);
  size_t i = 0;
  while (i < pts.size()) {
    const size_t end = std::min(pts.size(), i + frame_size(rng));
    const float z_ref = Rule::known(cell) ? Rule::reference_z(cell) : static_cast<float>(pts[i].z);
    typename Rule::Sums sums;
    for (; i < end; ++i)
      sums.add(pts[i].w, pts[i].x / cell_m, pts[i].y / cell_m, pts[i].z - double(z_ref));
    Rule::merge_frame(cfg, cell, sums, z_ref, cell_m);
  }
  return cell;
}

/// Batch reference in double: weighted mean and population co-moments.
Moments batch(const std::vector<Point>& pts) {
  Moments m;
  for (const auto& p : pts) {
    m.w += p.w;
    m.mx += p.w * p.x;
    m.my += p.w * p.y;
    m.mz += p.w * p.z;
  }
  m.mx /= m.w, m.my /= m.w, m.mz /= m.w;
  for (const auto& p : pts) {
    const double dx = p.x - m.mx, dy = p.y - m.my, dz = p.z - m.mz;
    m.sxx += p.w * dx * dx, m.syy += p.w * dy * dy, m.szz += p.w * dz * dz;
    m.sxy += p.w * dx * dy, m.sxz += p.w * dx * dz, m.syz += p.w * dy * dz;
  }
  m.count = static_cast<uint32_t>(pts.size());
  return m;
}

double rel(double a, double b) { return std::abs(a - b) / std::max(std::abs(b), 1e-300); }

struct Case {
  double z0;
  double spread;
  double tolerance;  // relative
  int max_per_frame;
};

class RuleInvariants : public ::testing::TestWithParam<Case> {};

TEST_P(RuleInvariants, CcmEqualsBatchMomentsInDouble) {
  const Case c = GetParam();
  std::mt19937_64 rng(17);
  const double r = 0.04;
  CcmRule::Config cfg;
  cfg.max_weight = 1e300;  // no cap
  for (int trial = 0; trial < 20; ++trial) {
    const auto pts = random_cell_points(rng, 300, r, c.z0, c.spread);
    const Moments ref = batch(pts);
    const Moments got = CcmRule::to_moments(fuse<CcmRule>(cfg, pts, r, rng, c.max_per_frame));
    ASSERT_LT(rel(got.w, ref.w), 1e-6);
    ASSERT_LT(std::abs(got.mz - ref.mz), c.tolerance * c.spread) << "mean z";
    ASSERT_LT(std::abs(got.mx - ref.mx), 1e-6 * r);
    ASSERT_LT(rel(got.szz, ref.szz), c.tolerance) << "szz, trial " << trial;
    ASSERT_LT(rel(got.sxx, ref.sxx), c.tolerance);
    ASSERT_LT(rel(got.syy, ref.syy), c.tolerance);
    ASSERT_LT(rel(got.sxz, ref.sxz), c.tolerance);
    ASSERT_LT(rel(got.syz, ref.syz), c.tolerance);
    ASSERT_LT(std::abs(got.sxy - ref.sxy), c.tolerance * std::sqrt(ref.sxx * ref.syy));
    ASSERT_EQ(got.count, ref.count);
  }
}

TEST_P(RuleInvariants, OmgEqualsBatchMixture) {
  // Batch: S = sum w, mu = sum w z / S, var = (sum w (z - mu)^2 + n) / S.
  const Case c = GetParam();
  std::mt19937_64 rng(23);
  OmgRule::Config cfg{1e300, 1.0};
  for (int trial = 0; trial < 20; ++trial) {
    const auto pts = random_cell_points(rng, 300, 0.01, c.z0, c.spread);
    const Moments ref = batch(pts);
    const OmgRule::Cell cell = fuse<OmgRule>(cfg, pts, 0.01, rng, c.max_per_frame);
    const double var_ref = (ref.szz + static_cast<double>(pts.size())) / ref.w;
    ASSERT_LT(rel(cell.weight, ref.w), 1e-6);
    ASSERT_LT(std::abs(OmgRule::mean(cell) - ref.mz), c.tolerance * c.spread);
    ASSERT_LT(rel(cell.variance_m2, var_ref), c.tolerance) << "trial " << trial;
  }
}

TEST_P(RuleInvariants, KalmanEqualsBatchInverseVariance) {
  const Case c = GetParam();
  std::mt19937_64 rng(29);
  KalmanRule::Config cfg{0.0, 0.0};
  for (int trial = 0; trial < 20; ++trial) {
    const auto pts = random_cell_points(rng, 300, 0.01, c.z0, c.spread);
    const Moments ref = batch(pts);  // w = 1/vm: mean is the inverse-variance mean
    const KalmanRule::Cell cell = fuse<KalmanRule>(cfg, pts, 0.01, rng, c.max_per_frame);
    ASSERT_LT(std::abs(KalmanRule::mean(cell) - ref.mz), c.tolerance * c.spread);
    ASSERT_LT(rel(KalmanRule::variance(cell), 1.0 / ref.w), 1e-6);
  }
}

INSTANTIATE_TEST_SUITE_P(
    Cases, RuleInvariants,
    ::testing::Values(Case{0.3, 0.01, 1e-5, 1},     // well conditioned, one point per frame
                      Case{0.3, 0.01, 1e-5, 200},   // well conditioned, many per frame
                      Case{-2.0, 0.005, 1e-5, 50},
                      Case{100.0, 0.001, 1e-3, 1},  // cancellation case: |z| = 100 m, 1 mm
                      Case{100.0, 0.001, 1e-3, 200},
                      Case{-100.0, 0.001, 1e-3, 7}));

TEST(CcmRule, WeightCapDividesWeightAndCoMomentsOncePerFrame) {
  CcmRule::Config cfg;
  cfg.max_weight = 50;
  std::mt19937_64 rng(3);
  const auto pts = random_cell_points(rng, 200, 0.04, 0.0, 0.01);
  CcmRule::Cell cell;
  FrameSums s;
  for (auto& p : pts) s.add(1.0, p.x / 0.04, p.y / 0.04, p.z);
  CcmRule::merge_frame(cfg, cell, s, 0.0, 0.04);
  // One frame of 200 unit-weight points: W = 200 > 50, psi = 4; covariances unchanged.
  std::vector<Point> unit = pts;
  for (auto& p : unit) p.w = 1.0;
  const Moments u = batch(unit);
  EXPECT_FLOAT_EQ(cell.w, 50.0f);
  EXPECT_NEAR(cell.szz / cell.w, u.szz / u.w, 1e-6 * u.szz / u.w);
  EXPECT_NEAR(cell.sxx / cell.w, u.sxx / u.w, 1e-6 * u.sxx / u.w);
}

TEST(OmgRule, WeightCapAndDecay) {
  OmgRule::Config cfg{100.0, 0.5};
  OmgRule::Cell c;
  OmgRule::update(cfg, c, 1.0, 0.001);  // w = 1000 > cap
  EXPECT_FLOAT_EQ(c.weight, 100.0f);
  EXPECT_FLOAT_EQ(c.variance_m2, 0.001f);  // first point: var = vm
  OmgRule::age(cfg, c, 1);
  EXPECT_FLOAT_EQ(c.weight, 50.0f);
}

}  // namespace
}  // namespace hazmap

// CCM queries on analytic cells: a plane, a step, coverage.

#include "hazmap/rules/ccm.hpp"

#include <cmath>
#include <random>

#include <gtest/gtest.h>

namespace hazmap {
namespace {

constexpr double kCell = 0.04;

/// A cell filled with a regular grid of m x m noise-free samples of z = f(x, y).
template <class F>
CcmRule::Cell sample_cell(const CcmRule::Config& cfg, int m, F f) {
  FrameSums s;
  for (int j = 0; j < m; ++j)
    for (int i = 0; i < m; ++i) {
      const double u = (i + 0.5) / m - 0.5, v = (j + 0.5) / m - 0.5;  // cell units
      s.add(1.0, u, v, f(u * kCell, v * kCell));
    }
  CcmRule::Cell c;
  CcmRule::merge_frame(cfg, c, s, 0.0, kCell);
  return c;
}

TEST(CcmRule, NoiseFreePlaneGivesItsSlopesAndZeroRoughness) {
  CcmRule::Config cfg;
  cfg.max_weight = 1e9;
  for (const auto& [a, b, c0] : {std::tuple{0.3, -0.2, 1.5}, std::tuple{-1.2, 0.7, -40.0},
                                 std::tuple{0.0, 2.5, 100.0}}) {
    const CcmRule::Cell c = sample_cell(cfg, 40, [&](double x, double y) { return a * x + b * y + c0; });
    double ga, gb;
    CcmRule::slopes(cfg, c, &ga, &gb);
    EXPECT_NEAR(ga, a, 1e-4);
    EXPECT_NEAR(gb, b, 1e-4);
    EXPECT_NEAR(CcmRule::roughness(cfg, c), 0.0, 1e-9);
    EXPECT_NEAR(CcmRule::height_at(cfg, c, 0.01, -0.015), a * 0.01 - b * 0.015 + c0, 1e-5);
    EXPECT_NEAR(CcmRule::inclination(cfg, c), std::atan(std::hypot(a, b)), 1e-4);
    EXPECT_NEAR(CcmRule::coverage(c, kCell), 1.0 - 1.0 / (40.0 * 40.0), 1e-4);  // grid of 40
  }
}

TEST(CcmRule, StepRoughnessIsTheSpecFormula) {
  // A step of height h along x covering fraction p: rho = h^2 p(1-p)(1 - 3p(1-p)).
  CcmRule::Config cfg;
  cfg.max_weight = 1e9;
  const double h = 0.03;
  for (const double p : {0.1, 0.25, 0.5, 0.75, 0.9}) {
    const CcmRule::Cell c = sample_cell(cfg, 200, [&](double x, double) {
      return x / kCell > 0.5 - p ? h : 0.0;
    });
    const double expected = h * h * p * (1 - p) * (1 - 3 * p * (1 - p));
    EXPECT_NEAR(CcmRule::roughness(cfg, c), expected, 0.02 * expected) << "p = " << p;
  }
}

TEST(CcmRule, ThesisFormIgnoresSxy) {
  // On a plane sampled along a diagonal band (correlated x and y), the full plane fit
  // stays exact while the thesis' diagonal form is biased.
  CcmRule::Config full, thesis;
  full.max_weight = thesis.max_weight = 1e9;
  thesis.full_plane = false;
  FrameSums s;
  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(-0.5, 0.5), n(-0.05, 0.05);
  for (int i = 0; i < 2000; ++i) {
    const double x = u(rng), y = 0.8 * x + n(rng);
    s.add(1.0, x, y, 0.5 * x * kCell + 0.25 * y * kCell);
  }
  CcmRule::Cell c;
  CcmRule::merge_frame(full, c, s, 0.0, kCell);
  double a, b, ta, tb;
  CcmRule::slopes(full, c, &a, &b);
  CcmRule::slopes(thesis, c, &ta, &tb);
  EXPECT_NEAR(a, 0.5, 1e-4);
  EXPECT_NEAR(b, 0.25, 1e-4);
  EXPECT_GT(std::abs(ta - 0.5), 0.05);
}

TEST(CcmRule, EvaluableNeedsCoverageAndPoints) {
  CcmRule::Config cfg;
  cfg.max_weight = 1e9;
  cfg.min_points = 10;
  cfg.min_coverage = 0.8;
  const CcmRule::Cell full = sample_cell(cfg, 10, [](double, double) { return 0.0; });
  EXPECT_TRUE(CcmRule::evaluable(cfg, full, kCell));
  const CcmRule::Cell few = sample_cell(cfg, 3, [](double, double) { return 0.0; });  // 9 points
  EXPECT_FALSE(CcmRule::evaluable(cfg, few, kCell));
  // Points in one half of the cell only: x spread is a quarter of the uniform value.
  FrameSums s;
  for (int i = 0; i < 100; ++i) s.add(1.0, 0.25 * ((i % 10) / 9.0) , (i / 10) / 9.0 - 0.5, 0.0);
  CcmRule::Cell half;
  CcmRule::merge_frame(cfg, half, s, 0.0, kCell);
  EXPECT_LT(CcmRule::coverage(half, kCell), 0.8);
  EXPECT_FALSE(CcmRule::evaluable(cfg, half, kCell));
}

// Which 4 x 4 sub-cells held a point: set by the frame's points, kept across frames and
// through the weight cap (which discounts old points' moments, not the fact that the
// ground there was seen), cleared with the cell.
TEST(CcmRule, OccupancyCollectsEverySubCellThatHeldAPoint) {
  CcmRule::Config cfg;
  cfg.max_weight = 50;  // the second frame's 100 points hit the cap
  const CcmRule::Cell grid = sample_cell(cfg, 8, [](double, double) { return 0.0; });
  EXPECT_EQ(CcmRule::occupied(grid), kAllOccupied);  // 8 x 8 samples: two per sub-cell and axis
  // Frame 1: the left half (sub-cell columns 0 and 1); frame 2: the right half.
  CcmRule::Cell c;
  FrameSums left, right;
  for (int i = 0; i < 100; ++i) {
    const double u = -0.5 + 0.49 * (i % 10) / 9.0, v = -0.5 + 0.99 * (i / 10) / 9.0;
    left.add(1.0, u, v, 0.0);
    right.add(1.0, u + 0.5, v, 0.0);
  }
  CcmRule::merge_frame(cfg, c, left, 0.0, kCell);
  EXPECT_EQ(CcmRule::occupied(c), 0x3333u);
  CcmRule::merge_frame(cfg, c, right, 0.0, kCell);
  EXPECT_EQ(CcmRule::occupied(c), kAllOccupied);
  EXPECT_NEAR(c.w, 50.0, 1e-3);  // capped
  CcmRule::clear(c);
  EXPECT_EQ(CcmRule::occupied(c), 0u);
}

}  // namespace
}  // namespace hazmap

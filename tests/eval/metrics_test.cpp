// score_layer on hand-built grids: each pixel's outcome and each sum is known.

#include "hazmap/eval/metrics.hpp"

#include <gtest/gtest.h>

#include "hazmap/core/error.hpp"

namespace hazmap::eval {
namespace {

// Ground truth: 8 x 8 pixels of 1 cm centred on (0.04, 0.04) (x, y in [0, 0.08)), flat
// at 0.1 m; a 2 x 2 pixel obstacle of 5 cm in the top-left corner and a 1 cm bump (below
// h_min) in the bottom-right pixel.
GroundTruth small_truth() {
  GroundTruth gt;
  gt.height.reset(8, 8, 0.01, 0.04, 0.04, 0.1f);
  gt.hazard.reset(8, 8, 0.01, 0.04, 0.04, 0.0f);
  for (int r = 0; r < 2; ++r)
    for (int c = 0; c < 2; ++c) {
      gt.hazard.at(r, c) = 0.05f;
      gt.height.at(r, c) = 0.15f;
    }
  gt.hazard.at(7, 7) = 0.01f;
  gt.height.at(7, 7) = 0.11f;
  return gt;
}

// Map: 2 x 2 cells of 4 cm over the same square. Top-left: hazard (h 0.1125);
// top-right: hazard (false alarm, h 0.1); bottom-left: unknown; bottom-right: traversable
// at 0.102 m.
LayerMaps small_map() {
  LayerMaps m;
  m.height.reset(2, 2, 0.04, 0.04, 0.04, 0.1f);
  m.variance.reset(2, 2, 0.04, 0.04, 0.04, 1e-6f);  // sigma 1 mm
  m.hazard.reset(2, 2, 0.04, 0.04, 0.04, 1.0f);
  m.hazard.at(0, 0) = 2.0f;
  m.height.at(0, 0) = 0.1125f;
  m.hazard.at(0, 1) = 2.0f;
  m.hazard.at(1, 0) = 0.0f;
  m.height.at(1, 0) = std::numeric_limits<float>::quiet_NaN();
  m.height.at(1, 1) = 0.102f;
  return m;
}

TEST(ScoreLayer, CountsEveryPixelOutcome) {
  const GroundTruth gt = small_truth();
  ErrorMaps maps;
  const MetricSums s = score_layer(small_map(), gt, Pose3d::Identity(), 0.03, &maps);
  EXPECT_EQ(s.extent_px, 64u);
  EXPECT_EQ(s.known_px, 48u);  // bottom-left cell unknown
  EXPECT_EQ(s.gt_hazard_px, 4u);
  EXPECT_EQ(s.gt_hazard_known_px, 4u);
  EXPECT_EQ(s.missed_px, 0u);
  EXPECT_EQ(s.false_alarm_px, 12u + 16u);  // free pixels of both hazard cells
  // Height: known free pixels, the bump (0 < 1 cm < h_min) is not free: 12 + 16 + 15.
  EXPECT_EQ(s.height_px, 43u);
  const double e2 = 12 * 0.0125 * 0.0125 + 16 * 0.0 + 15 * 0.002 * 0.002;
  EXPECT_NEAR(s.sq_error_sum_m2, e2, 1e-8);  // float heights
  // Violations (> 3 mm): the 12 top-left free pixels (12.5 mm), the obstacle pixels
  // (|0.1125 - 0.15| = 37.5 mm) and the bump (|0.102 - 0.11| = 8 mm); not the 2 mm ones.
  EXPECT_EQ(s.variance_px, 48u);
  EXPECT_EQ(s.violation_px, 12u + 4u + 1u);

  ASSERT_EQ(maps.outcome.rows, 8);
  ASSERT_EQ(maps.outcome.cols, 8);
  EXPECT_DOUBLE_EQ(maps.outcome.center_x_m, 0.04);
  EXPECT_EQ(maps.outcome.at(0, 0), static_cast<float>(PixelOutcome::hazard_ok));
  EXPECT_EQ(maps.outcome.at(0, 5), static_cast<float>(PixelOutcome::false_alarm));
  EXPECT_EQ(maps.outcome.at(6, 1), static_cast<float>(PixelOutcome::unknown));
  EXPECT_EQ(maps.outcome.at(7, 7), static_cast<float>(PixelOutcome::below_h_min));
  EXPECT_EQ(maps.outcome.at(5, 5), static_cast<float>(PixelOutcome::free_ok));
  EXPECT_NEAR(maps.abs_error_m.at(5, 5), 0.002, 1e-7);
  EXPECT_TRUE(std::isnan(maps.abs_error_m.at(6, 1)));

  // Traversable where the obstacle is: its 4 pixels are missed.
  LayerMaps blind = small_map();
  blind.hazard.at(0, 0) = 1.0f;
  const MetricSums b = score_layer(blind, gt, Pose3d::Identity(), 0.03);
  EXPECT_EQ(b.missed_px, 4u);
  const LayerMetrics m = derive_metrics(b);
  EXPECT_NEAR(m.missed_area_m2, 4e-4, 1e-15);
  EXPECT_NEAR(m.missed_of_hazard, 1.0, 1e-15);
  EXPECT_NEAR(m.missed_fraction, 4.0 / 48.0, 1e-15);
  EXPECT_NEAR(m.unknown_fraction, 0.25, 1e-15);
}

TEST(ScoreLayer, CcmLayersAreQueriedOnTheirPlanes) {
  LayerMaps m = small_map();
  m.slope_x.reset(2, 2, 0.04, 0.04, 0.04, 0.5f);
  m.slope_y.reset(2, 2, 0.04, 0.04, 0.04, -0.25f);
  // Cell (1, 1) spans x, y in [0.04, 0.08) x [0, 0.04): centre (0.06, 0.02).
  EXPECT_NEAR(layer_height_at(m, 0.075, 0.005), 0.102 + 0.5 * 0.015 - 0.25 * -0.015, 1e-7);
  EXPECT_TRUE(std::isnan(layer_height_at(m, 0.2, 0.0)));  // outside
}

TEST(ScoreLayer, PixelsOutsideTheWindowAreNotScored) {
  // The map window is one column of 4 cm cells, x in [0, 0.04) of the map frame, and
  // T_map_W moves W by -4 cm in x: the GT pixels with W x in [0.04, 0.08) land in it, the
  // others fall outside and are not scored.
  LayerMaps m;
  m.hazard.reset(2, 1, 0.04, 0.02, 0.04, 1.0f);
  Pose3d T = Pose3d::Identity();
  T.translation() = Eigen::Vector3d(-0.04, 0.0, 0.0);
  const MetricSums s = score_layer(m, small_truth(), T, 0.03);
  EXPECT_EQ(s.extent_px, 32u);  // GT x in [0.04, 0.08)
  EXPECT_EQ(s.height_px, 0u);   // hazard-only map
  EXPECT_EQ(s.false_alarm_px, 0u);
}

TEST(ScoreLayer, RejectsMismatchedGrids) {
  GroundTruth gt = small_truth();
  gt.hazard.reset(4, 4, 0.01, 0.04, 0.04, 0.0f);
  EXPECT_THROW(score_layer(small_map(), gt, Pose3d::Identity(), 0.03), Error);
  EXPECT_THROW(score_layer(small_map(), small_truth(), Pose3d::Identity(), 0.0), Error);
}

}  // namespace
}  // namespace hazmap::eval

// score_layer on hand-built grids: each pixel's outcome and each sum is known.

#include "hazmap/eval/metrics.hpp"

#include <cmath>
#include <limits>

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

// small_truth with obstacle pixels (5 cm >= h_min) in three cells of small_map: the 2 x 2
// block in the hazard cell (0, 0), two pixels in the unknown cell (1, 0) and one in the
// traversable cell (1, 1).
GroundTruth spread_truth() {
  GroundTruth gt = small_truth();
  for (const auto& [r, c] : {std::pair{5, 1}, std::pair{5, 2}, std::pair{4, 6}}) {
    gt.hazard.at(r, c) = 0.05f;
    gt.height.at(r, c) = 0.15f;
  }
  return gt;
}

TEST(ScoreLayer, RecallAndUnknownAreSharesOfTheObstaclePixels) {
  const MetricSums s = score_layer(small_map(), spread_truth(), Pose3d::Identity(), 0.03);
  EXPECT_EQ(s.gt_hazard_px, 7u);
  EXPECT_EQ(s.gt_hazard_found_px, 4u);
  EXPECT_EQ(s.gt_hazard_known_px, 5u);
  EXPECT_EQ(s.missed_px, 1u);
  const LayerMetrics m = derive_metrics(s);
  EXPECT_NEAR(m.hazard_recall, 4.0 / 7.0, 1e-15);
  EXPECT_NEAR(m.hazard_unknown, 2.0 / 7.0, 1e-15);
  EXPECT_NEAR(m.missed_of_hazard, 1.0 / 5.0, 1e-15);  // of the known obstacle pixels
  // Obstacles lower than h_min are not obstacles: with h_min 6 cm there are none.
  const LayerMetrics none = derive_metrics(score_layer(small_map(), spread_truth(),
                                                       Pose3d::Identity(), 0.06));
  EXPECT_TRUE(std::isnan(none.hazard_recall));
  EXPECT_TRUE(std::isnan(none.hazard_unknown));
  // A map that says unknown everywhere misses nothing and finds nothing.
  LayerMaps blind = small_map();
  blind.hazard.values.assign(blind.hazard.values.size(), 0.0f);
  const LayerMetrics b = derive_metrics(score_layer(blind, spread_truth(), Pose3d::Identity(), 0.03));
  EXPECT_EQ(b.missed_area_m2, 0.0);
  EXPECT_EQ(b.hazard_recall, 0.0);
  EXPECT_EQ(b.hazard_unknown, 1.0);
}

TEST(ScoreLayer, AllHeightMetricsIncludeCellsOfUnknownClass) {
  // Without a height in the unknown cell, "all" equals the known-only sums.
  const MetricSums plain = score_layer(small_map(), small_truth(), Pose3d::Identity(), 0.03);
  EXPECT_EQ(plain.height_all_px, plain.height_px);
  EXPECT_EQ(plain.variance_all_px, plain.variance_px);
  EXPECT_EQ(plain.violation_all_px, plain.violation_px);
  // The unknown cell (1, 0) publishes 0.11 m over ground at 0.1 m: 16 free pixels with
  // |e| = 10 mm > 3 sigma = 3 mm.
  LayerMaps m = small_map();
  m.height.at(1, 0) = 0.11f;
  const MetricSums s = score_layer(m, small_truth(), Pose3d::Identity(), 0.03);
  EXPECT_EQ(s.height_px, 43u);  // known-only sums unchanged (CountsEveryPixelOutcome)
  EXPECT_EQ(s.variance_px, 48u);
  EXPECT_EQ(s.violation_px, 17u);
  EXPECT_EQ(s.height_all_px, 43u + 16u);
  EXPECT_EQ(s.variance_all_px, 48u + 16u);
  EXPECT_EQ(s.violation_all_px, 17u + 16u);
  const double e2_known = 12 * 0.0125 * 0.0125 + 15 * 0.002 * 0.002;
  const double e2_all = e2_known + 16 * 0.01 * 0.01;
  const LayerMetrics d = derive_metrics(s);
  EXPECT_NEAR(d.height_rms_m, std::sqrt(e2_known / 43.0), 1e-6);  // float heights
  EXPECT_NEAR(d.height_rms_all_m, std::sqrt(e2_all / 59.0), 1e-6);
  EXPECT_EQ(d.height_samples_all, 59u);
  EXPECT_NEAR(d.variance_violation, 17.0 / 48.0, 1e-15);
  EXPECT_NEAR(d.variance_violation_all, 33.0 / 64.0, 1e-15);
  // A NaN variance keeps a pixel out of both violation counts but not out of the RMS.
  m.variance.at(1, 0) = std::numeric_limits<float>::quiet_NaN();
  const MetricSums v = score_layer(m, small_truth(), Pose3d::Identity(), 0.03);
  EXPECT_EQ(v.variance_all_px, 48u);
  EXPECT_EQ(v.height_all_px, 59u);
}

TEST(ScoreLayer, NaNSlopesFallBackToTheCellHeight) {
  // CCM cells that are not evaluable publish NaN slopes (SPEC 9): the query is then the
  // cell height, not NaN and not a plane through garbage.
  LayerMaps m = small_map();
  m.slope_x.reset(2, 2, 0.04, 0.04, 0.04, 0.5f);
  m.slope_y.reset(2, 2, 0.04, 0.04, 0.04, -0.25f);
  m.slope_x.at(1, 1) = std::numeric_limits<float>::quiet_NaN();
  m.slope_y.at(1, 1) = std::numeric_limits<float>::quiet_NaN();
  EXPECT_NEAR(layer_height_at(m, 0.075, 0.005), 0.102, 1e-7);
  // The neighbouring cell (0, 1), centre (0.06, 0.06), keeps its plane.
  EXPECT_NEAR(layer_height_at(m, 0.075, 0.075), 0.1 + 0.5 * 0.015 - 0.25 * 0.015, 1e-7);
  // With every slope NaN, scoring equals that of the layer without slope grids (a NaN
  // query would drop the pixels from the RMS instead).
  m.slope_x.values.assign(4, std::numeric_limits<float>::quiet_NaN());
  m.slope_y.values.assign(4, std::numeric_limits<float>::quiet_NaN());
  ASSERT_TRUE(m.has_plane());
  const MetricSums with_nan = score_layer(m, small_truth(), Pose3d::Identity(), 0.03);
  const MetricSums without = score_layer(small_map(), small_truth(), Pose3d::Identity(), 0.03);
  EXPECT_EQ(with_nan.height_px, 43u);
  EXPECT_EQ(with_nan.sq_error_sum_m2, without.sq_error_sum_m2);
  EXPECT_EQ(with_nan.violation_px, without.violation_px);
}

TEST(ScoreLayer, NearSumsCountOnlyPixelsInTheDiscAroundTheRover) {
  // Disc of radius 3.5 cm around W (0, 0.08), the top-left corner: pixel centres at
  // (0.005 + 0.01 i, 0.075 - 0.01 j) are inside for (i, j) in {0,1,2}^2 minus (2, 2)
  // (d^2 = 0.00125 > 0.001225): 8 pixels, the 4 obstacle pixels and 4 free pixels of the
  // hazard cell (0, 0), i.e. 4 false alarms.
  const NearRegion near{0.0, 0.08, 0.035};
  MetricSums n;
  const MetricSums s = score_layer(small_map(), small_truth(), Pose3d::Identity(), 0.03, nullptr,
                                   &near, &n);
  EXPECT_EQ(s.extent_px, 64u);  // the window's sums are unaffected
  EXPECT_EQ(s.false_alarm_px, 28u);
  EXPECT_EQ(n.extent_px, 8u);
  EXPECT_EQ(n.known_px, 8u);
  EXPECT_EQ(n.gt_hazard_px, 4u);
  EXPECT_EQ(n.gt_hazard_found_px, 4u);
  EXPECT_EQ(n.false_alarm_px, 4u);
  EXPECT_EQ(n.missed_px, 0u);
  EXPECT_DOUBLE_EQ(n.pixel_area_m2, 1e-4);
  LayerMaps blind = small_map();
  blind.hazard.at(0, 0) = 1.0f;
  score_layer(blind, small_truth(), Pose3d::Identity(), 0.03, nullptr, &near, &n);
  EXPECT_EQ(n.missed_px, 4u);  // recomputed, not accumulated onto the previous call
  EXPECT_EQ(n.false_alarm_px, 0u);
  EXPECT_EQ(derive_metrics(n).hazard_recall, 0.0);

  // The disc is tested in W, where the rover truly is, not in the (shifted) map frame:
  // the one-column window of PixelsOutsideTheWindowAreNotScored holds W x in [0.04, 0.08);
  // around W (0.08, 0.08) the same 8-pixel pattern (mirrored) falls inside it. In the map
  // frame those pixels sit 4 cm further left, all farther than 3.5 cm.
  LayerMaps column;
  column.hazard.reset(2, 1, 0.04, 0.02, 0.04, 1.0f);
  Pose3d T = Pose3d::Identity();
  T.translation() = Eigen::Vector3d(-0.04, 0.0, 0.0);
  const NearRegion corner{0.08, 0.08, 0.035};
  score_layer(column, small_truth(), T, 0.03, nullptr, &corner, &n);
  EXPECT_EQ(n.extent_px, 8u);
  const NearRegion negative{0.0, 0.0, -1.0};
  EXPECT_THROW(score_layer(column, small_truth(), T, 0.03, nullptr, &negative, &n), Error);
}

TEST(MetricSums, NewMetricsPoolExactlyThroughSums) {
  // Frame a: 10 obstacle pixels, 2 found, 6 unknown; frame b: 2 obstacle pixels, both
  // found. Pooled recall 4/12 and unknown 6/12, not the means of the frames' fractions
  // (0.6 and 0.3).
  MetricSums a, b;
  a.pixel_area_m2 = b.pixel_area_m2 = 1e-4;
  a.gt_hazard_px = 10, a.gt_hazard_known_px = 4, a.gt_hazard_found_px = 2, a.missed_px = 2;
  b.gt_hazard_px = 2, b.gt_hazard_known_px = 2, b.gt_hazard_found_px = 2;
  a.height_all_px = 3, a.sq_error_all_sum_m2 = 3 * 0.01 * 0.01;
  b.height_all_px = 1, b.sq_error_all_sum_m2 = 0.05 * 0.05;
  a.variance_all_px = 4, a.violation_all_px = 1;
  b.variance_all_px = 1, b.violation_all_px = 1;
  MetricSums p = a;
  p += b;
  const LayerMetrics m = derive_metrics(p);
  EXPECT_NEAR(m.hazard_recall, 4.0 / 12.0, 1e-15);
  EXPECT_NEAR(m.hazard_unknown, 6.0 / 12.0, 1e-15);
  EXPECT_NEAR(m.height_rms_all_m, std::sqrt((3e-4 + 2.5e-3) / 4.0), 1e-15);
  EXPECT_NEAR(m.variance_violation_all, 2.0 / 5.0, 1e-15);
  EXPECT_EQ(m.height_samples_all, 4u);
}

// Deepest below the terrain (issue 19): over cells, each published height against the
// GT pixel holding the cell centre, whatever the cell's class.
TEST(ScoreLayer, DeepestBelowTheTerrainIsTakenOverCellCentres) {
  GroundTruth gt;
  gt.height.reset(8, 8, 0.01, 0.04, 0.04, 0.1f);
  gt.hazard.reset(8, 8, 0.01, 0.04, 0.04, 0.0f);
  gt.height.at(5, 2) = 0.2f;  // a 10 cm rock top
  gt.hazard.at(5, 2) = 0.1f;
  LayerMaps m;  // 1 cm cells on the GT pixels; class unknown everywhere
  m.height.reset(8, 8, 0.01, 0.04, 0.04, 0.1f);
  m.variance.reset(8, 8, 0.01, 0.04, 0.04, 1e-6f);
  m.hazard.reset(8, 8, 0.01, 0.04, 0.04, 0.0f);
  m.height.at(5, 2) = 0.12f;  // 8 cm below the rock top
  m.height.at(1, 6) = 0.07f;  // 3 cm below the ground
  m.height.at(3, 3) = std::numeric_limits<float>::quiet_NaN();
  const NearRegion near{m.height.x_of_col(6), m.height.y_of_row(1), 0.012};
  MetricSums n;
  const MetricSums s = score_layer(m, gt, Pose3d::Identity(), 0.03, nullptr, &near, &n);
  EXPECT_EQ(s.height_cells, 63u);
  EXPECT_NEAR(s.max_below_m, 0.08, 1e-6);  // float heights
  EXPECT_EQ(n.height_cells, 5u);  // the cell and its four neighbours
  EXPECT_NEAR(n.max_below_m, 0.03, 1e-6);
  EXPECT_NEAR(derive_metrics(s).max_below_m, 0.08, 1e-6);

  // The same map in a frame shifted by (2 cm, 0, 5 cm) from W: unchanged.
  Pose3d T_map_W = Pose3d::Identity();
  T_map_W.translation() = Eigen::Vector3d(0.02, 0.0, 0.05);
  LayerMaps shifted = m;
  for (DenseGrid* g : {&shifted.height, &shifted.variance, &shifted.hazard}) g->center_x_m += 0.02;
  for (float& h : shifted.height.values) h += 0.05f;
  const MetricSums t = score_layer(shifted, gt, T_map_W, 0.03);
  EXPECT_EQ(t.height_cells, 63u);
  EXPECT_NEAR(t.max_below_m, 0.08, 1e-6);

  // Every cell above the truth: the largest of the (negative) differences.
  LayerMaps above = m;
  above.height.values.assign(64, 0.3f);
  EXPECT_NEAR(score_layer(above, gt, Pose3d::Identity(), 0.03).max_below_m, -0.1, 1e-6);
  // A hazard-only map has no cells with heights: undefined.
  LayerMaps hazard_only;
  hazard_only.hazard = m.hazard;
  const MetricSums none = score_layer(hazard_only, gt, Pose3d::Identity(), 0.03);
  EXPECT_EQ(none.height_cells, 0u);
  EXPECT_TRUE(std::isnan(derive_metrics(none).max_below_m));
  // Pooled over frames by max.
  MetricSums pooled = none;
  pooled += n;
  pooled += s;
  EXPECT_EQ(pooled.height_cells, 68u);
  EXPECT_NEAR(derive_metrics(pooled).max_below_m, 0.08, 1e-6);
}

// The footprint's truth: every pixel whose centre lies within the radius of an obstacle
// pixel's centre takes that obstacle's height (the tallest when several reach it),
// checked against a brute-force search over all pixel pairs.
TEST(DilateObstacles, EachPixelTakesTheTallestObstacleWithinTheRadius) {
  GroundTruth gt;
  gt.height.reset(30, 40, 0.01, 0.0, 0.0, 0.0f);
  gt.hazard.reset(30, 40, 0.01, 0.0, 0.0, 0.0f);
  gt.hazard.at(5, 6) = 0.05f;
  gt.hazard.at(8, 9) = 0.12f;  // overlaps the first one's disc
  gt.hazard.at(20, 39) = 0.03f;  // at the border: its disc is clipped
  gt.hazard.at(0, 30) = std::numeric_limits<float>::quiet_NaN();  // no data stays no data
  const double radius = 0.045;
  const GroundTruth d = dilate_obstacles(gt, radius);
  int reached = 0;
  for (int r = 0; r < 30; ++r)
    for (int c = 0; c < 40; ++c) {
      if (r == 0 && c == 30) {
        EXPECT_TRUE(std::isnan(d.hazard.at(r, c)));
        continue;
      }
      float expect = 0.0f;
      for (int rr = 0; rr < 30; ++rr)
        for (int cc = 0; cc < 40; ++cc) {
          const float h = gt.hazard.at(rr, cc);
          const double dist = std::hypot(gt.hazard.x_of_col(c) - gt.hazard.x_of_col(cc),
                                         gt.hazard.y_of_row(r) - gt.hazard.y_of_row(rr));
          if (h > expect && dist <= radius) expect = h;
        }
      EXPECT_EQ(d.hazard.at(r, c), expect) << r << "," << c;
      reached += expect > 0.0f;
      EXPECT_EQ(d.height.at(r, c), gt.height.at(r, c));
    }
  // Two overlapping discs of 69 pixels (radius 4.5 px) and half a disc at the border.
  EXPECT_GT(reached, 69 + 30);
  EXPECT_LT(reached, 2 * 69 + 69);
  EXPECT_THROW(dilate_obstacles(gt, -0.01), Error);
}

TEST(ScoreLayer, RejectsMismatchedGrids) {
  GroundTruth gt = small_truth();
  gt.hazard.reset(4, 4, 0.01, 0.04, 0.04, 0.0f);
  EXPECT_THROW(score_layer(small_map(), gt, Pose3d::Identity(), 0.03), Error);
  EXPECT_THROW(score_layer(small_map(), small_truth(), Pose3d::Identity(), 0.0), Error);
}

}  // namespace
}  // namespace hazmap::eval

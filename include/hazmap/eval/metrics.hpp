#pragma once
// Scoring one map layer against ground truth (SPEC 10). Pure geometry on DenseGrids and
// Eigen; reading run folders and writing reports live in run_evaluation.hpp.
//
// For every ground-truth (GT) pixel whose centre, moved into the map frame, falls inside
// the layer's window:
//   - the map cell is *known* when its hazard class is not unknown (so a CCM cell that
//     is not evaluable, or a piecewise-constant cell whose kernel is too empty, is
//     unknown: what a planner would be told);
//   - height error e = h_map(q) - z_gt, with q the pixel centre in the map frame and
//     z_gt the GT height moved into the map frame; h_map is the cell height (piecewise
//     constant) or the cell plane h + slope_x dx + slope_y dy (CCM, sub-cell);
//     height RMS is over known pixels whose GT hazard is 0;
//   - missed hazard: GT obstacle height >= h_min but the map says traversable;
//     false alarm: GT obstacle height 0 but the map says hazard; pixels with an obstacle
//     lower than h_min are scored neither way;
//   - variance violation: known pixels with |e| > 3 sqrt(variance) (all known pixels
//     with a finite variance, obstacles included, as SPEC 10 states).
// Areas are pixel counts times the GT pixel area.

#include <cstddef>
#include <cstdint>
#include <limits>

#include "hazmap/core/types.hpp"
#include "hazmap/map/dense_grid.hpp"

namespace hazmap::eval {

/// Ground truth on one grid in the true world frame W (SPEC 9, 10).
struct GroundTruth {
  DenseGrid height;  ///< terrain surface height at pixel centres [m], rocks included
  DenseGrid hazard;  ///< obstacle height above the ground [m], 0 = no obstacle
};

/// One layer of one written frame, in the map frame (the frame of the poses the run
/// used). `height` and `variance` may be empty (rows == 0) for hazard-only maps such as
/// the fused map; `slope_x`/`slope_y` are filled for CCM layers only.
struct LayerMaps {
  DenseGrid height;    ///< at cell centres [m], NaN unknown
  DenseGrid variance;  ///< [m^2]
  DenseGrid hazard;    ///< HazardClass values 0 / 1 / 2; defines the layer's window
  DenseGrid slope_x;   ///< dz/dx (CCM)
  DenseGrid slope_y;   ///< dz/dy (CCM)

  bool has_height() const { return height.rows > 0; }
  bool has_plane() const { return slope_x.rows > 0 && slope_y.rows > 0; }
};

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();

/// Sums behind the metrics, so frames and runs can be pooled exactly (add, then derive).
struct MetricSums {
  std::size_t extent_px = 0;        ///< GT pixels inside the layer's window
  std::size_t known_px = 0;         ///< ... whose map cell is known
  std::size_t height_px = 0;        ///< known, GT hazard 0, finite map height
  double sq_error_sum_m2 = 0.0;     ///< sum of e^2 over height_px
  std::size_t gt_hazard_px = 0;     ///< GT obstacle >= h_min, inside the window
  std::size_t gt_hazard_known_px = 0;
  std::size_t missed_px = 0;
  std::size_t false_alarm_px = 0;
  std::size_t variance_px = 0;      ///< known pixels with finite height and variance
  std::size_t violation_px = 0;     ///< ... with |e| > 3 sigma
  double pixel_area_m2 = 0.0;

  MetricSums& operator+=(const MetricSums& o);
};

/// The SPEC 10 metrics derived from MetricSums. Fractions are NaN when their
/// denominator is empty (e.g. missed_of_hazard when no obstacle is known).
struct LayerMetrics {
  double extent_area_m2 = 0.0;
  double known_area_m2 = 0.0;
  double unknown_fraction = kNaN;      ///< 1 - known / extent
  double height_rms_m = kNaN;
  std::size_t height_samples = 0;
  double gt_hazard_area_m2 = 0.0;      ///< GT obstacles >= h_min inside the window
  double gt_hazard_known_area_m2 = 0.0;
  double missed_area_m2 = 0.0;
  double missed_fraction = kNaN;       ///< missed / known area (SPEC 10)
  double missed_of_hazard = kNaN;      ///< missed / known GT obstacle area (1 - recall)
  double false_alarm_area_m2 = 0.0;
  double false_alarm_fraction = kNaN;  ///< false alarm / known area (SPEC 10)
  double variance_violation = kNaN;    ///< fraction of known pixels beyond 3 sigma
};

LayerMetrics derive_metrics(const MetricSums& sums);

/// What happened at each GT pixel, for pictures.
enum class PixelOutcome : std::uint8_t {
  outside = 0,         ///< not inside the layer's window
  unknown = 1,         ///< map cell unknown
  free_ok = 2,         ///< GT free, map traversable
  hazard_ok = 3,       ///< GT obstacle >= h_min, map hazard
  missed = 4,          ///< GT obstacle >= h_min, map traversable
  false_alarm = 5,     ///< GT free, map hazard
  below_h_min = 6,     ///< GT obstacle lower than h_min (not scored)
};

/// Per-pixel pictures over the GT pixels the window covers (a crop of the GT grid, same
/// resolution and W geometry).
struct ErrorMaps {
  DenseGrid abs_error_m;  ///< |e| at known pixels with a height, NaN elsewhere
  DenseGrid outcome;      ///< PixelOutcome values
};

/// Scores one layer. `T_map_W` moves true-world points into the map frame (identity
/// when the run used true poses; see run_evaluation.hpp for the drifted case).
/// `h_min_m` > 0. When `maps` is not null, fills them. Throws Error on empty ground
/// truth, a non-positive h_min or grids whose sizes disagree.
MetricSums score_layer(const LayerMaps& layer, const GroundTruth& gt, const Pose3d& T_map_W,
                       double h_min_m, ErrorMaps* maps = nullptr);

/// Map height at map-frame point (x, y): the cell's height, or for a layer with planes
/// the plane through it; NaN when outside the window or unknown.
double layer_height_at(const LayerMaps& layer, double x_m, double y_m);

}  // namespace hazmap::eval

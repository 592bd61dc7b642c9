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
//     height RMS is over known pixels whose GT hazard is 0; height RMS "all" over every
//     pixel with a published (finite) height whose GT hazard is 0, unknown class included
//     (a consumer reads those heights too; obstacles stay out of both, since no cell
//     height is meant to follow a rock's shape);
//   - hazard recall: of the GT obstacle pixels (>= h_min) in the window, the fraction
//     the map labels hazard; hazard unknown: the fraction it labels unknown (recall +
//     unknown + missed share = 1);
//   - missed hazard: GT obstacle height >= h_min but the map says traversable;
//     false alarm: GT obstacle height 0 but the map says hazard; pixels with an obstacle
//     lower than h_min are scored neither way;
//   - variance violation: known pixels with |e| > 3 sqrt(variance) (all known pixels
//     with a finite variance, obstacles included, as SPEC 10 states); "all": the same
//     over every pixel with a finite published height and variance, unknown class included.
//   - deepest below the terrain (issue 19): over the layer's *cells* rather than the GT
//     pixels, every cell with a finite published height (any class), max(z_gt - h) with h
//     the cell's published height (at its centre) and z_gt the GT height of the pixel
//     holding the cell centre, moved into the map frame. Cells, not pixels: a coarse cell
//     cannot follow a rock across it, but none should sit below the ground under its
//     centre (measured: mismatched points put 1 cm cells 13 cm below a rock's top).
// Optionally the same counts restricted to GT pixels within a radius of a point of W
// (the rover's true position: `evaluate --near R`).
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
  std::size_t gt_hazard_found_px = 0;  ///< ... the map labels hazard
  std::size_t missed_px = 0;
  std::size_t false_alarm_px = 0;
  std::size_t variance_px = 0;      ///< known pixels with finite height and variance
  std::size_t violation_px = 0;     ///< ... with |e| > 3 sigma
  std::size_t height_all_px = 0;    ///< finite map height, GT hazard 0, any class
  double sq_error_all_sum_m2 = 0.0; ///< sum of e^2 over height_all_px
  std::size_t variance_all_px = 0;  ///< finite map height and variance, any class
  std::size_t violation_all_px = 0; ///< ... with |e| > 3 sigma
  double pixel_area_m2 = 0.0;
  /// Cells with a finite published height whose centre has GT, and the largest
  /// z_gt - h over them [m] (-inf when none); pooled by max.
  std::size_t height_cells = 0;
  double max_below_m = -std::numeric_limits<double>::infinity();

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
  double hazard_recall = kNaN;         ///< GT obstacle pixels labelled hazard / all of them
  double hazard_unknown = kNaN;        ///< GT obstacle pixels labelled unknown / all of them
  double height_rms_all_m = kNaN;      ///< over every published height (GT hazard 0)
  std::size_t height_samples_all = 0;
  double variance_violation_all = kNaN;  ///< over every published height with a variance
  /// Deepest published cell height below the GT at the cell centre [m] (negative: every
  /// cell lies above it); NaN when no cell has a height.
  double max_below_m = kNaN;
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

/// A disc of W (horizontal distance) that a second set of sums is restricted to.
struct NearRegion {
  double x_m = 0.0, y_m = 0.0;  ///< centre in W (the rover's true position)
  double radius_m = 0.0;
  bool contains(double x, double y) const {
    return (x - x_m) * (x - x_m) + (y - y_m) * (y - y_m) <= radius_m * radius_m;
  }
};

/// Scores one layer. `T_map_W` moves true-world points into the map frame (identity
/// when the run used true poses; see run_evaluation.hpp for the drifted case).
/// `h_min_m` > 0. When `maps` is not null, fills them. When `near` and `near_sums` are
/// not null, `*near_sums` receives the sums over the GT pixels whose centre (in W) lies
/// in `near`. Throws Error on empty ground truth, a non-positive h_min, a negative near
/// radius or grids whose sizes disagree.
MetricSums score_layer(const LayerMaps& layer, const GroundTruth& gt, const Pose3d& T_map_W,
                       double h_min_m, ErrorMaps* maps = nullptr, const NearRegion* near = nullptr,
                       MetricSums* near_sums = nullptr);

/// The ground truth of a rover-centre map (the footprint map, SPEC 8.5): each pixel's
/// obstacle height becomes the tallest obstacle within `radius_m` of its centre (pixel
/// centres compared), so a footprint cell is truly hazardous when the rover centred there
/// would touch an obstacle. Heights are unchanged. radius_m >= 0.
GroundTruth dilate_obstacles(const GroundTruth& gt, double radius_m);

/// Map height at map-frame point (x, y): the cell's height, or for a layer with planes
/// the plane through it; NaN when outside the window or unknown. A CCM cell whose slopes
/// are NaN (not evaluable) gives its cell height.
double layer_height_at(const LayerMaps& layer, double x_m, double y_m);

}  // namespace hazmap::eval

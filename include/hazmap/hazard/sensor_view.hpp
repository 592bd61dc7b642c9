#pragma once
// What the stereo pair looked at in one frame, for the wheel ring's view_edge proof
// (hazard.partial_ring_proof: view_edge, issue 34). A ring sample a layer cannot use to
// prove is excused only in a cell that no frame's view ever covered whole: the ground
// there was never (or only in part) in the images, so the ring is cut by the edge of
// what was looked at. A hole inside the view (a shadow, ground behind a rock, a face
// without texture, a rock top with few points) is never excused: a rock may be exactly
// there.
//
// A point counts as looked at when some point of the vertical column over it projects
// into the matchable part of the rectified left image (edge_margin_px in from the
// border) within depth [z_min, z_max], and its match into the right image's
// (right_edge_margin_px in from its left border). The column spans the ground a coarser layer knows
// there (TerrainBand: its height +- k sigma and a slope's rise over its cell) or, where
// none does, `band_below_m` under to `band_above_m` over the body's wheel plane (the
// terrain the stereo stage expects: stereo.band_max_depth, stereo.band_max_height).
// A layer's lateral gate (rules.ccm.max_std_ratio) does not end its view: beyond it the
// coarser layers saw the ground, and a ring sample there comes from their plane
// (hazard.coarse_ring_fill) or keeps the ring from proving. (Measured: excusing such
// samples proved the rim of a 12 cm rock under low sun.) A cell is wholly viewed when its
// centre and four corners are looked at in one frame. Without a view (the map core fed
// points from elsewhere) the hazard stage counts every cell as wholly viewed: only full
// rings prove.

#include <cstdint>
#include <vector>

#include "hazmap/core/types.hpp"
#include "hazmap/map/dense_grid.hpp"
#include "hazmap/map/grid_rect.hpp"

namespace hazmap {

struct SensorView {
  Pose3d T_W_B = Pose3d::Identity();   ///< the body at this frame
  Pose3d T_B_C = Pose3d::Identity();   ///< the rectified left camera on the body (x right, y down, z forward)
  double focal_px = 0, cx_px = 0, cy_px = 0;
  int width_px = 0, height_px = 0;     ///< the rectified image
  /// No disparity within this many pixels of the image's border (the matching window),
  /// nor in the first blank_left_px columns (a matcher's blank band).
  double edge_margin_px = 0;
  double blank_left_px = 0;
  /// Nor where the match would fall within this many pixels of the right image's left
  /// border (u - f B / Z < it): the right camera did not see that ground with a window
  /// to spare (bm and sgbm with stereo.match_left_border drop such matches: block_size;
  /// otherwise half a window). 0: the right image is not checked.
  double right_edge_margin_px = 0;
  double z_min_m = 0, z_max_m = 0;     ///< depth along the optical axis (stereo.z_min, z_max)
  double band_below_m = 0.5, band_above_m = 0.5;
  /// The frame's disparity image (rectified left, x16 fixed point, row-major with
  /// `disparity_stride` elements per row; a value <= invalid_below_x16 or <= 0 is no
  /// disparity) and the part of it that may give points, for the hole-free test
  /// (hazard/hole_marker.hpp). Null: no disparity image (points from elsewhere).
  const std::int16_t* disparity_x16 = nullptr;
  int disparity_stride = 0;
  int invalid_below_x16 = 0;
  int roi_x0 = 0, roi_y0 = 0, roi_x1 = 0, roi_y1 = 0;  ///< [x0, x1) x [y0, y1)
  int stride = 1;  ///< pixels giving points: every stride-th from (roi_x0, roi_y0)
  double baseline_m = 0;
  /// Per layer: the depth beyond which the layer's lateral gate drops every point
  /// (map.layers.N.max_std_ratio), set once; a pixel farther gives the layer nothing, so
  /// the hole-free test does not look there. Empty or 0: z_max.
  std::vector<double> layer_depth_limit_m;

  /// True when the column over W point (x, y), between the body band's heights, reaches
  /// the matchable image (edge_margin_px in from its border) within the depth range.
  bool sees_column(double x_m, double y_m) const;
};

/// Where the terrain may be, from coarser layers' heights: the band the view test hangs a
/// cell's column on instead of the body's wide band, where a layer knows the ground. The
/// band is the first source's height at the point, +- k sigma and the spread of ground
/// up to the steepest traversable slope over the source's cell.
class TerrainBand {
 public:
  /// Sources are read in the order added (finest first); the grids must outlive the band.
  void add(const DenseGrid* height, const DenseGrid* variance, double k_sigma, double spread_m) {
    sources_.push_back({height, variance, k_sigma, spread_m});
  }
  /// The band at W point (x, y); false where no source knows the height.
  bool at(double x_m, double y_m, double* lo, double* hi) const;

 private:
  struct Source {
    const DenseGrid* height;
    const DenseGrid* variance;
    double k_sigma, spread_m;
  };
  std::vector<Source> sources_;
};

/// A view mask's values: never looked at (0), partly (some of the cell's centre and
/// corners were seen), wholly (all of them, at one frame).
constexpr float kPartlyViewed = 1.0f;
constexpr float kWhollyViewed = 2.0f;

/// Raises the cells of a layer's view mask to what each frame's view sees of them.
class ViewMarker {
 public:
  /// Raises every cell of `viewed` (a layer's geometry) to what `view` sees of it, and
  /// returns the smallest rectangle holding the cells it changed (empty: none). Wholly
  /// viewed cells are not tested again. `terrain` (may be null) narrows a point's column
  /// to the ground a coarser layer knows there. Allocates only on a wider mask than
  /// before.
  GridRect mark(const SensorView& view, DenseGrid& viewed, const TerrainBand* terrain = nullptr);

 private:
  std::vector<std::uint8_t> top_, bottom_;  ///< a row's upper and lower cell corners
};

}  // namespace hazmap

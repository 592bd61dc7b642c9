#pragma once
// The hole-free test (issue 34, map.layers.N.hole_free_coverage): marks the cells of a
// CCM layer that a frame's disparity image saw whole (map/seen_whole.hpp).
//
// A cell is tested at a frame when its four corners, on the level plane at its published
// height, project into the part of the left image that gives points, within the depth
// range and as deep as the layer takes points (its lateral gate). Every pixel that gives
// points (the stride grid) whose ray meets that plane inside the cell looked at it; its
// disparity is compared with the plane's, f B / depth, and counted in the cell's quarter
// where the ray meets it:
//  - within `tolerance_px`: it saw the quarter's ground;
//  - off by more (nearer: something in front hid it; farther: not this plane): the frame
//    says nothing of the quarter;
//  - no disparity (none, or removed as occluded by known terrain): a pixel the matcher
//    missed. Scattered ones are its noise (measured: a single one vetoing made the map
//    blind, evenly lit too), so only a quarter whose every pixel was missed is a hole.
// A hole is final: under a low sun the part of a cell without points is often a rock's
// shadow, in every frame. A cell with no hole whose four quarters each saw ground, and
// nothing else, is seen whole: its points are as dense as the pixels over it allow (its
// coverage stays short of 0.8 at range because a few pixel rows span it).

#include "hazmap/core/parallel_for.hpp"
#include "hazmap/hazard/sensor_view.hpp"
#include "hazmap/map/grid_rect.hpp"
#include "hazmap/map/layer.hpp"
#include "hazmap/map/seen_whole.hpp"

namespace hazmap {

class HoleMarker {
 public:
  /// Tests the known cells of `map` (a CCM layer's export) without a hole yet, raises
  /// `marks` (the layer's window, image order) and returns the smallest rectangle holding
  /// the cells whose mark changed (empty: none). Without a disparity image in `view`,
  /// nothing.
  /// Only corners within `max_depth_m` (and z_max) are in view: pixels farther give the
  /// layer no points (its lateral gate). Bands of rows on `pool`'s threads (null: this
  /// thread); the same marks.
  static GridRect mark(const SensorView& view, const LayerGrids& map, double tolerance_px,
                       DenseGrid& marks, double max_depth_m = 1e300,
                       const ParallelFor* pool = nullptr);

  /// The verdict of one frame on one cell: kHoleSeen, kSeenWhole or 0 (none). The cell
  /// spans [x0, x1] x [y0, y1] at height z (W).
  static float test_cell(const SensorView& view, double x0, double x1, double y0, double y1,
                         double z, double tolerance_px, double max_depth_m = 1e300);
};

}  // namespace hazmap

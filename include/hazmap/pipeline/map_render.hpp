#pragma once
// Map grids as PNG panels a person can read at any size: the map (each cell k x k
// pixels), a footer naming it ("L0 1 cm kalman hazard", its extent in metres) with a
// metric scale bar, text scaled with the image, and the robot as a hollow ring with a
// heading tick so the cells under it stay visible, and an axis glyph in the map's corner
// (W's x and y: maps are axis-aligned with W and drawn north-up). Height panels colour a
// robust percentile range (one wild cell would squash the rest into one colour) and print
// both that range and the full one.

#include <limits>
#include <string>

#include <opencv2/core.hpp>

#include "hazmap/map/dense_grid.hpp"
#include "hazmap/map/height_range.hpp"

namespace hazmap {

/// Where the robot is drawn: position in W, heading (yaw about z) or NaN for none.
struct RobotMarker {
  double x_m = 0.0;
  double y_m = 0.0;
  double yaw_rad = std::numeric_limits<double>::quiet_NaN();
};

/// A scale-bar length for a panel `width_m` wide: the largest 1, 2 or 5 x 10^k metres
/// not longer than a quarter of it.
double scale_bar_length_m(double width_m);

/// The part of a map image of `map_size` pixels the axis glyph covers (its arrows, their
/// dark edges and the labels "x", "y"): the bottom-left corner. Outside it a panel's map
/// pixels are the cells' colours (and the robot marker).
cv::Rect axis_glyph_box(cv::Size map_size);

/// The side in pixels of the map part of a panel of `grid` (its longer side) as
/// render_hazard / render_height draw it for `min_size` and `max_size`.
int map_side_px(const DenseGrid& grid, int min_size, int max_size = 0);

/// Hazard palette panel (unknown 90,90,90; traversable 40,170,70; hazard 220,40,40 RGB),
/// cells k x k pixels with k the smallest whole number making the map >= min_size, then
/// the footer with `title`. `max_size` > 0: a grid of more cells than that a side is
/// shown f x f cells per pixel, each pixel the worst class of its cells (the mosaic).
/// `side_px` > 0 (at least map_side_px): the map part is side_px x side_px instead, the
/// cells k x k with the largest whole k that fits, centred on the panel's background (the
/// mosaic's panels of one size).
cv::Mat render_hazard(const DenseGrid& hazard, int min_size, const RobotMarker& robot,
                      const std::string& title, int max_size = 0, int side_px = 0);

/// Height panel in viridis over robust_height_range(clip_pct), unknown grey, a labelled
/// colour bar to the right, the footer below; `max_size` and `side_px` as for
/// render_hazard, each pixel the mean of its known cells.
cv::Mat render_height(const DenseGrid& height, int min_size, const RobotMarker& robot,
                      const std::string& title, double clip_pct, int max_size = 0,
                      int side_px = 0);

}  // namespace hazmap

#pragma once
// Ground-truth grids (SPEC 9, 10): gt_height.jdem holds the surface height at each cell
// centre, gt_hazard.jdem the obstacle height above the local ground there. One layout and
// one obstacle definition for both producers, `hazmap simulate` (analytic terrain, whose
// ground is known) and `hazmap ground-truth` (a scanned cloud, whose ground is estimated:
// eval/cloud_ground_truth.hpp), so `hazmap evaluate` scores against the same quantity.

#include <cmath>
#include <string>

#include <Eigen/Core>

#include "hazmap/io/jdem.hpp"

namespace hazmap {

/// The obstacle height gt_hazard stores: how far the surface stands above the local
/// ground, never negative (a depression is ground, its depth shows in gt_height); NaN
/// where either is unknown.
inline double obstacle_height_m(double surface_m, double ground_m) {
  if (std::isnan(surface_m) || std::isnan(ground_m)) return std::nan("");
  return std::max(0.0, surface_m - ground_m);
}

/// A zero grid of `quantity` (units m, yaw 0) with rows x cols cells of `resolution_m`
/// centred on `center_W`. Throws Error on a non-positive resolution or size.
JdemGrid ground_truth_grid(const std::string& quantity, double resolution_m,
                           const Eigen::Vector2d& center_W, int rows, int cols);

/// The smallest grid with an even number of rows and columns whose cell borders lie on
/// multiples of the resolution (SPEC 1) and that covers [x0, x1] x [y0, y1].
JdemGrid aligned_ground_truth_grid(const std::string& quantity, double x0_m, double x1_m,
                                   double y0_m, double y1_m, double resolution_m);

/// W position of the centre of cell (row, col) (row 0 = largest y, column 0 = smallest x).
inline Eigen::Vector2d cell_center_W(const JdemGrid& grid, int row, int col) {
  return {grid.center_x_m + (col - 0.5 * (grid.cols - 1)) * grid.resolution_m,
          grid.center_y_m + (0.5 * (grid.rows - 1) - row) * grid.resolution_m};
}

/// Calls f(row, col, x_m, y_m) for every cell centre, row by row.
template <class F>
void for_each_cell_center(const JdemGrid& grid, F&& f) {
  for (int row = 0; row < grid.rows; ++row) {
    const double y_m = grid.center_y_m + (0.5 * (grid.rows - 1) - row) * grid.resolution_m;
    for (int col = 0; col < grid.cols; ++col) {
      const double x_m = grid.center_x_m + (col - 0.5 * (grid.cols - 1)) * grid.resolution_m;
      f(row, col, x_m, y_m);
    }
  }
}

/// gt_hazard from a surface grid and a ground grid of the same layout: obstacle_height_m
/// per cell. Throws Error if the layouts differ.
JdemGrid obstacle_height_grid(const JdemGrid& surface, const JdemGrid& ground);

}  // namespace hazmap

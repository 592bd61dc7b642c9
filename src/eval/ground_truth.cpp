#include "hazmap/eval/ground_truth.hpp"

#include <cstdio>

#include "hazmap/core/error.hpp"

namespace hazmap {

JdemGrid ground_truth_grid(const std::string& quantity, double resolution_m,
                           const Eigen::Vector2d& center_W, int rows, int cols) {
  check(resolution_m > 0.0 && std::isfinite(resolution_m),
        "ground truth: resolution must be positive");
  check(rows > 0 && cols > 0, "ground truth: rows and cols must be positive");
  JdemGrid grid;
  grid.quantity = quantity;
  grid.units = "m";
  grid.rows = rows;
  grid.cols = cols;
  grid.resolution_m = resolution_m;
  grid.center_x_m = center_W.x();
  grid.center_y_m = center_W.y();
  grid.yaw_rad = 0.0;
  grid.values.assign(static_cast<std::size_t>(rows) * static_cast<std::size_t>(cols), 0.0f);
  return grid;
}

JdemGrid aligned_ground_truth_grid(const std::string& quantity, double x0_m, double x1_m,
                                   double y0_m, double y1_m, double resolution_m) {
  check(resolution_m > 0.0 && std::isfinite(resolution_m),
        "ground truth: resolution must be positive");
  auto axis = [&](double lo, double hi, double& center, int& cells) {
    // The 1e-9 slack keeps -0.3 / 0.01 = -29.999999999999996 on lattice line -30.
    const double first = std::floor(lo / resolution_m + 1e-9);
    const double count = std::ceil(hi / resolution_m - 1e-9) - first;
    check(count < 2e9, "ground truth: the grid would have more than 2e9 cells along an axis");
    cells = std::max(1, static_cast<int>(count));
    cells += cells % 2;
    center = (first + 0.5 * cells) * resolution_m;
  };
  Eigen::Vector2d center;
  int rows = 0, cols = 0;  // each < 2e9: fits an int
  axis(x0_m, x1_m, center.x(), cols);
  axis(y0_m, y1_m, center.y(), rows);
  // Checked before allocating: one stray point far away must not ask for terabytes.
  if (static_cast<double>(rows) * cols > 4e8) {
    char cells[32];
    std::snprintf(cells, sizeof cells, "%.3g", static_cast<double>(rows) * cols);
    throw Error(std::string("ground truth: the grid would have ") + cells +
                " cells (more than 4e8): crop the area or use a coarser resolution");
  }
  return ground_truth_grid(quantity, resolution_m, center, rows, cols);
}

JdemGrid obstacle_height_grid(const JdemGrid& surface, const JdemGrid& ground) {
  check(surface.rows == ground.rows && surface.cols == ground.cols &&
            surface.resolution_m == ground.resolution_m &&
            surface.center_x_m == ground.center_x_m && surface.center_y_m == ground.center_y_m,
        "ground truth: surface and ground grids differ in layout");
  JdemGrid hazard = surface;
  hazard.quantity = "hazard";
  for (std::size_t i = 0; i < hazard.values.size(); ++i)
    hazard.values[i] = static_cast<float>(obstacle_height_m(surface.values[i], ground.values[i]));
  return hazard;
}

}  // namespace hazmap

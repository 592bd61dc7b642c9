#pragma once
// A plain, axis-aligned grid of floats in image order: row 0 holds the largest y,
// column 0 the smallest x (the JDEM and PNG layout). Layers export their ring buffers
// into dense grids for hazard analysis and output.

#include <cmath>
#include <vector>

namespace hazmap {

struct DenseGrid {
  int rows = 0;
  int cols = 0;
  double resolution_m = 0.0;
  double center_x_m = 0.0;  ///< W coordinates of the grid's geometric centre
  double center_y_m = 0.0;
  std::vector<float> values;  ///< row-major; NaN = unknown

  /// Sets geometry and fills with `fill`, reusing the buffer.
  void reset(int rows_, int cols_, double resolution, double cx, double cy, float fill) {
    rows = rows_;
    cols = cols_;
    resolution_m = resolution;
    center_x_m = cx;
    center_y_m = cy;
    values.assign(static_cast<size_t>(rows) * cols, fill);
  }
  float& at(int row, int col) { return values[static_cast<size_t>(row) * cols + col]; }
  float at(int row, int col) const { return values[static_cast<size_t>(row) * cols + col]; }

  /// W x of the centre of column `col`, W y of the centre of row `row`.
  double x_of_col(int col) const { return center_x_m + (col + 0.5 - cols / 2.0) * resolution_m; }
  double y_of_row(int row) const { return center_y_m + (rows / 2.0 - row - 0.5) * resolution_m; }

  /// Cell holding W point (x, y); false when outside the grid.
  bool cell_at(double x_m, double y_m, int* row, int* col) const {
    const double c = std::floor((x_m - center_x_m) / resolution_m + cols / 2.0);
    const double r = std::floor((center_y_m - y_m) / resolution_m + rows / 2.0);
    if (c < 0 || r < 0 || c >= cols || r >= rows) return false;
    *row = static_cast<int>(r);
    *col = static_cast<int>(c);
    return true;
  }
};

/// Ternary hazard classes, as stored in hazard JDEM files (SPEC 9).
enum class HazardClass : unsigned char { unknown = 0, traversable = 1, hazard = 2 };

}  // namespace hazmap

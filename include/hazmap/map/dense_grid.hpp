#pragma once
// A plain, axis-aligned grid of floats in image order: row 0 holds the largest y,
// column 0 the smallest x (the JDEM and PNG layout). Layers export their ring buffers
// into dense grids for hazard analysis and output.

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <cstring>
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
  /// Moves the values by whole cells, value(row, col) = old value(row + drow, col + dcol),
  /// with `fill` where that lies outside: a rolling window's export keeps the cells that
  /// stayed in the window (each at its new place) when it moves. No allocation.
  void shift(int drow, int dcol, float fill) {
    if (drow == 0 && dcol == 0) return;
    if (std::abs(drow) >= rows || std::abs(dcol) >= cols) {
      std::fill(values.begin(), values.end(), fill);
      return;
    }
    const int width = cols - std::abs(dcol);
    const int src_col = std::max(dcol, 0), dst_col = std::max(-dcol, 0);
    // Rows in the order that never overwrites a source row before it is read.
    for (int k = 0; k < rows; ++k) {
      const int row = drow >= 0 ? k : rows - 1 - k;
      float* dst = &values[static_cast<size_t>(row) * cols];
      const int src_row = row + drow;
      if (src_row < 0 || src_row >= rows) {
        std::fill(dst, dst + cols, fill);
        continue;
      }
      std::memmove(dst + dst_col, &values[static_cast<size_t>(src_row) * cols] + src_col,
                   static_cast<size_t>(width) * sizeof(float));
      std::fill(dst, dst + dst_col, fill);
      std::fill(dst + dst_col + width, dst + cols, fill);
    }
  }
  /// Sets the cells of rows [row0, row1) x columns [col0, col1) to `v`.
  void fill_rect(int row0, int row1, int col0, int col1, float v) {
    for (int row = row0; row < row1; ++row)
      std::fill(&values[static_cast<size_t>(row) * cols + col0],
                &values[static_cast<size_t>(row) * cols + col1], v);
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

#pragma once
// A rectangle of cells of a dense grid (image order, dense_grid.hpp), half-open:
// rows [row0, row1) x columns [col0, col1). The unit of partial work on a grid: a layer
// exports, and a classifier classifies, the cells of a rectangle only (SPEC 8.6).

#include <algorithm>

namespace hazmap {

struct GridRect {
  int row0 = 0, row1 = 0, col0 = 0, col1 = 0;

  static GridRect full(int rows, int cols) { return {0, rows, 0, cols}; }

  bool empty() const { return row0 >= row1 || col0 >= col1; }
  long area() const { return empty() ? 0 : long(row1 - row0) * long(col1 - col0); }
  bool contains(int row, int col) const {
    return row >= row0 && row < row1 && col >= col0 && col < col1;
  }
  /// Grown by `cells` on every side (not clipped); an empty rectangle stays empty.
  GridRect dilated(int cells) const {
    if (empty()) return *this;
    return {row0 - cells, row1 + cells, col0 - cells, col1 + cells};
  }
  /// Cut to a rows x cols grid.
  GridRect clipped(int rows, int cols) const {
    return {std::max(row0, 0), std::min(row1, rows), std::max(col0, 0), std::min(col1, cols)};
  }
  bool intersects(const GridRect& o) const {
    return !empty() && !o.empty() && row0 < o.row1 && o.row0 < row1 && col0 < o.col1 && o.col0 < col1;
  }
  /// The smallest rectangle holding both (an empty one adds nothing).
  GridRect hull(const GridRect& o) const {
    if (empty()) return o;
    if (o.empty()) return *this;
    return {std::min(row0, o.row0), std::max(row1, o.row1), std::min(col0, o.col0),
            std::max(col1, o.col1)};
  }
  bool operator==(const GridRect& o) const {
    return row0 == o.row0 && row1 == o.row1 && col0 == o.col0 && col1 == o.col1;
  }
};

}  // namespace hazmap

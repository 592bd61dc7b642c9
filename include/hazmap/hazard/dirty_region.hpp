#pragma once
// The cells of a grid that one frame must recompute (SPEC 8.6), as a few disjoint
// rectangles: what insertion touched, the strips the rolling window gained or lost, each
// grown by how far a result reads. Rectangles that overlap are merged into their hull,
// so a cell is recomputed at most once; the hull may add cells, which only costs time
// (recomputing a cell whose inputs did not change gives the same result). Fixed
// capacity: no allocation.

#include <array>

#include "hazmap/map/grid_rect.hpp"

namespace hazmap {

class DirtyRegion {
 public:
  /// A frame adds at most: insertion, two entered and two left strips per grid, and the
  /// changed cells of each contributing layer; beyond this, rectangles merge.
  static constexpr int kCapacity = 16;

  void clear() { count_ = 0; }
  /// Adds `r` (ignored when empty), merging it with every rectangle it overlaps; when
  /// full, with the rectangle whose hull grows least.
  void add(GridRect r);

  bool empty() const { return count_ == 0; }
  int size() const { return count_; }
  const GridRect& operator[](int i) const { return rects_[static_cast<std::size_t>(i)]; }
  const GridRect* begin() const { return rects_.data(); }
  const GridRect* end() const { return rects_.data() + count_; }
  /// Cells covered (the rectangles are disjoint).
  long area() const;
  bool contains(int row, int col) const;
  /// Each rectangle grown by `cells` and cut to rows x cols (re-merged).
  void dilate(int cells, int rows, int cols);
  /// The smallest rectangle holding every rectangle.
  GridRect bounds() const;

 private:
  std::array<GridRect, kCapacity> rects_{};
  int count_ = 0;
};

}  // namespace hazmap

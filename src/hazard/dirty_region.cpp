#include "hazmap/hazard/dirty_region.hpp"

namespace hazmap {

void DirtyRegion::add(GridRect r) {
  if (r.empty()) return;
  // Absorb every rectangle r overlaps; the hull may then overlap others: repeat.
  for (bool merged = true; merged;) {
    merged = false;
    for (int i = 0; i < count_; ++i) {
      if (!r.intersects(rects_[i])) continue;
      r = r.hull(rects_[i]);
      rects_[i] = rects_[--count_];
      merged = true;
      break;
    }
  }
  if (count_ < kCapacity) {
    rects_[count_++] = r;
    return;
  }
  int best = 0;
  long growth = -1;
  for (int i = 0; i < count_; ++i) {
    const long g = rects_[i].hull(r).area() - rects_[i].area();
    if (growth < 0 || g < growth) best = i, growth = g;
  }
  const GridRect h = rects_[best].hull(r);
  rects_[best] = rects_[--count_];
  add(h);
}

long DirtyRegion::area() const {
  long a = 0;
  for (const GridRect& r : *this) a += r.area();
  return a;
}

bool DirtyRegion::contains(int row, int col) const {
  for (const GridRect& r : *this)
    if (r.contains(row, col)) return true;
  return false;
}

void DirtyRegion::dilate(int cells, int rows, int cols) {
  std::array<GridRect, kCapacity> old = rects_;
  const int n = count_;
  count_ = 0;
  for (int i = 0; i < n; ++i) add(old[i].dilated(cells).clipped(rows, cols));
}

GridRect DirtyRegion::bounds() const {
  GridRect b;
  for (const GridRect& r : *this) b = b.hull(r);
  return b;
}

}  // namespace hazmap

#pragma once
// Internal to LayerStack: not part of the hazmap API.
// The horizontal bounding box of a frame's points (LayerStack::changed_cells), grown
// chunk by chunk inside the insertion loop, while the chunk is in cache for the layers.

#include <limits>

namespace hazmap {

struct PointBounds {
  float lo_x = std::numeric_limits<float>::infinity(), hi_x = -lo_x;
  float lo_y = lo_x, hi_y = hi_x;

  /// Grows the box by points [0, n) of x, y. A NaN coordinate leaves its bound as it
  /// was, as in `lo = std::min(lo, x)`, point after point (what this computes, in vector
  /// lanes: a minimum of non-NaN numbers does not depend on the order it is taken in).
  void extend(const float* x, const float* y, int n);
};

}  // namespace hazmap

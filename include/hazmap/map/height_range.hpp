#pragma once
// The range a height grid is coloured over: a robust percentile range of its known cells
// (one wild cell must not squash the rest into one colour) and the full one. Shared by the
// PNG panels (pipeline/map_render.hpp) and the run viewer (eval/run_viewer.hpp).

#include "hazmap/map/dense_grid.hpp"

namespace hazmap {

/// Colour range of a height panel.
struct HeightRange {
  bool any = false;        ///< some cell is known
  double lo = 0, hi = 0;   ///< coloured range: percentiles clip_pct and 100 - clip_pct
  double min = 0, max = 0; ///< all known cells
};

/// The known cells' range; `clip_pct` in [0, 50) cut from each end (0: min and max).
HeightRange robust_height_range(const DenseGrid& height, double clip_pct);

}  // namespace hazmap

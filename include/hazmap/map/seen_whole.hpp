#pragma once
// Cells of a CCM layer that a disparity image saw whole, without a hole (issue 34): the
// hazard stage's marks (hazard/hole_marker.hpp), read by the layer's export. A cell whose
// points spread over less than rules.ccm.min_coverage of it is still given its plane, for
// its own tests, when the spread reaches `min_coverage` here and some frame saw every
// quarter of the cell: its points are then as dense as the pixels over it allow, and no
// part of it (a rock's shadow, ground a rock hid, a face without texture) went unmeasured.

#include "hazmap/map/dense_grid.hpp"

namespace hazmap {

/// A mark's values: no verdict yet (0), seen whole at some frame, or a hole seen in it
/// (final: no pixel over a quarter of the cell had a disparity, at some frame).
constexpr float kSeenWhole = 1.0f;
constexpr float kHoleSeen = 2.0f;

/// LayerGrids::evaluable of a cell whose plane comes from the mark alone: it classifies
/// the cell itself but is no wheel-ring sample for others (nor their nearest plane). A
/// plane over part of a cell is a weaker guess elsewhere, and measured under low sun,
/// rings completed by such planes proved a rock's rim cell (docs/hazards.md).
constexpr float kEvaluableOwnCell = 0.5f;

struct SeenWhole {
  const DenseGrid* marks = nullptr;  ///< the layer's window, image order
  double min_coverage = 1.0;         ///< kappa a marked cell needs (map.layers.N.hole_free_coverage)
  int min_points = 10;               ///< points it needs (rules.ccm.min_points)

  /// Whether cell (row, col) has a plane by the mark: it was seen whole, without a hole
  /// since, with this coverage and point count.
  bool by_mark(int row, int col, double coverage, double count) const {
    return marks->at(row, col) == kSeenWhole && coverage >= min_coverage && count >= min_points;
  }
};

}  // namespace hazmap

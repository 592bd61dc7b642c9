#pragma once
// Cells of a CCM layer without a hole (issue 34): the hazard stage's marks of cells a
// disparity image saw whole (hazard/hole_marker.hpp), and the rule's own occupancy mask,
// read by the layer's export. A cell whose points spread over less than
// rules.ccm.min_coverage of it is still given its plane, for its own tests, when the
// spread reaches `min_coverage` here and either some frame saw every quarter of the cell
// or its points have landed in every one of its 4 x 4 sub-cells: no part of it (a rock's
// shadow, ground a rock hid, a face without texture) went unmeasured, and its points are
// only denser in some parts than in others (the near rows of a frame weigh more; pixel
// rows cross a cell unevenly). Measured: such cells had points in all 16 sub-cells and a
// spread of 0.69-0.80 (docs/hazards.md).

#include <cstdint>

#include "hazmap/map/dense_grid.hpp"
#include "hazmap/map/moments.hpp"

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

  /// Whether cell (row, col) has a plane without a hole, with this coverage and point
  /// count: a frame saw it whole (its mark, no hole seen since), or its points have
  /// filled every sixteenth of it (`occupied`, the rule's 4 x 4 occupancy mask: all set).
  bool hole_free(int row, int col, double coverage, double count, std::uint16_t occupied) const {
    return (marks->at(row, col) == kSeenWhole || occupied == kAllOccupied) &&
           coverage >= min_coverage && count >= min_points;
  }
};

}  // namespace hazmap

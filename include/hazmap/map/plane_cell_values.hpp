#pragma once
// What a plane cell publishes beside its plane (SPEC 6.4): the values a rule with kHasPlane
// hands the layer for the count, noise and lateral grids of LayerGrids (map/layer.hpp), so
// that the layer names no rule's cell fields (rules/update_rule.hpp: cell_values).

namespace hazmap {

struct PlaneCellValues {
  float count;           ///< points behind the cell
  float noise_variance;  ///< mean measurement height variance of its points [m^2]
  float lateral_xx, lateral_yy, lateral_xy;  ///< lateral covariance S/W [m^2]
  float lateral_xz, lateral_yz;              ///< lateral-height covariance S/W [m^2]
};

}  // namespace hazmap

#pragma once
// Hazards of a CCM layer (SPEC 8.2). Only evaluable cells are classified; the others are
// unknown. An evaluable cell is a hazard when
//   - its roughness (plane-normal variance) exceeds rho_max: a sub-cell obstacle
//     (a step of h_min covering 9 % to 91 % of the cell when rho_max = h_min^2 / 16);
//   - its plane is steeper than atan(h_min / r): a rock face filling the cell;
//   - the vehicle would tilt more than max_slope: for cells smaller than the wheelbase,
//     a plane fitted to the sub-cell heights at 8 points on a circle of radius
//     wheelbase / 2 around the cell centre (unknown if a sample lands in an unknown or
//     unevaluable cell); for larger cells, the cell's own inclination.

#include "hazmap/map/dense_grid.hpp"
#include "hazmap/map/layer.hpp"

namespace hazmap {

struct CcmHazardParams {
  double rho_max_m2 = 5.6e-5;       ///< roughness threshold
  double max_face_rad = 0.9;        ///< atan(h_min / r)
  double max_slope_rad = 0.349;     ///< vehicle slope limit (20 deg)
  double wheelbase_m = 0.30;
};

/// Parameters for a layer of resolution r from h_min (rho_max = h_min^2/16 unless given).
CcmHazardParams ccm_hazard_params(double resolution_m, double h_min_m, double rho_max_m2,
                                  double max_slope_deg, double wheelbase_m);

/// Classifies every cell of `grids` (a CCM layer's export) into `hazard` (HazardClass).
void classify_ccm(const LayerGrids& grids, const CcmHazardParams& params, DenseGrid& hazard);

/// Sub-cell height of the layer's plane surface at W point (x, y); NaN when the cell is
/// outside the grid or not evaluable.
double ccm_surface_height(const LayerGrids& grids, double x_m, double y_m);

}  // namespace hazmap

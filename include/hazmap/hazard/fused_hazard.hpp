#pragma once
// Fused hazard map (SPEC 8.3): on the finest layer's grid, a cell is a hazard where any
// layer covering its centre says hazard, traversable where some layer knows it and none
// says hazard, and unknown otherwise.

#include <vector>

#include "hazmap/map/dense_grid.hpp"

namespace hazmap {

/// `layers` finest first (values 0/1/2 as HazardClass); `fused` gets layers[0]'s geometry.
void fuse_hazards(const std::vector<const DenseGrid*>& layers, DenseGrid& fused);

}  // namespace hazmap

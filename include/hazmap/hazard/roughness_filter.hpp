#pragma once
// Roughness hazards for piecewise-constant layers (SPEC 8.1). Over a circular kernel of
// diameter D cells around each cell, roughness = max - min of the observed heights; the
// cell is a hazard when roughness > threshold. Unknown when the cell is unobserved, the
// kernel leaves the grid, or fewer than min_fill of the kernel's cells are observed.
//
// The fast path runs sliding-window min/max along rows (one pass per distinct
// half-width of the circle) and combines D rows per cell: O(cells * D), not O(cells * D^2).

#include <vector>

#include "hazmap/map/dense_grid.hpp"

namespace hazmap {

struct RoughnessParams {
  int kernel = 5;                   ///< diameter D in cells, odd
  double threshold_m = 0.025;       ///< hazard when max - min > threshold
  double min_fill = 0.5;            ///< fraction of kernel cells that must be observed
};

/// Half-widths of the circular kernel: row offset dy in [-(D-1)/2, (D-1)/2] spans
/// columns [-w, w] with w = floor(sqrt((D/2)^2 - dy^2)); index dy + (D-1)/2.
std::vector<int> kernel_half_widths(int kernel);

/// Per-cell roughness (max - min of observed heights in the kernel; NaN where the kernel
/// leaves the grid or holds no observed cell) and fill fraction, fast path.
class RoughnessFilter {
 public:
  /// Computes into `roughness` and `fill` (same geometry as `height`), reusing buffers.
  void compute(const DenseGrid& height, int kernel, DenseGrid& roughness, DenseGrid& fill);

 private:
  std::vector<float> row_max_, row_min_, row_count_;
  std::vector<int> deque_;
  int kernel_ = -1;            ///< kernel of the cached widths
  std::vector<int> widths_;    ///< kernel_half_widths(kernel_)
  std::vector<unsigned char> width_used_;
};

/// Brute-force O(cells * D^2) reference of RoughnessFilter::compute.
void roughness_brute_force(const DenseGrid& height, int kernel, DenseGrid& roughness,
                           DenseGrid& fill);

/// Classifies cells (values 0 unknown, 1 traversable, 2 hazard) from height, roughness
/// and fill grids.
void classify_roughness(const DenseGrid& height, const DenseGrid& roughness,
                        const DenseGrid& fill, const RoughnessParams& params, DenseGrid& hazard);

}  // namespace hazmap

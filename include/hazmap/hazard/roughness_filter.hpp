#pragma once
// Roughness of piecewise-constant layers (SPEC 8.1): over a circular kernel of diameter D
// cells around each cell, roughness = max - min of the observed heights, with standard
// deviation sqrt(var(max cell) + var(min cell)).
//
// The fast path runs sliding-window min/max along rows (one pass per distinct
// half-width of the circle) and combines D rows per cell: O(cells * D), not O(cells * D^2).

#include <vector>

#include "hazmap/map/dense_grid.hpp"
#include "hazmap/map/grid_rect.hpp"

namespace hazmap {

/// Half-widths of the circular kernel: row offset dy in [-(D-1)/2, (D-1)/2] spans
/// columns [-w, w] with w = floor(sqrt((D/2)^2 - dy^2)); index dy + (D-1)/2.
std::vector<int> kernel_half_widths(int kernel);

/// Per-cell roughness (max - min of observed heights in the kernel; NaN where the kernel
/// leaves the grid or holds no observed cell), its standard deviation, and the observed
/// fraction of the kernel.
class RoughnessFilter {
 public:
  /// Computes into `roughness`, `sigma` and `fill` (geometry of `height`; `variance` holds
  /// the cells' height variances), reusing buffers.
  void compute(const DenseGrid& height, const DenseGrid& variance, int kernel,
               DenseGrid& roughness, DenseGrid& sigma, DenseGrid& fill);
  /// The same for the cells of `region` only (SPEC 8.6), reading the rows and columns the
  /// kernel reaches around it; the outputs must have `height`'s geometry already and keep
  /// their other cells. Equal, cell for cell, to the whole-grid computation.
  void compute(const DenseGrid& height, const DenseGrid& variance, int kernel,
               const GridRect& region, DenseGrid& roughness, DenseGrid& sigma, DenseGrid& fill);

 private:
  std::vector<float> row_max_, row_min_, row_count_, row_max_var_, row_min_var_;
  std::vector<int> deque_;
  int kernel_ = -1;            ///< kernel of the cached widths
  std::vector<int> widths_;    ///< kernel_half_widths(kernel_)
  std::vector<unsigned char> width_used_;
};

/// Brute-force O(cells * D^2) reference of RoughnessFilter::compute.
void roughness_brute_force(const DenseGrid& height, const DenseGrid& variance, int kernel,
                           DenseGrid& roughness, DenseGrid& sigma, DenseGrid& fill);

}  // namespace hazmap

#pragma once
// Roughness of piecewise-constant layers (SPEC 8.1): over a circular kernel of diameter D
// cells around each cell, roughness = max - min of the observed heights, with standard
// deviation sqrt(var(max cell) + var(min cell)).
//
// The fast path runs sliding-window min/max along rows (one pass per distinct
// half-width of the circle) and combines D rows per cell: O(cells * D), not O(cells * D^2).
//
// Detrended (hazard.roughness: detrended; ours): max - min of the residuals from the
// least-squares plane through the kernel's observed cells, so that a slope, which the
// wheel ring tests over the wheelbase, does not eat the margin a 6-cell baseline leaves
// for noise (measured: on a 15 deg ramp the 1 cm range of 1.6 cm left 0.6 cm below the
// 20 deg threshold, less than the noise of 37 cells). O(cells * D^2).

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
  /// Residuals from the kernel's plane instead of raw heights (see above).
  void set_detrended(bool detrended) { detrended_ = detrended; }
  bool detrended() const { return detrended_; }
  /// Computes into `roughness`, `sigma` and `fill` (geometry of `height`; `variance` holds
  /// the cells' height variances), reusing buffers.
  /// Detrended: `slope` and `slope_sigma` (if given) receive tan of the kernel plane's
  /// inclination and its standard deviation (NaN where it has none).
  void compute(const DenseGrid& height, const DenseGrid& variance, int kernel,
               DenseGrid& roughness, DenseGrid& sigma, DenseGrid& fill,
               DenseGrid* slope = nullptr, DenseGrid* slope_sigma = nullptr);
  /// The same for the cells of `region` only (SPEC 8.6), reading the rows and columns the
  /// kernel reaches around it; the outputs must have `height`'s geometry already and keep
  /// their other cells. Equal, cell for cell, to the whole-grid computation.
  void compute(const DenseGrid& height, const DenseGrid& variance, int kernel,
               const GridRect& region, DenseGrid& roughness, DenseGrid& sigma, DenseGrid& fill,
               DenseGrid* slope = nullptr, DenseGrid* slope_sigma = nullptr);

 private:
  void compute_detrended(const DenseGrid& height, const DenseGrid& variance, const GridRect& out,
                         DenseGrid& roughness, DenseGrid& sigma, DenseGrid& fill,
                         DenseGrid* slope, DenseGrid* slope_sigma);

  bool detrended_ = false;
  std::vector<float> row_max_, row_min_, row_count_, row_max_var_, row_min_var_;
  std::vector<int> deque_;
  std::vector<int> kdx_, kdy_;
  std::vector<float> kz_, kvar_;
  int kernel_ = -1;            ///< kernel of the cached widths
  std::vector<int> widths_;    ///< kernel_half_widths(kernel_)
  std::vector<unsigned char> width_used_;
};

/// Brute-force O(cells * D^2) reference of RoughnessFilter::compute (range).
void roughness_brute_force(const DenseGrid& height, const DenseGrid& variance, int kernel,
                           DenseGrid& roughness, DenseGrid& sigma, DenseGrid& fill);

/// Least-squares plane z = a + b dx + c dy through n points (dx, dy in any unit), the
/// minimum-norm solution where they are collinear (a line along them) or coincide (their
/// mean). Returns (a, b, c) at dx = dy = 0.
struct KernelPlane {
  double a = 0, b = 0, c = 0;
  /// Per unit height variance of the cells: the variance of the inclination tan,
  /// trace((sum u u^T)^-1) (an upper bound on the variance of |(b, c)|) on a plane, the
  /// inverse scatter along a line; infinity where there is no slope to know.
  double slope_variance_factor = 0;
};
KernelPlane fit_kernel_plane(const int* dx, const int* dy, const float* z, int n);

}  // namespace hazmap

#pragma once
// One hazard classifier per layer, chosen once from the layer's rule family (SPEC 8):
// piecewise-constant layers (Bananas, Kalman, OMG) by their roughness kernel
// (kernel_classifier.hpp), CCM layers by their planes (plane_classifier.hpp); both add
// the wheel ring's tests on layers finer than the wheelbase. A family runs a list of
// hazard tests on each cell (hazard_test.hpp); every test follows Evidence's rule
// (evidence.hpp).

#include <cmath>
#include <limits>
#include <memory>

#include "hazmap/core/parallel_for.hpp"
#include "hazmap/hazard/hazard_params.hpp"
#include "hazmap/hazard/sensor_view.hpp"
#include "hazmap/hazard/wheel_ring.hpp"
#include "hazmap/map/layer.hpp"

namespace hazmap {

/// Intermediate grids a classifier leaves for output and inspection.
struct HazardDiagnostics {
  DenseGrid kernel_range;  ///< piecewise constant: max - min in the kernel [m]
  DenseGrid kernel_sigma;  ///< its standard deviation [m]
  DenseGrid kernel_fill;   ///< observed fraction of the kernel
  /// Detrended kernels only (empty otherwise): tan of the kernel plane's inclination and
  /// its standard deviation.
  DenseGrid kernel_slope;
  DenseGrid kernel_slope_sigma;
};

/// Where a wheel-ring sample comes from when the layer has not measured its point
/// (hazard.coarse_ring_fill): a coarser layer's surface (CoarseRingFill).
class RingFallback {
 public:
  virtual ~RingFallback() = default;
  /// The terrain at W point (x, y), or an unknown sample.
  virtual RingSample at(double x_m, double y_m) const = 0;
};

class HazardClassifier {
 public:
  explicit HazardClassifier(const LayerHazardParams& params)
      : params_(params), ring_(params.wheelbase_m / 2.0, params.k_sigma, params.partial_ring_proof) {}
  virtual ~HazardClassifier() = default;

  /// Classifies every cell of `grids` (a layer's export) into `hazard` (HazardClass),
  /// giving `hazard` and the diagnostics the layer's geometry.
  void classify(const LayerGrids& grids, DenseGrid& hazard, HazardDiagnostics& diagnostics);

  /// Classifies the cells of `region` only (SPEC 8.6) and leaves every other cell as it
  /// is. `hazard` and the diagnostics must have the layer's geometry already: an earlier
  /// classification of this window, shifted with it (DenseGrid::shift). A cell's result
  /// is the same as in a whole-layer classification.
  virtual void classify(const LayerGrids& grids, const GridRect& region, DenseGrid& hazard,
                        HazardDiagnostics& diagnostics) = 0;

  /// How far a cell's result reads, in cells along rows and columns (kernel, wheel ring):
  /// it can change only where a cell at most this far away changed (SPEC 8.6).
  virtual int reach_cells() const = 0;

  const LayerHazardParams& params() const { return params_; }

  /// Ring samples this layer has not measured are asked of `fallback` (null: none). The
  /// fallback must outlive the classifier's use and read the same frame's map.
  void set_ring_fallback(const RingFallback* fallback) { fallback_ = fallback; }

  /// The layer's view mask (ViewMarker: how much of each cell the stereo pair has
  /// looked at), for hazard.partial_ring_proof: view_edge; null: every cell wholly viewed.
  /// Must outlive the classifier's use.
  void set_view_mask(const DenseGrid* viewed) { viewed_ = viewed; }

  /// hazard.footprint_centre_ring: classify() also writes into `ring_only` (the layer's
  /// geometry, kept beside `hazard` and moved with it) 1 where a cell is unknown only
  /// because its wheel ring lacked samples, 0 elsewhere; null: nothing. Must outlive the
  /// classifier's use.
  void set_ring_only(DenseGrid* ring_only) { ring_only_ = ring_only; }

  /// classify() may split a region's rows over `pool`'s threads (null: this thread); a
  /// cell's result is the same either way. Call before classifying (it sizes scratch).
  virtual void set_parallel(const ParallelFor* pool) { pool_ = pool; }

  /// A diagnostic pass (issue 34; `output.unknown_reasons`, for `hazmap evaluate`): a
  /// whole-layer classification of `grids` that writes into `reasons` (given the layer's
  /// geometry) the UnknownReason bits of each unknown cell, 0 at known cells. Separate
  /// from classify() so that the per-frame path writes no such grid; it allocates.
  void explain(const LayerGrids& grids, DenseGrid& reasons);

 protected:
  /// Records a cell's reasons when explain() asked for them.
  /// And whether only the ring kept it unknown (set_ring_only), which a family may
  /// narrow (`ring_only_ok`: its own check of the cell against its neighbours).
  void record(int row, int col, const Evidence& ev, bool ring_only_ok = true) {
    if (reasons_) reasons_->at(row, col) = ev.result() == HazardClass::unknown ? ev.reasons() : 0;
    if (ring_only_)
      ring_only_->at(row, col) = ring_only_ok && unknown_for_ring_only(ev) ? 1.0f : 0.0f;
  }
  void record(int row, int col, std::uint16_t reasons) {
    if (reasons_) reasons_->at(row, col) = reasons;
    if (ring_only_) ring_only_->at(row, col) = 0.0f;
  }
  static bool unknown_for_ring_only(const Evidence& ev) {
    return ev.result() == HazardClass::unknown && ev.reasons() == kReasonRingIncomplete;
  }
  bool wants_ring_only() const { return ring_only_ != nullptr; }

  /// Gives the diagnostics the geometry of `height` before a whole-layer classification.
  virtual void reset_diagnostics(const DenseGrid& /*height*/, HazardDiagnostics& /*diag*/) const {}

  LayerHazardParams params_;
  WheelRing ring_;
  DenseGrid* reasons_ = nullptr;  ///< set during explain() only
  DenseGrid* ring_only_ = nullptr;  ///< set_ring_only()
  const RingFallback* fallback_ = nullptr;
  const DenseGrid* viewed_ = nullptr;
  const ParallelFor* pool_ = nullptr;
};

/// The classifier of the layer's family, with the family's shipped list of tests.
std::unique_ptr<HazardClassifier> make_hazard_classifier(const LayerHazardParams& params);

namespace detail {

/// True when (row, col) lies in `viewed` (a layer's view mask, or null) and no view has
/// covered it whole (sensor_view.hpp): a ring sample there that cannot prove is
/// RingSample::unseen.
inline bool outside_view(const DenseGrid* viewed, int row, int col) {
  return viewed != nullptr && row >= 0 && col >= 0 && row < viewed->rows && col < viewed->cols &&
         viewed->at(row, col) < kWhollyViewed;
}

/// The cell of the 3 x 3 block around (row, col), inside the grid, that `accept`s and
/// lies nearest by `distance2(r, c)` (the first of equals in row-major order); false if
/// none. Both families look there when a ring sample's own cell cannot serve.
template <class Accept, class Distance2>
bool nearest_in_3x3(const DenseGrid& grid, int row, int col, Accept accept, Distance2 distance2,
                    int* best_row, int* best_col) {
  double best = std::numeric_limits<double>::infinity();
  for (int r = row - 1; r <= row + 1; ++r)
    for (int c = col - 1; c <= col + 1; ++c) {
      if (r < 0 || c < 0 || r >= grid.rows || c >= grid.cols || !accept(r, c)) continue;
      const double d2 = distance2(r, c);
      if (d2 < best) {
        best = d2;
        *best_row = r;
        *best_col = c;
      }
    }
  return std::isfinite(best);
}

}  // namespace detail

}  // namespace hazmap

#pragma once
// hazard.coarse_ring_fill (issue 34): a fine layer's wheel ring often has holes where the
// fine layer has no points (its lateral gate, gaps between footprints), while the next
// coarser CCM layer measured the ground there. Such a sample is taken from that layer's
// plane, with its prediction variance plus the residual variance about it, and can then
// prove like any measured sample. A point no layer measured stays unknown: unlike the
// partial ring (hazard.partial_ring_proof) nothing is extrapolated over unseen ground,
// which under low sun is often the rock that hid it.

#include "hazmap/hazard/plane_classifier.hpp"

namespace hazmap {

class CoarseRingFill final : public RingFallback {
 public:
  /// `coarse`: the coarser layer's hazard parameters (its plane statistics' weighting).
  explicit CoarseRingFill(const LayerHazardParams& coarse) : surface_(coarse) {}

  /// The coarser layer's export for this frame (null: every sample unknown).
  void set_grids(const LayerGrids* grids) { grids_ = grids; }

  RingSample at(double x_m, double y_m) const override {
    return grids_ ? surface_.terrain_at(*grids_, x_m, y_m) : RingSample{};
  }

 private:
  PlaneSurface surface_;
  const LayerGrids* grids_ = nullptr;
};

}  // namespace hazmap

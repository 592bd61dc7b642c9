#pragma once
// The piecewise-constant family's own hazard tests (SPEC 8.1), on the roughness kernel's
// statistics of a cell (KernelCell, hazard_classifier.hpp). The list they run in is
// PiecewiseConstantTests; the shape of a test is in hazard_test.hpp.

#include <cmath>

#include "hazmap/hazard/hazard_test.hpp"

namespace hazmap {

/// Roughness: the kernel's height range against the roughness threshold. The kernel is
/// evidence even around an unobserved cell; proof needs the cell, the kernel's fill and
/// the whole kernel inside the layer. The range is the largest difference among the
/// kernel's observed cells, so its hazard side counts the cells it was picked from.
struct KernelRoughness {
  static bool enabled(const LayerHazardParams&) { return true; }
  explicit KernelRoughness(const LayerHazardParams& p)
      : threshold_m_(p.roughness_threshold_m), half_width_((p.kernel - 1) / 2) {}
  int reach_cells(const TestReach&) const { return half_width_; }

  template <class Cell>
  void add(const Cell& c, Evidence& ev) const {
    ev.why(std::isnan(c.z) ? kReasonNoHeight : kReasonKernelIncomplete, kReasonRoughnessMargin);
    ev.test(c.range(), c.range_sigma(), threshold_m_, c.kernel_complete, c.range_k);
  }

 private:
  double threshold_m_;
  int half_width_;
};

/// Detrended kernels (hazard.roughness = detrended): a kernel plane rising h_min within the
/// kernel's radius is a face, even on a partly seen kernel (measured: a partial ring
/// leaves rock faces unknown). Evidence only: slopes short of a face are the wheel ring's
/// to judge (RingSlope); against max_slope itself the 6-cell plane turned stereo noise on
/// ramps into hazards.
struct KernelFace {
  static bool enabled(const LayerHazardParams& p) { return p.detrended_roughness; }
  explicit KernelFace(const LayerHazardParams& p)
      : face_tan_(p.kernel_face_tan), half_width_((p.kernel - 1) / 2) {}
  int reach_cells(const TestReach&) const { return half_width_; }

  template <class Cell>
  void add(const Cell& c, Evidence& ev) const {
    ev.evidence(c.kernel_slope(), c.kernel_slope_sigma(), face_tan_);
  }

 private:
  double face_tan_;
  int half_width_;
};

}  // namespace hazmap

#pragma once
// The wheel ring's hazard tests (SPEC 8.2, 8.3), run by both families on layers finer
// than the wheelbase (LayerHazardParams::ring_tests). The samples come from the family's
// cell (`c.ring()`, read only when a test needs them), the tests themselves from
// WheelRing (wheel_ring.hpp). A cell already shown to be a hazard skips them: they could
// only add evidence to a settled result.

#include <cmath>

#include "hazmap/hazard/hazard_test.hpp"
#include "hazmap/hazard/wheel_ring.hpp"

namespace hazmap {

/// Vehicle slope: the ring plane's inclination against max_slope. Plane layers always run
/// it; piecewise-constant ones only with a detrended kernel (a range kernel judges slopes
/// itself, as part of its range).
struct RingSlope {
  static bool enabled(const LayerHazardParams& p) {
    return p.ring_tests && (p.family == HazardFamily::plane || p.detrended_roughness);
  }
  explicit RingSlope(const LayerHazardParams& p) : tan_slope_(std::tan(p.max_slope_rad)) {}
  int reach_cells(const TestReach& r) const { return r.ring_cells; }

  template <class Cell>
  void add(const Cell& c, Evidence& ev) const {
    if (ev.hazard()) return;
    if (std::isnan(c.z)) return ev.missing(kReasonNoHeight);
    c.wheel.slope_test(c.ring(), tan_slope_, ev);
  }

 private:
  double tan_slope_;
};

/// Step above the ring: the cell's height above the ring plane against h_min (sees rock
/// tops too flat and wide for a roughness test). The cell height's variance is the
/// family's (`c.step_variance()`).
struct RingStep {
  static bool enabled(const LayerHazardParams& p) { return p.ring_tests; }
  explicit RingStep(const LayerHazardParams& p)
      : h_min_m_(p.h_min_m), tan_slope_(std::tan(p.max_slope_rad)) {}
  int reach_cells(const TestReach& r) const { return r.ring_cells; }

  template <class Cell>
  void add(const Cell& c, Evidence& ev) const {
    if (ev.hazard()) return;
    if (std::isnan(c.z)) return ev.missing(kReasonNoHeight);
    c.wheel.step_test(c.z, c.step_variance(), c.ring(), h_min_m_, tan_slope_, ev);
  }

 private:
  double h_min_m_, tan_slope_;
};

}  // namespace hazmap

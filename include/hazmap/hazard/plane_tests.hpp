#pragma once
// The plane (CCM) family's own hazard tests (SPEC 8.2), on a cell's points: their
// residual about the cell's plane and the plane's inclination (PlaneCell,
// hazard_classifier.hpp). The list they run in is PlaneTests; the shape of a test is in
// hazard_test.hpp.

#include <algorithm>
#include <cmath>

#include "hazmap/hazard/hazard_test.hpp"
#include "hazmap/map/layer.hpp"

namespace hazmap {

/// Sub-cell obstacle: the residual variance beyond the sensor's against rho_max; its
/// estimate from n points has a standard deviation of about rho sqrt(2 / (n - 3)).
struct PlaneRoughness {
  static bool enabled(const LayerHazardParams&) { return true; }
  explicit PlaneRoughness(const LayerHazardParams& p) : rho_max_m2_(p.rho_max_m2) {}
  int reach_cells(const TestReach&) const { return 0; }

  template <class Cell>
  void add(const Cell& c, Evidence& ev) const {
    ev.why(kReasonNotEvaluable, kReasonRoughnessMargin);
    ev.test(c.noise.rho - c.noise.sensor,
            c.noise.rho * std::sqrt(2.0 / std::max(c.noise.n_eff - 3.0, 1.0)), rho_max_m2_,
            c.evaluable);
  }

 private:
  double rho_max_m2_;
};

/// Rock face (and, on layers without wheel-ring tests, the vehicle slope): the plane's
/// inclination against tan_face (tan max_slope). Along the principal axes of the points'
/// lateral spread, so that on a partly covered cell the slope along its well-observed
/// axis is evidence enough; slope i has variance res_var / (n lambda_i). Proof needs the
/// whole plane: |g| has a standard deviation of at most sqrt(var_g).
struct PlaneInclination {
  static bool enabled(const LayerHazardParams&) { return true; }
  explicit PlaneInclination(const LayerHazardParams& p)
      : tan_face_(p.tan_face), tan_slope_(std::tan(p.max_slope_rad)),
        own_slope_(!p.ring_tests), min_axis_coverage_(p.min_axis_coverage) {}
  int reach_cells(const TestReach&) const { return 0; }

  template <class Cell>
  void add(const Cell& c, Evidence& ev) const {
    const LayerGrids& g = c.grids;
    const int row = c.row, col = c.col;
    const double r = g.height.resolution_m;
    const double cxx = g.lateral_xx.at(row, col), cyy = g.lateral_yy.at(row, col),
                 cxy = g.lateral_xy.at(row, col);
    const double cxz = g.lateral_xz.at(row, col), cyz = g.lateral_yz.at(row, col);
    const double mid = 0.5 * (cxx + cyy), half_gap = std::hypot(0.5 * (cxx - cyy), cxy);
    const double lambda[2] = {mid + half_gap, mid - half_gap};
    const double theta = 0.5 * std::atan2(2.0 * cxy, cxx - cyy);  // axis of lambda[0]
    const double ex[2] = {std::cos(theta), -std::sin(theta)};
    const double ey[2] = {std::sin(theta), std::cos(theta)};
    const double tiny = 1e-6 * r * r;
    const double min_axis_spread = min_axis_coverage_ * r * r / 12.0;
    const double res_var = c.noise.res_var, n_eff = c.noise.n_eff;
    double g2 = 0, var_g = 0;
    bool both_axes = true;
    for (int i = 0; i < 2; ++i) {
      if (!(lambda[i] > tiny)) {
        both_axes = false;
        continue;
      }
      const double gi = (ex[i] * cxz + ey[i] * cyz) / lambda[i];
      const double si = std::sqrt(res_var / (std::max(n_eff, 1.0) * lambda[i]));
      // Evidence only along an axis the points span well: across a thin strip their
      // spread is mostly their own lateral noise, whose error moves x and z together
      // (measured on a 15 deg ramp: 56 and 65 deg across strips 0.13 and 0.2 cells wide).
      if (lambda[i] >= min_axis_spread) {
        ev.evidence(std::abs(gi), si, tan_face_);
        if (own_slope_) ev.evidence(std::abs(gi), si, tan_slope_);
      }
      g2 += gi * gi;
      var_g += si * si;
    }
    const bool plane_known = c.evaluable && both_axes;
    ev.why(kReasonNotEvaluable, kReasonSlopeMargin);
    if (!plane_known) return ev.missing();
    const double slope = std::sqrt(g2);
    ev.test(slope, std::sqrt(var_g), tan_face_, true);
    if (own_slope_) ev.test(slope, std::sqrt(var_g), tan_slope_, true);
  }

 private:
  double tan_face_, tan_slope_;
  bool own_slope_;  ///< no wheel ring on this layer: the plane's own inclination is the slope
  double min_axis_coverage_;
};

}  // namespace hazmap

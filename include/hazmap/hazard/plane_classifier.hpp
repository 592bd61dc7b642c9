#pragma once
// The plane family's classifier (SPEC 8.2 + 8.3; CCM layers): each cell's plane and
// points, and the wheel ring sampled on the neighbours' planes, judged by the family's
// lists of hazard tests (PlaneTests, and FewPointsTests for a cell with fewer points than
// a plane needs).

#include <algorithm>
#include <cmath>

#include "hazmap/hazard/hazard_classifier.hpp"
#include "hazmap/hazard/plane_tests.hpp"
#include "hazmap/hazard/ring_tests.hpp"

namespace hazmap {

/// A CCM cell's noise statistics: its roughness rho, the sensor part of it, the residual
/// variance about the plane and the number of points it rests on.
struct PlaneCellNoise {
  double rho = 0, sensor = 0, res_var = 0, n_eff = 0;
};

/// The cell's sensor noise variance; 0 where the layer does not know it.
inline double sensor_noise_at(const DenseGrid& noise, int row, int col) {
  if (noise.rows == 0) return 0.0;
  const double v = noise.at(row, col);
  return std::isfinite(v) ? v : 0.0;
}

inline PlaneCellNoise plane_cell_noise(const LayerGrids& g, int row, int col,
                                       double max_effective_count) {
  PlaneCellNoise c;
  c.rho = g.roughness.at(row, col);
  c.sensor = sensor_noise_at(g.noise_variance, row, col);
  c.res_var = std::max(c.rho, c.sensor);
  c.n_eff = std::min<double>(g.count.at(row, col), max_effective_count);
  return c;
}

/// Samples the terrain of a CCM layer at any point (the wheel ring's samples).
class PlaneSurface {
 public:
  explicit PlaneSurface(const LayerHazardParams& params)
      : max_effective_count_(params.max_effective_count) {}

  /// Sub-cell height of the plane surface at W point (x, y) and its variance (exact): the
  /// holding cell's plane, or if that cell is not evaluable the plane of its nearest
  /// evaluable neighbour extrapolated to the point; failing both, on a known cell its
  /// mu_z with the published and sensor variance (known, not exact: evidence only);
  /// unknown outside the grid or on an empty cell.
  RingSample at(const LayerGrids& g, double x_m, double y_m) const {
    int row = 0, col = 0;
    if (!g.height.cell_at(x_m, y_m, &row, &col)) return RingSample{};
    if (g.evaluable.at(row, col) == 1.0f) return plane_sample(g, row, col, x_m, y_m);
    // The holding cell is not evaluable: the plane of the nearest evaluable neighbour,
    // extrapolated to the point (its variance grows with the lever), still a measurement.
    const DenseGrid& h = g.height;
    int best_row = 0, best_col = 0;  // (row, col) itself is not evaluable: never chosen
    if (detail::nearest_in_3x3(
            h, row, col, [&](int r, int c) { return g.evaluable.at(r, c) == 1.0f; },
            [&](int r, int c) {
              return std::pow(h.x_of_col(c) - x_m, 2) + std::pow(h.y_of_row(r) - y_m, 2);
            },
            &best_row, &best_col))
      return plane_sample(g, best_row, best_col, x_m, y_m);
    RingSample s;
    if (std::isnan(h.at(row, col))) return s;
    // Evidence only: the cell's published mu_z, whose variance covers the tilt it may
    // hide (SPEC 6.4), plus its points' sensor variance (a few points' spread says little).
    s.z_m = h.at(row, col);
    s.var_m2 = g.variance.at(row, col) + sensor_noise_at(g.noise_variance, row, col);
    s.known = std::isfinite(s.var_m2);
    return s;
  }

  /// The terrain at W point (x, y) as the plane of the cell holding it says, for a finer
  /// layer's wheel ring (hazard.coarse_ring_fill): exact when that cell has a plane,
  /// with the plane's prediction variance plus the residual variance about it (the
  /// ground under a wheel departs from a plane this coarse as the cell's points did);
  /// else unknown (no extrapolation: the finer layer asks because nothing was measured).
  RingSample terrain_at(const LayerGrids& g, double x_m, double y_m) const {
    int row = 0, col = 0;
    if (!g.height.cell_at(x_m, y_m, &row, &col) || g.evaluable.at(row, col) != 1.0f)
      return RingSample{};
    RingSample s = plane_sample(g, row, col, x_m, y_m);
    s.var_m2 += plane_cell_noise(g, row, col, max_effective_count_).res_var;
    s.known = s.exact = s.exact && std::isfinite(s.var_m2);
    return s;
  }

  /// The plane of evaluable cell (row, col) at (x, y), as plane_sample.
  RingSample plane_of(const LayerGrids& g, int row, int col, double x_m, double y_m) const {
    return plane_sample(g, row, col, x_m, y_m);
  }

 private:
  /// The evaluable cell (row, col)'s plane at (x, y) with its prediction variance: the
  /// least-squares res_var / n (1 + d^T C^-1 d), d from the cell centre (an evaluable
  /// cell's points spread over it, so their mean is near the centre).
  RingSample plane_sample(const LayerGrids& g, int row, int col, double x_m, double y_m) const {
    RingSample s;
    const double dx = x_m - g.height.x_of_col(col), dy = y_m - g.height.y_of_row(row);
    s.z_m = g.height.at(row, col) + g.slope_x.at(row, col) * dx + g.slope_y.at(row, col) * dy;
    const PlaneCellNoise noise = plane_cell_noise(g, row, col, max_effective_count_);
    const double cxx = g.lateral_xx.at(row, col), cyy = g.lateral_yy.at(row, col),
                 cxy = g.lateral_xy.at(row, col);
    const double det = cxx * cyy - cxy * cxy;
    const double lever = det > 0 ? (cyy * dx * dx - 2 * cxy * dx * dy + cxx * dy * dy) / det : 0.0;
    s.var_m2 = noise.res_var / std::max(noise.n_eff, 1.0) * (1.0 + lever);
    s.known = s.exact = std::isfinite(s.z_m) && std::isfinite(s.var_m2);
    return s;
  }

  double max_effective_count_;
};

/// What a CCM layer's tests read of cell (row, col): its height, plane, noise statistics
/// and wheel ring (sampled on first use from the surface around it).
class PlaneCell {
 public:
  PlaneCell(const LayerGrids& g, const PlaneSurface& s, const WheelRing& w, int r, int c, float z0,
            const RingFallback* fallback = nullptr, const DenseGrid* viewed = nullptr)
      : grids(g), wheel(w), row(r), col(c), z(z0), surface_(s), fallback_(fallback),
        viewed_(viewed) {}

  const LayerGrids& grids;
  const WheelRing& wheel;
  const int row, col;
  const float z;               ///< the cell's height (never NaN here)
  bool evaluable = false;      ///< the cell has a plane
  PlaneCellNoise noise;
  double step_variance_m2 = 0;  ///< the height's variance for the step test

  double step_variance() const { return step_variance_m2; }

  const RingSample (&ring() const)[WheelRing::kSamples] {
    if (!ring_ready_) {
      const double cx = grids.height.x_of_col(col), cy = grids.height.y_of_row(row);
      for (int k = 0; k < WheelRing::kSamples; ++k) {
        const double x = cx + wheel.dx(k), y = cy + wheel.dy(k);
        ring_[k] = surface_.at(grids, x, y);
        // Not measured here (a measurement, even one too poor to prove, is kept).
        if (!ring_[k].known && fallback_) ring_[k] = fallback_->at(x, y);
        int r = -1, c = -1;
        ring_[k].unseen = !ring_[k].exact && grids.height.cell_at(x, y, &r, &c) &&
                          detail::outside_view(viewed_, r, c);
      }
      ring_ready_ = true;
    }
    return ring_;
  }

 private:
  const PlaneSurface& surface_;
  const RingFallback* fallback_;
  const DenseGrid* viewed_;
  mutable bool ring_ready_ = false;
  mutable RingSample ring_[WheelRing::kSamples];
};

/// The plane family's tests, in the order they run, on a cell with a plane's worth of
/// points.
using PlaneTests = HazardTests<PlaneRoughness, PlaneInclination, RingSlope, RingStep>;
/// On a cell with fewer than min_points points (SPEC 8.2 has no test for it): their mean
/// height, with the variance that covers any tilt (SPEC 6.4) and their sensor variance,
/// stands above the ring or not: the step as evidence only, since such a cell is never
/// proven (ours: on 12 cm rocks 17 % of the 4 cm rock cells in view had fewer points).
using FewPointsTests = HazardTests<RingStep>;

/// Classifies a CCM layer with the lists `Tests` and `FewTests` (HazardTests).
template <class Tests, class FewTests>
class PlaneFamilyClassifier final : public HazardClassifier {
 public:
  explicit PlaneFamilyClassifier(const LayerHazardParams& params)
      : HazardClassifier(params), surface_(params_), tests_(params), few_tests_(params) {}
  using HazardClassifier::classify;

  void classify(const LayerGrids& g, const GridRect& region, DenseGrid& hazard,
                HazardDiagnostics&) override {
    const DenseGrid& h = g.height;
    const LayerHazardParams& p = params_;
    const GridRect cells = region.clipped(h.rows, h.cols);
    for (int row = cells.row0; row < cells.row1; ++row)
      for (int col = cells.col0; col < cells.col1; ++col) {
        hazard.at(row, col) = static_cast<float>(HazardClass::unknown);
        const float z = h.at(row, col);
        if (std::isnan(z)) {
          record(row, col, kReasonNoHeight);
          continue;
        }
        PlaneCell cell(g, surface_, ring_, row, col, z, fallback_, viewed_);
        Evidence ev(p.k_sigma);
        if (double(g.count.at(row, col)) < p.min_points) {
          ev.missing(kReasonFewPoints);
          // The points' spread says little with so few: their sensor variance too, as a
          // ring sample of such a cell has (PlaneSurface::at).
          cell.step_variance_m2 = g.variance.at(row, col) + sensor_noise_at(g.noise_variance, row, col);
          few_tests_.run(cell, ev);
        } else {
          // A plane from a hole-free view classifies its own cell (PlaneSurface::at
          // reads only 1: no ring sample for others).
          cell.evaluable = g.evaluable.at(row, col) == 1.0f || g.evaluable.at(row, col) == kEvaluableOwnCell;
          cell.noise = plane_cell_noise(g, row, col, p.max_effective_count);
          // The height: the plane at the centre (the mean's variance), or mu_z with the
          // published variance, which covers the unknown tilt.
          cell.step_variance_m2 = cell.evaluable
                                      ? cell.noise.res_var / std::max(cell.noise.n_eff, 1.0)
                                      : g.variance.at(row, col);
          tests_.run(cell, ev);
        }
        hazard.at(row, col) = static_cast<float>(ev.result());
        record(row, col, ev,
               !wants_ring_only() || !unknown_for_ring_only(ev) || agrees_with_neighbours(g, cell));
      }
  }

  /// A ring sample reads the cell holding a point R from the centre, at most ceil(R / r)
  /// cells away, one more for rounding, and when that cell is not evaluable one of its
  /// neighbours (PlaneSurface::at): one more.
  int reach_cells() const override {
    const int ring = static_cast<int>(std::ceil(ring_.radius() / params_.resolution_m)) + 2;
    return std::max(tests_.reach_cells(TestReach{ring}), few_tests_.reach_cells(TestReach{ring}));
  }

  /// The surface the wheel ring samples (PlaneSurface::at).
  RingSample surface_at(const LayerGrids& g, double x_m, double y_m) const {
    return surface_.at(g, x_m, y_m);
  }

 private:
  /// hazard.footprint_centre_ring: a cell whose own tests proved it but whose wheel ring
  /// lacked samples counts as clear under the rover's body only if no step of h_min
  /// hides between it and a neighbour (two planar cells, each below the face limit, may
  /// still meet at a step on their common edge): the cell's height lies within h_min,
  /// k sigma included, of every evaluable 8-neighbour's plane at its centre.
  bool agrees_with_neighbours(const LayerGrids& g, const PlaneCell& cell) const {
    if (!cell.evaluable) return false;
    const DenseGrid& h = g.height;
    const double x = h.x_of_col(cell.col), y = h.y_of_row(cell.row);
    for (int dr = -1; dr <= 1; ++dr)
      for (int dc = -1; dc <= 1; ++dc) {
        const int r = cell.row + dr, c = cell.col + dc;
        if ((dr == 0 && dc == 0) || r < 0 || c < 0 || r >= h.rows || c >= h.cols) continue;
        if (g.evaluable.at(r, c) != 1.0f) continue;
        const RingSample s = surface_.plane_of(g, r, c, x, y);
        if (!s.exact) return false;
        const double sigma = std::sqrt(cell.step_variance() + s.var_m2);
        if (std::abs(cell.z - s.z_m) + params_.k_sigma * sigma > params_.h_min_m) return false;
      }
    return true;
  }

  PlaneSurface surface_;
  Tests tests_;
  FewTests few_tests_;
};

using PlaneClassifier = PlaneFamilyClassifier<PlaneTests, FewPointsTests>;
extern template class PlaneFamilyClassifier<PlaneTests, FewPointsTests>;

}  // namespace hazmap

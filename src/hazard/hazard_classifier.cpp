#include "hazmap/hazard/hazard_classifier.hpp"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <limits>

#include "hazmap/hazard/evidence.hpp"

namespace hazmap {
namespace {

/// The cell's sensor noise variance; 0 where the layer does not know it.
double noise_at(const DenseGrid& noise, int row, int col) {
  if (noise.rows == 0) return 0.0;
  const double v = noise.at(row, col);
  return std::isfinite(v) ? v : 0.0;
}

/// The cell offset (row, col) that holds wheel-ring sample k on a piecewise-constant
/// layer: the sample point rounded to a cell centre.
int ring_col_offset(const WheelRing& ring, int k, double resolution_m) {
  return static_cast<int>(std::lround(ring.dx(k) / resolution_m));
}
int ring_row_offset(const WheelRing& ring, int k, double resolution_m) {
  return -static_cast<int>(std::lround(ring.dy(k) / resolution_m));  // row 0 = max y
}

/// The cell of the 3 x 3 block around (row, col), inside the grid, that `accept`s and
/// lies nearest by `distance2(r, c)` (the first of equals in row-major order); false if
/// none. Both classifiers look there when a ring sample's own cell cannot serve.
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

}  // namespace

void HazardClassifier::classify(const LayerGrids& g, DenseGrid& hazard, HazardDiagnostics& diag) {
  const DenseGrid& h = g.height;
  hazard.reset(h.rows, h.cols, h.resolution_m, h.center_x_m, h.center_y_m,
               static_cast<float>(HazardClass::unknown));
  reset_diagnostics(h, diag);
  classify(g, GridRect::full(h.rows, h.cols), hazard, diag);
}

void HazardClassifier::explain(const LayerGrids& g, DenseGrid& reasons) {
  const DenseGrid& h = g.height;
  reasons.reset(h.rows, h.cols, h.resolution_m, h.center_x_m, h.center_y_m, 0.0f);
  DenseGrid hazard;
  HazardDiagnostics diag;
  reasons_ = &reasons;
  classify(g, hazard, diag);
  reasons_ = nullptr;
}

// ---- Piecewise-constant layers (SPEC 8.1, 8.3) ----

PiecewiseConstantClassifier::PiecewiseConstantClassifier(const LayerHazardParams& params)
    : HazardClassifier(params) {
  filter_.set_detrended(params.detrended_roughness);
  for (int w : kernel_half_widths(params.kernel)) kernel_cells_ += 2 * w + 1;
  for (int n = 0; n <= kernel_cells_; ++n) kernel_k_.push_back(kernel_k_sigma(params.k_sigma, n));
}

void PiecewiseConstantClassifier::reset_diagnostics(const DenseGrid& h,
                                                   HazardDiagnostics& diag) const {
  const float nan = std::numeric_limits<float>::quiet_NaN();
  diag.kernel_range.reset(h.rows, h.cols, h.resolution_m, h.center_x_m, h.center_y_m, nan);
  diag.kernel_sigma.reset(h.rows, h.cols, h.resolution_m, h.center_x_m, h.center_y_m, nan);
  diag.kernel_fill.reset(h.rows, h.cols, h.resolution_m, h.center_x_m, h.center_y_m, 0.0f);
  if (params_.detrended_roughness) {
    diag.kernel_slope.reset(h.rows, h.cols, h.resolution_m, h.center_x_m, h.center_y_m, nan);
    diag.kernel_slope_sigma.reset(h.rows, h.cols, h.resolution_m, h.center_x_m, h.center_y_m, nan);
  }
}

int PiecewiseConstantClassifier::reach_cells() const {
  int reach = (params_.kernel - 1) / 2;
  if (params_.ring_tests)
    for (int k = 0; k < WheelRing::kSamples; ++k)  // + 1: a sample may come from a neighbour
      reach = std::max({reach, std::abs(ring_col_offset(ring_, k, params_.resolution_m)) + 1,
                        std::abs(ring_row_offset(ring_, k, params_.resolution_m)) + 1});
  return reach;
}

RingSample PiecewiseConstantClassifier::ring_sample(const LayerGrids& g, int row, int col,
                                                    double tan_slope) const {
  // The cell holding the sample point, or if it is unobserved (a fine layer has holes) the
  // nearest observed of its 8 neighbours: its height stands d away from the point, which
  // ground up to max_slope can shift by d tan(max_slope) (added as variance).
  const DenseGrid& h = g.height;
  const auto cells2 = [&](int r, int c) {
    return double((r - row) * (r - row) + (c - col) * (c - col));
  };
  int r = 0, c = 0;
  if (!nearest_in_3x3(h, row, col, [&](int rr, int cc) { return !std::isnan(h.at(rr, cc)); },
                      cells2, &r, &c))
    return RingSample{};
  const double lever2 = cells2(r, c) * h.resolution_m * h.resolution_m * tan_slope * tan_slope;
  return {h.at(r, c), g.variance.at(r, c) + lever2, true, true};
}

void PiecewiseConstantClassifier::classify(const LayerGrids& g, const GridRect& region,
                                           DenseGrid& hazard, HazardDiagnostics& diag) {
  const DenseGrid& h = g.height;
  const LayerHazardParams& p = params_;
  const GridRect cells = region.clipped(h.rows, h.cols);
  const bool detrended = p.detrended_roughness;
  filter_.compute(h, g.variance, p.kernel, cells, diag.kernel_range, diag.kernel_sigma,
                  diag.kernel_fill, detrended ? &diag.kernel_slope : nullptr,
                  detrended ? &diag.kernel_slope_sigma : nullptr);
  const double tan_slope = std::tan(p.max_slope_rad);
  const int kernel_cells = kernel_cells_;
  // Ring samples as cell offsets (the observed cell that holds each sample point).
  int ring_dr[WheelRing::kSamples], ring_dc[WheelRing::kSamples];
  for (int k = 0; k < WheelRing::kSamples; ++k) {
    ring_dc[k] = ring_col_offset(ring_, k, h.resolution_m);
    ring_dr[k] = ring_row_offset(ring_, k, h.resolution_m);
  }
  for (int row = cells.row0; row < cells.row1; ++row)
    for (int col = cells.col0; col < cells.col1; ++col) {
      hazard.at(row, col) = static_cast<float>(HazardClass::unknown);
      const float range = diag.kernel_range.at(row, col);
      if (std::isnan(range)) {  // kernel off the layer or empty: unknown
        record(row, col, kReasonNoHeight);
        continue;
      }
      const float z = h.at(row, col);
      Evidence ev(p.k_sigma);
      ev.why(std::isnan(z) ? kReasonNoHeight : kReasonKernelIncomplete, kReasonRoughnessMargin);
      // The kernel is evidence even around an unobserved cell; proof needs the cell, the
      // kernel's fill and the whole kernel inside the layer.
      const bool complete = !std::isnan(z) && diag.kernel_fill.at(row, col) >= p.min_kernel_fill;
      // The range is the largest difference among the kernel's observed cells: its hazard
      // side counts the cells it was picked from.
      const int observed = static_cast<int>(std::lround(double(diag.kernel_fill.at(row, col)) * kernel_cells));
      ev.test(range, diag.kernel_sigma.at(row, col), p.roughness_threshold_m, complete,
              kernel_k_[std::clamp(observed, 0, kernel_cells)]);
      // Detrended: a kernel plane rising h_min within the kernel's radius is a face, even
      // on a partly seen kernel (measured: a partial ring leaves rock faces unknown).
      // Slopes short of that are the ring's to judge: against max_slope itself, the
      // 6-cell plane turned stereo noise on ramps into hazards.
      if (detrended)
        ev.evidence(diag.kernel_slope.at(row, col), diag.kernel_slope_sigma.at(row, col),
                    p.kernel_face_tan);
      if (p.ring_tests && !ev.hazard()) {
        if (std::isnan(z)) {
          ev.missing(kReasonNoHeight);
        } else {
          RingSample s[WheelRing::kSamples];
          for (int k = 0; k < WheelRing::kSamples; ++k)
            s[k] = ring_sample(g, row + ring_dr[k], col + ring_dc[k], tan_slope);
          // Detrended kernels leave slopes to the ring (SPEC 8.2's vehicle slope).
          if (detrended) ring_.slope_test(s, tan_slope, ev);
          ring_.step_test(z, g.variance.at(row, col), s, p.h_min_m, tan_slope, ev);
        }
      }
      hazard.at(row, col) = static_cast<float>(ev.result());
      record(row, col, ev);
    }
}

// ---- CCM layers (SPEC 8.2, 8.3) ----

PlaneClassifier::CellNoise PlaneClassifier::cell_noise(const LayerGrids& g, int row,
                                                       int col) const {
  CellNoise c;
  c.rho = g.roughness.at(row, col);
  c.sensor = noise_at(g.noise_variance, row, col);
  c.res_var = std::max(c.rho, c.sensor);
  c.n_eff = std::min<double>(g.count.at(row, col), params_.max_effective_count);
  return c;
}

RingSample PlaneClassifier::plane_sample(const LayerGrids& g, int row, int col, double x_m,
                                         double y_m) const {
  RingSample s;
  const double dx = x_m - g.height.x_of_col(col), dy = y_m - g.height.y_of_row(row);
  s.z_m = g.height.at(row, col) + g.slope_x.at(row, col) * dx + g.slope_y.at(row, col) * dy;
  // Least-squares prediction variance res_var / n (1 + d^T C^-1 d), d from the cell centre
  // (an evaluable cell's points spread over it, so their mean is near the centre).
  const CellNoise noise = cell_noise(g, row, col);
  const double cxx = g.lateral_xx.at(row, col), cyy = g.lateral_yy.at(row, col),
               cxy = g.lateral_xy.at(row, col);
  const double det = cxx * cyy - cxy * cxy;
  const double lever = det > 0 ? (cyy * dx * dx - 2 * cxy * dx * dy + cxx * dy * dy) / det : 0.0;
  s.var_m2 = noise.res_var / std::max(noise.n_eff, 1.0) * (1.0 + lever);
  s.known = s.exact = std::isfinite(s.z_m) && std::isfinite(s.var_m2);
  return s;
}

RingSample PlaneClassifier::surface_at(const LayerGrids& g, double x_m, double y_m) const {
  int row = 0, col = 0;
  if (!g.height.cell_at(x_m, y_m, &row, &col)) return RingSample{};
  if (g.evaluable.at(row, col) == 1.0f) return plane_sample(g, row, col, x_m, y_m);
  // The holding cell is not evaluable: the plane of the nearest evaluable neighbour,
  // extrapolated to the point (its variance grows with the lever), still a measurement.
  const DenseGrid& h = g.height;
  int best_row = 0, best_col = 0;  // (row, col) itself is not evaluable: never chosen
  if (nearest_in_3x3(
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
  s.var_m2 = g.variance.at(row, col) + cell_noise(g, row, col).sensor;
  s.known = std::isfinite(s.var_m2);
  return s;
}

void PlaneClassifier::ring_around(const LayerGrids& g, int row, int col,
                                  RingSample (&s)[WheelRing::kSamples]) const {
  const double cx = g.height.x_of_col(col), cy = g.height.y_of_row(row);
  for (int k = 0; k < WheelRing::kSamples; ++k)
    s[k] = surface_at(g, cx + ring_.dx(k), cy + ring_.dy(k));
}

int PlaneClassifier::reach_cells() const {
  // A ring sample reads the cell holding a point R from the centre, at most ceil(R / r)
  // cells away, one more for rounding, and when that cell is not evaluable one of its
  // neighbours (surface_at): one more.
  if (!params_.ring_tests) return 0;
  return static_cast<int>(std::ceil(ring_.radius() / params_.resolution_m)) + 2;
}

void PlaneClassifier::classify(const LayerGrids& g, const GridRect& region, DenseGrid& hazard,
                               HazardDiagnostics&) {
  const DenseGrid& h = g.height;
  const LayerHazardParams& p = params_;
  const GridRect cells = region.clipped(h.rows, h.cols);
  const double tan_slope = std::tan(p.max_slope_rad);
  for (int row = cells.row0; row < cells.row1; ++row)
    for (int col = cells.col0; col < cells.col1; ++col) {
      hazard.at(row, col) = static_cast<float>(HazardClass::unknown);
      const float z = h.at(row, col);
      if (std::isnan(z)) {
        record(row, col, kReasonNoHeight);
        continue;
      }
      if (double(g.count.at(row, col)) < p.min_points) {
        // Too few points for the plane's tests (SPEC 8.2), but their mean height, with the
        // variance that covers any tilt (SPEC 6.4), stands above the ring or not: the step
        // test as evidence only (ours; a rock's rim or top seen by a few points: on 12 cm
        // rocks 17 % of the 4 cm rock cells in view had fewer than min_points).
        if (p.ring_tests) {
          Evidence ev(p.k_sigma);
          ev.missing(kReasonFewPoints);
          RingSample s[WheelRing::kSamples];
          ring_around(g, row, col, s);
          // The points' spread says little with so few: their sensor variance too, as a
          // ring sample of such a cell has (surface_at).
          ring_.step_test(z, g.variance.at(row, col) + noise_at(g.noise_variance, row, col), s,
                          p.h_min_m, tan_slope, ev);
          hazard.at(row, col) = static_cast<float>(ev.result());
          record(row, col, ev);
        } else {
          record(row, col, kReasonFewPoints);
        }
        continue;
      }
      const bool evaluable = g.evaluable.at(row, col) == 1.0f;
      const CellNoise noise = cell_noise(g, row, col);
      const double res_var = noise.res_var, n_eff = noise.n_eff;
      Evidence ev(p.k_sigma);

      // Sub-cell obstacle: the residual variance beyond the sensor's, whose estimate from
      // n points has a standard deviation of about rho sqrt(2 / (n - 3)).
      ev.why(kReasonNotEvaluable, kReasonRoughnessMargin);
      ev.test(noise.rho - noise.sensor, noise.rho * std::sqrt(2.0 / std::max(n_eff - 3.0, 1.0)),
              p.rho_max_m2, evaluable);

      // Slopes along the principal axes of the points' lateral spread: on a partly covered
      // cell the slope along its well-observed axis is evidence enough. Slope i has
      // variance res_var / (n lambda_i).
      const double cxx = g.lateral_xx.at(row, col), cyy = g.lateral_yy.at(row, col),
                   cxy = g.lateral_xy.at(row, col);
      const double cxz = g.lateral_xz.at(row, col), cyz = g.lateral_yz.at(row, col);
      const double mid = 0.5 * (cxx + cyy), half_gap = std::hypot(0.5 * (cxx - cyy), cxy);
      const double lambda[2] = {mid + half_gap, mid - half_gap};
      const double theta = 0.5 * std::atan2(2.0 * cxy, cxx - cyy);  // axis of lambda[0]
      const double ex[2] = {std::cos(theta), -std::sin(theta)};
      const double ey[2] = {std::sin(theta), std::cos(theta)};
      const double tiny = 1e-6 * h.resolution_m * h.resolution_m;
      const double min_axis_spread = p.min_axis_coverage * h.resolution_m * h.resolution_m / 12.0;
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
          ev.evidence(std::abs(gi), si, p.tan_face);
          if (!p.ring_tests) ev.evidence(std::abs(gi), si, tan_slope);
        }
        g2 += gi * gi;
        var_g += si * si;
      }
      // Proof needs the whole plane: |g| has a standard deviation of at most sqrt(var_g).
      const bool plane_known = evaluable && both_axes;
      ev.why(kReasonNotEvaluable, kReasonSlopeMargin);
      const double slope = plane_known ? std::sqrt(g2) : 0.0;
      if (plane_known) {
        ev.test(slope, std::sqrt(var_g), p.tan_face, true);
        if (!p.ring_tests) ev.test(slope, std::sqrt(var_g), tan_slope, true);  // own inclination
      } else {
        ev.missing();
      }

      if (p.ring_tests && !ev.hazard()) {
        RingSample s[WheelRing::kSamples];
        ring_around(g, row, col, s);
        ring_.slope_test(s, tan_slope, ev);
        // The cell's own height: its plane at the centre (mean's variance), or mu_z with
        // the published variance, which covers the unknown tilt.
        const double var_h = evaluable ? res_var / std::max(n_eff, 1.0) : g.variance.at(row, col);
        ring_.step_test(z, var_h, s, p.h_min_m, tan_slope, ev);
      }
      hazard.at(row, col) = static_cast<float>(ev.result());
      record(row, col, ev);
    }
}

std::unique_ptr<HazardClassifier> make_hazard_classifier(const LayerHazardParams& params) {
  if (params.family == HazardFamily::plane) return std::make_unique<PlaneClassifier>(params);
  return std::make_unique<PiecewiseConstantClassifier>(params);
}

}  // namespace hazmap

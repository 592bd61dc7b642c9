#pragma once
// Converging Covariance Map rule (SPEC 6.4): per cell the weighted mean and co-moments
// of the 3-D points, x and y relative to the cell centre. A cell therefore knows a plane
// (height at any point inside it, slopes), its roughness about that plane, and how well
// its points cover it.
//
//   W' = W + w,  delta = d - mu,  mu' = mu + (w/W') delta,  S' = S + w delta (d - mu')^T
//
// A frame's points in a cell are summed relative to a reference (no division per point)
// and merged with the exact moment merge (SPEC 6.5), equal to the recursion above; the
// weight cap (W > W_l: W, S divided by W/W_l) then acts once per frame, as SPEC 6.4
// requires. Storage is float; the mean height is a float reference plus a float offset,
// so cells at |z| ~ 100 m with millimetre spreads keep their co-moments (no E[x^2]-mu^2).

#include <cmath>
#include <cstdint>
#include <limits>

#include "hazmap/core/core_config.hpp"
#include "hazmap/map/internal/run_sums.hpp"
#include "hazmap/map/internal/split_height.hpp"
#include "hazmap/map/moments.hpp"
#include "hazmap/map/plane_cell_values.hpp"
#include "hazmap/map/point_chunk.hpp"
#include "hazmap/rules/merge_policy.hpp"

namespace hazmap {

struct CcmRule {
  static constexpr const char* kName = "ccm";
  // Traits (rules/update_rule.hpp), the same four in the same order in every rule:
  /// Cells fit a plane: the layer exports the plane grids (SPEC 6.4).
  static constexpr bool kHasPlane = true;
  /// The weight cap applies once per frame (SPEC 6.4): runs go to a frame accumulator.
  static constexpr MergePolicy kMerge = MergePolicy::per_frame;
  /// The layer keeps each cell's last-merge frame beside the cells.
  static constexpr bool kStampInCell = false;
  /// No SPEC 4 consistency gate.
  static constexpr bool kHeightGate = false;

  /// As read from rules.ccm (core/core_config.hpp: max_weight, min_points, min_coverage,
  /// full_plane; weighting and max_std_ratio act before the rule), plus one value the
  /// layer derives from the hazard section:
  struct Config : CcmConfig {
    /// hazard.max_slope_deg in radians: the tilt a cell that is not evaluable may hide,
    /// in its published variance (SPEC 6.4).
    double max_slope_rad = 20.0 * M_PI / 180.0;
    /// Keep each cell's 4 x 4 occupancy mask (Cell::occupied): set per layer by make_layer
    /// where map.layers.N.hole_free_coverage reads it; it costs that layer about a fifth
    /// of its insertion time (docs/hazards.md), so other layers do not pay for it.
    bool occupancy = false;
  };

  /// The layer's Config from the hazard section (rule_registry.hpp: rule_config).
  static void derive_config(Config& cfg, const HazardConfig& hazard) {
    cfg.max_slope_rad = hazard.max_slope_deg * M_PI / 180.0;
  }

  struct Cell {
    float w = 0.0f;
    float mx_m = 0.0f, my_m = 0.0f;  ///< mean x, y relative to the cell centre
    SplitHeight mz_m;                ///< mean height
    float sxx = 0.0f, syy = 0.0f, szz = 0.0f, sxy = 0.0f, sxz = 0.0f, syz = 0.0f;  ///< co-moments
    float noise_var_m2 = 0.0f;  ///< weighted mean of the points' Sigma_zz
    std::uint32_t count = 0;
    /// Which of the cell's 4 x 4 sub-cells ever held a point (map/moments.hpp:
    /// occupancy_bit; only with Config::occupancy, and on a pooled layer only the points
    /// it took itself); not discounted by the weight cap: ground seen stays seen.
    std::uint16_t occupied = 0;
  };

  using Sums = FrameSums;

  static bool known(const Cell& c) { return c.w > 0.0f; }
  static void clear(Cell& c) { c = Cell{}; }
  static float reference_z(const Cell& c) { return c.mz_m.ref_m; }
  /// Null for unit weights: add_plane_run then reads no weights.
  static const float* weights(const PointChunk& c) {
    return c.unit_ccm_weight ? nullptr : c.ccm_weight;
  }
  /// Adds a run of points in this cell (z relative to z_ref_m) to a frame's sums, with
  /// their sub-cells where the layer keeps the occupancy mask.
  static void add_run(const Config& cfg, Sums& s, const RunPoints& run,
                      double z_ref_m) {  // run.var_z required
    add_plane_run(run, z_ref_m, s, cfg.occupancy);
  }
  static double mean_z(const Cell& c) { return c.mz_m.value(); }

  static Moments to_moments(const Cell& c) {
    Moments m;
    if (!known(c)) return m;
    m.w = c.w;
    m.mx = c.mx_m;
    m.my = c.my_m;
    m.mz = mean_z(c);
    m.sxx = c.sxx, m.syy = c.syy, m.szz = c.szz;
    m.sxy = c.sxy, m.sxz = c.sxz, m.syz = c.syz;
    m.noise_var = c.noise_var_m2;
    m.count = c.count;
    return m;
  }

  /// Stores moments into the cell, applying the weight cap.
  static void from_moments(const Config& cfg, Cell& c, Moments m) {
    if (m.empty()) {
      clear(c);
      return;
    }
    if (m.w > cfg.max_weight) m.scale_weight(cfg.max_weight / m.w);
    c.w = static_cast<float>(m.w);
    c.mx_m = static_cast<float>(m.mx);
    c.my_m = static_cast<float>(m.my);
    c.mz_m.set(m.mz);
    c.sxx = static_cast<float>(m.sxx), c.syy = static_cast<float>(m.syy);
    c.szz = static_cast<float>(m.szz), c.sxy = static_cast<float>(m.sxy);
    c.sxz = static_cast<float>(m.sxz), c.syz = static_cast<float>(m.syz);
    c.noise_var_m2 = static_cast<float>(m.noise_var);
    c.count = m.count;
  }

  static void merge_frame(const Config& cfg, Cell& c, const Sums& s, double z_ref_m,
                          double cell_m) {
    if (!(s.w > 0)) return;
    Moments m = to_moments(c);
    m.merge(s.to_moments(cell_m, z_ref_m));
    const std::uint16_t occupied = c.occupied | s.occupied;
    from_moments(cfg, c, m);
    c.occupied = occupied;
  }

  /// The cell's occupancy mask (bit 4 j + i: sub-cell (i, j) held a point).
  static std::uint16_t occupied(const Cell& c) { return c.occupied; }

  /// Nothing changes with time.
  static void age(const Config&, Cell&, std::uint32_t) {}
  /// Whether age() changes what a cell exports.
  static bool ages_exports(const Config&) { return false; }

  // ---- Queries (SPEC 6.4); covariances are S / W. ----

  /// Slopes (dz/dx, dz/dy) of the cell's plane; (0, 0) when the lateral spread is
  /// degenerate (a line of points or a single point).
  static void slopes(const Config& cfg, const Cell& c, double* a, double* b) {
    *a = 0.0;
    *b = 0.0;
    if (!known(c)) return;
    const double sxx = c.sxx, syy = c.syy, sxy = cfg.full_plane ? double(c.sxy) : 0.0;
    const double det = sxx * syy - sxy * sxy;
    if (!(det > 1e-12 * (sxx * syy)) || !(sxx > 0) || !(syy > 0)) return;
    *a = (syy * c.sxz - sxy * c.syz) / det;
    *b = (sxx * c.syz - sxy * c.sxz) / det;
  }

  /// Height of the plane at cell-centric point (qx, qy) [m]: mu_z + a (qx - mx) + b (qy - my).
  static double height_at(const Config& cfg, const Cell& c, double qx_m, double qy_m) {
    double a, b;
    slopes(cfg, c, &a, &b);
    return mean_z(c) + a * (qx_m - c.mx_m) + b * (qy_m - c.my_m);
  }

  /// Plane-normal variance rho = szz - c^T Sxy^-1 c [m^2] (thesis form when !full_plane).
  static double roughness(const Config& cfg, const Cell& c) {
    if (!known(c)) return std::numeric_limits<double>::quiet_NaN();
    double a, b;
    slopes(cfg, c, &a, &b);
    // c^T Sxy^-1 c = [a b] . c  for the solved slopes (and the diagonal thesis form).
    const double rho = (c.szz - (a * c.sxz + b * c.syz)) / c.w;
    return std::max(rho, 0.0);
  }

  /// Inclination of the plane [rad].
  static double inclination(const Config& cfg, const Cell& c) {
    double a, b;
    slopes(cfg, c, &a, &b);
    return std::atan(std::sqrt(a * a + b * b));
  }

  /// What the cell publishes beside its plane (rules/update_rule.hpp): its point count,
  /// mean noise variance and lateral (co)variances S/W.
  static PlaneCellValues cell_values(const Cell& c) {
    return {static_cast<float>(c.count), c.noise_var_m2, c.sxx / c.w, c.syy / c.w,
            c.sxy / c.w,                 c.sxz / c.w,     c.syz / c.w};
  }

  /// Lateral coverage kappa = min(sxx, syy) / (r^2 / 12); 1 for points spread uniformly.
  static double coverage(const Cell& c, double cell_m) {
    if (!known(c)) return 0.0;
    return std::min(c.sxx, c.syy) / c.w / (cell_m * cell_m / 12.0);
  }

  static bool evaluable(const Config& cfg, const Cell& c, double cell_m) {
    return known(c) && c.count >= static_cast<std::uint32_t>(cfg.min_points) &&
           coverage(c, cell_m) >= cfg.min_coverage;
  }

  /// Height variance of the cell's points, szz / W (their height spread: plane tilt,
  /// roughness and noise).
  static float variance(const Cell& c) {
    return known(c) ? c.szz / c.w : std::numeric_limits<float>::quiet_NaN();
  }

  /// Published height variance (SPEC 6.4): szz / W on an evaluable cell; on one that is
  /// not, whose published height is mu_z (the height at the points' mean), plus
  /// (r^2/12 + |mu_xy|^2) tan^2(max_slope): the mean square, over the cell, of a plane
  /// tilted by max_slope about the points' mean, which nobody measured (a cell seen in
  /// one corner is extrapolated farther).
  static double published_variance(const Config& cfg, const Cell& c, double cell_m,
                                    bool evaluable) {
    if (!known(c)) return std::numeric_limits<double>::quiet_NaN();
    const double v = double(c.szz) / double(c.w);
    if (evaluable) return v;
    const double t = std::tan(cfg.max_slope_rad);
    const double lever2 = cell_m * cell_m / 12.0 + double(c.mx_m) * c.mx_m + double(c.my_m) * c.my_m;
    return v + lever2 * t * t;
  }
};

}  // namespace hazmap

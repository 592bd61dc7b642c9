#pragma once
// Kalman height rule (SPEC 6.2): one scalar Kalman filter per cell on the height.
//
//   first point:  mu = z,  var = vm
//   update:       mu' = (vm mu + var z) / (var + vm),  var' = var vm / (var + vm)
//   floor:        var' = max(var', min_variance)
//   per frame:    var += time_inflation on every known cell (forgetting, so that the
//                 map can re-converge when the terrain or the pose estimate changes)
//
// vm is the measurement's height variance Sigma_W(2,2) (SPEC 4). A run of points in a
// cell (consecutive points of a scan line) is summed in information form (sum 1/vm,
// sum z/vm) and merged at once: this equals the point-by-point recursion above exactly
// (both are the inverse-variance weighted mean, variance 1 / sum(1/vm)); only the floor
// is applied once per run instead of after every point.
// The cell stores the precision 1/var rather than var: a merge then costs one division
// (var' = 1 / (1/var + sum 1/vm)) and the floor is a cap on the precision. The mean is a
// SplitHeight, so cells far from the origin (|z| ~ 100 m) keep sub-micrometre resolution.

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>

#include "hazmap/core/core_config.hpp"
#include "hazmap/map/internal/split_height.hpp"
#include "hazmap/map/moments.hpp"
#include "hazmap/map/point_chunk.hpp"
#include "hazmap/rules/merge_policy.hpp"
#include "hazmap/rules/run_view.hpp"

namespace hazmap {

struct KalmanRule {
  static constexpr const char* kName = "kalman";
  // Traits (rules/update_rule.hpp), the same four in the same order in every rule:
  /// Piecewise-constant cells: height and variance, no plane.
  static constexpr bool kHasPlane = false;
  /// A run merges like a frame: the floor applies per run (closer to the per-point
  /// recursion). A run's sums come from ChunkRuns::sum_heights, and plain layers hand a
  /// chunk's whole run list to merge_chunk_runs (eight runs at once).
  static constexpr MergePolicy kMerge = MergePolicy::per_chunk;
  /// The cell holds its last-merge frame: a merge then reads and writes one 16-byte cell.
  static constexpr bool kStampInCell = true;
  /// Has the SPEC 4 consistency gate (gate_state).
  static constexpr bool kHeightGate = true;

  /// As read from rules.kalman (core/core_config.hpp): time_inflation_m2, min_variance_m2,
  /// gate_sigma.
  using Config = KalmanConfig;

  /// precision 0 marks a cell that has never been observed.
  struct Cell {
    SplitHeight mean_m;
    float precision = 0.0f;   ///< 1 / variance [1/m^2]
    std::uint32_t stamp = 0;  ///< frame of the last merge (the layer's lazy ageing, SPEC 7)
  };

  /// Information-form sums of a run's (or a frame's) points, z relative to a reference.
  struct Sums {
    double w = 0, wz = 0;
    void add(double wt, double /*x*/, double /*y*/, double z) {
      w += wt;
      wz += wt * z;
    }
  };

  static bool known(const Cell& c) { return c.precision > 0.0f; }
  static void clear(Cell& c) { c = Cell{}; }

  /// SPEC 4 consistency gate: the cell's height and variance (with the `owed` frames of
  /// inflation) a point is tested against; false if the cell is unknown (no gate).
  static bool gate_state(const Config& cfg, Cell c, std::uint32_t owed, double* mu, double* var) {
    if (!known(c)) return false;
    age(cfg, c, owed);
    *mu = mean(c);
    *var = 1.0 / double(c.precision);
    return true;
  }
  static double mean(const Cell& c) { return c.mean_m.value(); }
  static float reference_z(const Cell& c) { return c.mean_m.ref_m; }
  static const float* weights(const PointChunk& c) { return c.inv_var_z; }
  /// Sums of run r of the chunk (points in one cell), z relative to the run's first height:
  /// ChunkRuns holds them (sum_heights), the chunk is not read again.
  static Sums run_sums(const ChunkRuns& runs, int r) {
    Sums s;
    s.w = runs.sum_w(r);
    s.wz = runs.sum_wz(r);
    return s;
  }
  static Sums run_sums(const PointChunk& /*chunk*/, const ChunkRuns& runs, int r) {
    return run_sums(runs, r);
  }

  /// Merges a run's or a frame's sums (z relative to z_ref_m) into the cell: the
  /// information-form update, then the floor as a cap on the precision.
  static void merge_frame(const Config& cfg, Cell& c, const Sums& s, double z_ref_m,
                          double /*cell_m*/) {
    merge_run(cfg, c, s, z_ref_m, 0, max_precision(cfg));
  }

  /// var >= floor  <=>  precision <= 1 / floor: the cap merge_run applies, for pooling.
  static float floored(const Config& cfg, double precision) {
    return static_cast<float>(std::min(precision, max_precision(cfg)));
  }

  /// age(cfg, c, owed), then the information-form merge of sums s (z relative to z_ref_m)
  /// and the floor as a cap on the precision, fused into one division and no branch on
  /// the cell (layers merge runs this way). With p the cell's precision, off its mean
  /// relative to z_ref_m, D = 1 + owed q p the ageing divisor and A = p + D W:
  ///   precision' = p / D + W = A / D,   mean' - z_ref = (p off + D WZ) / A,
  /// and both quotients come from r = 1 / (D A). A cleared cell (p = 0, mean 0) needs no
  /// case of its own: D = 1 and mean' = WZ / W.
  static void merge_run(const Config& cfg, Cell& c, const Sums& s, double z_ref_m,
                        std::uint32_t owed, double max_precision) {
    if (!(s.w > 0)) {  // nothing to merge; the caller stamps the cell, so age it now
      age(cfg, c, owed);
      return;
    }
    const double p = c.precision, off = c.mean_m.value() - z_ref_m;
    const double d = 1.0 + double(owed) * cfg.time_inflation_m2 * p;
    const double a = p + d * s.w;
    const double r = 1.0 / (d * a);
    c.mean_m.set(z_ref_m + (p * off + d * s.wz) * d * r);
    c.precision = static_cast<float>(std::min(a * a * r, max_precision));
  }
  /// A chunk's runs merged into a plain (unpooled) layer, eight at a time in SIMD lanes
  /// (src/map/kalman_runs.cpp). A run's merge is a chain of dependent steps around a
  /// division (load the cell, age, merge, cap, split, store); merged one after another,
  /// only a few runs' chains overlap in the core. Here eight runs share one chain: their
  /// cells are loaded and transposed into lanes, merged in double lanes with merge_run's
  /// steps, transposed back and stored whole. A batch whose runs do not all fall in
  /// distinct cells inside the window (two runs of one cell would read it before the
  /// first merge lands) is merged run by run with merge_run, as is the chunk's last
  /// partial batch. Runs outside the window (slot < 0) are skipped; merged cells are
  /// stamped with `frame`. Returns the number of points merged.
  static std::size_t merge_chunk_runs(const Config& cfg, Cell* cells, std::uint32_t frame,
                                      const ChunkRuns& runs);
  /// merge_run run after run (what merge_chunk_runs does without AVX2).
  static std::size_t merge_chunk_runs_scalar(const Config& cfg, Cell* cells, std::uint32_t frame,
                                             const ChunkRuns& runs);

  /// The precision cap merge_run takes: 1 / min_variance (infinite without a floor).
  static double max_precision(const Config& cfg) {
    return cfg.min_variance_m2 > 0 ? 1.0 / cfg.min_variance_m2
                                   : std::numeric_limits<double>::infinity();
  }

  /// Sequential single-point update (the SPEC 6.2 recursion), for tests and references.
  static void update(const Config& cfg, Cell& c, double z_m, double vm_m2) {
    Sums s;
    s.add(1.0 / vm_m2, 0, 0, 0);
    merge_frame(cfg, c, s, z_m, 0);
  }

  /// Whether age() changes what a cell exports: the variance grows every frame.
  static bool ages_exports(const Config& cfg) { return cfg.time_inflation_m2 > 0; }

  /// The inflation of `frames` frames at once: var += frames q, i.e.
  /// precision = 1 / (1 / precision + frames q). Layers apply it lazily, when a cell is
  /// next merged or read, so that a frame does not pass over every cell.
  static void age(const Config& cfg, Cell& c, std::uint32_t frames) {
    if (known(c) && cfg.time_inflation_m2 > 0 && frames > 0)
      c.precision = static_cast<float>(
          double(c.precision) / (1.0 + double(frames) * cfg.time_inflation_m2 * c.precision));
  }

  /// Pooling view: each cell is one measurement (mu, var): weight 1/var.
  static Moments to_moments(const Cell& c) {
    Moments m;
    if (!known(c)) return m;
    m.w = c.precision;
    m.mz = mean(c);
    m.szz = 1.0;  // w * var: keeps OMG parents' spread meaning consistent
    m.count = 1;
    return m;
  }
  static void from_moments(const Config& cfg, Cell& c, const Moments& m) {
    if (m.empty()) {
      clear(c);
      return;
    }
    c.mean_m.set(m.mz);
    c.precision = floored(cfg, m.w);
  }

  static float height(const Cell& c) {
    return known(c) ? static_cast<float>(mean(c)) : std::numeric_limits<float>::quiet_NaN();
  }
  static float variance(const Cell& c) {
    return known(c) ? 1.0f / c.precision : std::numeric_limits<float>::quiet_NaN();
  }
};

}  // namespace hazmap

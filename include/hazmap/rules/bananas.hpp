#pragma once
// Baseline rule (SPEC 6.1): the cell holds the height of the last point that fell in
// it, and that point's sensor height variance Sigma_zz (what it knows about the height).
// No fusion; the reference the other rules are measured against.

#include <cmath>
#include <cstdint>
#include <limits>

#include "hazmap/map/moments.hpp"
#include "hazmap/map/point_chunk.hpp"
#include "hazmap/rules/merge_policy.hpp"
#include "hazmap/rules/run_view.hpp"

namespace hazmap {

struct BananasRule {
  static constexpr const char* kName = "bananas";
  // Traits (rules/update_rule.hpp), the same four in the same order in every rule:
  /// Piecewise-constant cells: height and variance, no plane.
  static constexpr bool kHasPlane = false;
  /// The last point wins whatever the grouping: runs merge one by one straight into their
  /// cells (run_sums reads the run's last point from the chunk).
  static constexpr MergePolicy kMerge = MergePolicy::per_run;
  /// The layer keeps each cell's last-merge frame beside the cells.
  static constexpr bool kStampInCell = false;
  /// No SPEC 4 consistency gate.
  static constexpr bool kHeightGate = false;

  struct Config {};
  struct Cell {
    float height_m = std::numeric_limits<float>::quiet_NaN();
    float variance_m2 = std::numeric_limits<float>::quiet_NaN();  ///< last point's Sigma_zz
  };
  /// The frame's last point (scan-line order), relative to the reference.
  struct Sums {
    double last_z = 0;
    float last_var = 0;  ///< its Sigma_zz [m^2]
    std::uint32_t count = 0;
  };

  static bool known(const Cell& c) { return !std::isnan(c.height_m); }
  static void clear(Cell& c) { c = Cell{}; }
  static float reference_z(const Cell& c) { return c.height_m; }
  static const float* weights(const PointChunk& c) { return c.inv_var_z; }  // unused
  /// Sums of run r of the chunk (points in one cell), relative to the run's first height:
  /// the last point counts.
  static Sums run_sums(const PointChunk& chunk, const ChunkRuns& runs, int r) {
    Sums s;
    const int last = runs.end(r) - 1;
    s.last_z = double(chunk.z[last]) - double(chunk.z[runs.begin(r)]);
    s.last_var = chunk.var_z[last];
    s.count = static_cast<std::uint32_t>(runs.end(r) - runs.begin(r));
    return s;
  }
  static void merge_frame(const Config&, Cell& c, const Sums& s, double z_ref_m, double) {
    if (s.count > 0) {
      c.height_m = static_cast<float>(z_ref_m + s.last_z);
      c.variance_m2 = s.last_var;
    }
  }
  /// Nothing ages, so this is merge_frame.
  static void merge_run(const Config& cfg, Cell& c, const Sums& s, double z_ref_m, std::uint32_t,
                        double) {
    merge_frame(cfg, c, s, z_ref_m, 0.0);
  }
  /// No precision to cap (merge_run ignores its last argument).
  static double max_precision(const Config&) { return 0.0; }
  static void update(const Config&, Cell& c, double z_m, double vm_m2) {
    c.height_m = static_cast<float>(z_m);
    c.variance_m2 = static_cast<float>(vm_m2);
  }
  /// Nothing changes with time.
  static void age(const Config&, Cell&, std::uint32_t) {}
  /// Whether age() changes what a cell exports (its height or variance).
  static bool ages_exports(const Config&) { return false; }
  /// Pooling view: an unweighted height sample with its variance (szz = w var, as OMG),
  /// so that a pooled parent's variance is the children's mean variance plus the spread
  /// of their heights.
  static Moments to_moments(const Cell& c) {
    Moments m;
    if (!known(c)) return m;
    m.w = 1.0;
    m.mz = c.height_m;
    m.szz = c.variance_m2;
    m.noise_var = c.variance_m2;
    m.count = 1;
    return m;
  }
  static void from_moments(const Config&, Cell& c, const Moments& m) {
    if (m.empty()) {
      c = Cell{};
      return;
    }
    c.height_m = static_cast<float>(m.mz);
    c.variance_m2 = static_cast<float>(m.szz / m.w);
  }
  static float height(const Cell& c) { return c.height_m; }
  /// The sensor height variance of the last point (NaN on an unknown cell).
  static float variance(const Cell& c) { return c.variance_m2; }
};

}  // namespace hazmap

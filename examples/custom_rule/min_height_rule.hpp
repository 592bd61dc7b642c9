#pragma once
// A complete update rule outside the library (rules/update_rule.hpp): one struct, checked
// at compile time by RollingLayer<MinHeightRule> (hazmap/map/rolling_layer.hpp), which
// gives it the map's insertion, rolling, pooling and export. examples/custom_rule/main.cpp
// runs it; tests/rules/update_rule_test.cpp holds it to the properties every rule has.
// To let a configuration name it (map.layers[].rule: min_height) it joins the registry
// inside hazmap: an enumerator in RuleKind (core/core_config.hpp), its #include and one
// RuleEntry line in rules/rule_registry.hpp, and its settings, if any, in rules.<name>.

#include <cmath>
#include <cstdint>
#include <limits>

#include "hazmap/map/moments.hpp"
#include "hazmap/map/point_chunk.hpp"
#include "hazmap/rules/merge_policy.hpp"
#include "hazmap/rules/run_view.hpp"

namespace custom_rule {

/// A rule written outside the library: a cell holds the lowest height of the points that
/// fell in it, and that point's sensor height variance Sigma_zz. The minimum does not depend on how the
/// points are grouped, so runs merge straight into their cells. No ageing, no gate, no
/// plane. Pooling (finest_then_pool) sees a cell as one height sample, like the baseline.
struct MinHeightRule {
  static constexpr const char* kName = "min_height";
  // Traits (rules/update_rule.hpp), the same four in the same order in every rule:
  /// Piecewise-constant cells: height and variance, no plane.
  static constexpr bool kHasPlane = false;
  /// The minimum is the same whatever the grouping: runs merge one by one straight into
  /// their cells (run_sums reads the run's points from the chunk).
  static constexpr hazmap::MergePolicy kMerge = hazmap::MergePolicy::per_run;
  /// The layer keeps each cell's last-merge frame beside the cells.
  static constexpr bool kStampInCell = false;
  /// No SPEC 4 consistency gate.
  static constexpr bool kHeightGate = false;

  struct Config {};
  struct Cell {
    float height_m = std::numeric_limits<float>::quiet_NaN();
    float variance_m2 = std::numeric_limits<float>::quiet_NaN();
  };
  /// The lowest point of a run, relative to the reference height, and its Sigma_zz.
  struct Sums {
    double min_dz = std::numeric_limits<double>::infinity();
    float var = 0.0f;
  };

  static bool known(const Cell& c) { return !std::isnan(c.height_m); }
  static void clear(Cell& c) { c = Cell{}; }
  static void age(const Config&, Cell&, std::uint32_t) {}
  static bool ages_exports(const Config&) { return false; }
  /// Run r's lowest point, relative to the run's first height (which merge_run gets).
  static Sums run_sums(const hazmap::PointChunk& chunk, const hazmap::ChunkRuns& runs, int r) {
    Sums s;
    const double z0 = chunk.z[runs.begin(r)];
    for (int i = runs.begin(r); i < runs.end(r); ++i) {
      const double dz = double(chunk.z[i]) - z0;
      if (dz < s.min_dz) {
        s.min_dz = dz;
        s.var = chunk.var_z[i];
      }
    }
    return s;
  }
  static void merge_run(const Config&, Cell& c, const Sums& s, double z_ref_m, std::uint32_t,
                        double) {
    if (!(s.min_dz < std::numeric_limits<double>::infinity())) return;
    const auto z = static_cast<float>(z_ref_m + s.min_dz);  // exact: a float plus its offset
    if (!known(c) || z < c.height_m) {
      c.height_m = z;
      c.variance_m2 = s.var;
    }
  }
  static double max_precision(const Config&) { return 0.0; }
  static hazmap::Moments to_moments(const Cell& c) {
    hazmap::Moments m;
    if (!known(c)) return m;
    m.w = 1.0;
    m.mz = c.height_m;
    m.szz = c.variance_m2;
    m.noise_var = c.variance_m2;
    m.count = 1;
    return m;
  }
  static void from_moments(const Config&, Cell& c, const hazmap::Moments& m) {
    if (m.empty()) {
      clear(c);
      return;
    }
    c.height_m = static_cast<float>(m.mz);
    c.variance_m2 = static_cast<float>(m.szz / m.w);
  }
  static float height(const Cell& c) { return c.height_m; }
  static float variance(const Cell& c) { return c.variance_m2; }
};

}  // namespace custom_rule

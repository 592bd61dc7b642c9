#pragma once
// Optimal mixture of Gaussians rule (SPEC 6.3): (mu, var, S), weights w = 1/vm.
//
//   S' = S + w,  mu' = mu + (w/S')(z - mu),  var' = (S var + w (z - mu)(z - mu') + 1) / S'
//
// so S var = sum w (z - mu)^2 + n: var is the weighted sample spread plus the mean
// measurement variance. A frame's points in a cell are summed (sum w, sum w z,
// sum w z^2, n, relative to a reference height) and merged with the exact moment merge,
// which equals the recursion above; the weight cap S <= max_weight and the decay
// S *= decay act once per frame.

#include <cmath>
#include <cstdint>
#include <limits>

#include "hazmap/core/core_config.hpp"
#include "hazmap/map/internal/run_sums.hpp"
#include "hazmap/map/internal/split_height.hpp"
#include "hazmap/map/moments.hpp"
#include "hazmap/map/point_chunk.hpp"
#include "hazmap/rules/merge_policy.hpp"

namespace hazmap {

struct OmgRule {
  static constexpr const char* kName = "omg";
  // Traits (rules/update_rule.hpp), the same four in the same order in every rule:
  /// Piecewise-constant cells: height and variance, no plane.
  static constexpr bool kHasPlane = false;
  /// The weight cap applies once per frame: runs go to a frame accumulator (add_run).
  static constexpr MergePolicy kMerge = MergePolicy::per_frame;
  /// The layer keeps each cell's last-merge frame beside the cells.
  static constexpr bool kStampInCell = false;
  /// Has the SPEC 4 consistency gate (gate_state).
  static constexpr bool kHeightGate = true;
  /// finest_then_pool pools OMG layers with Kalman layers (SPEC 5): both cells pool as a
  /// weighted height (to_moments: w = weight or precision, mz), so they are one family
  /// (rules/rule_registry.hpp; a rule without kPoolFamily pools only with itself).
  static constexpr const char* kPoolFamily = "kalman";

  /// As read from rules.omg (core/core_config.hpp): max_weight, decay, gate_sigma.
  using Config = OmgConfig;

  struct Cell {
    SplitHeight mean_m;
    float variance_m2 = std::numeric_limits<float>::quiet_NaN();  ///< NaN: never observed
    float weight = 0.0f;   ///< S
  };

  struct Sums {
    double w = 0, wz = 0, wzz = 0;
    std::uint32_t count = 0;
    void add(double wt, double, double, double z) {
      w += wt;
      const double t = wt * z;
      wz += t;
      wzz += t * z;
      ++count;
    }
  };

  static bool known(const Cell& c) { return !std::isnan(c.variance_m2); }
  static void clear(Cell& c) { c = Cell{}; }

  /// SPEC 4 consistency gate: the cell's height and variance a point is tested against
  /// (decay changes S only); false if the cell is unknown (no gate).
  static bool gate_state(const Config&, const Cell& c, std::uint32_t, double* mu, double* var) {
    if (!known(c)) return false;
    *mu = mean(c);
    *var = c.variance_m2;
    return true;
  }
  static double mean(const Cell& c) { return c.mean_m.value(); }
  static float reference_z(const Cell& c) { return c.mean_m.ref_m; }
  static const float* weights(const PointChunk& c) { return c.inv_var_z; }
  /// Adds a run of points in this cell (z relative to z_ref_m) to a frame's sums.
  static void add_run(const Config&, Sums& s, const RunPoints& run, double z_ref_m) {
    const HeightSums h = height_run(run, z_ref_m);
    s.w += h.w;
    s.wz += h.wz;
    s.wzz += h.wzz;
    s.count += static_cast<std::uint32_t>(run.end - run.begin);
  }

  static Moments to_moments(const Cell& c) {
    Moments m;
    if (!known(c)) return m;
    m.w = c.weight;
    m.mz = mean(c);
    m.szz = double(c.weight) * double(c.variance_m2);
    m.count = 1;
    return m;
  }
  static void from_moments(const Config& cfg, Cell& c, const Moments& m) {
    if (m.empty()) {
      clear(c);
      return;
    }
    c.mean_m.set(m.mz);
    c.variance_m2 = static_cast<float>(m.szz / m.w);
    c.weight = static_cast<float>(std::min(m.w, cfg.max_weight));
  }

  static void merge_frame(const Config& cfg, Cell& c, const Sums& s, double z_ref_m, double) {
    if (!(s.w > 0)) return;
    Moments f;
    f.w = s.w;
    const double u = s.wz / s.w;
    f.mz = z_ref_m + u;
    f.szz = std::max(0.0, s.wzz - s.w * u * u) + s.count;  // spread + n (the "+1" per point)
    f.count = s.count;
    Moments m = to_moments(c);
    m.merge(f);
    from_moments(cfg, c, m);
  }

  static void update(const Config& cfg, Cell& c, double z_m, double vm_m2) {
    Sums s;
    s.add(1.0 / vm_m2, 0, 0, 0);
    merge_frame(cfg, c, s, z_m, 0);
  }

  /// Whether age() changes what a cell exports: no, decay scales S only, which neither the
  /// height nor the variance shows (it weighs later points).
  static bool ages_exports(const Config&) { return false; }

  /// The decay of `frames` frames at once: S *= decay^frames (applied lazily by layers).
  static void age(const Config& cfg, Cell& c, std::uint32_t frames) {
    if (known(c) && frames > 0 && cfg.decay != 1.0)
      c.weight = static_cast<float>(
          c.weight * (frames == 1 ? cfg.decay : std::pow(cfg.decay, double(frames))));
  }

  static float height(const Cell& c) {
    return known(c) ? static_cast<float>(mean(c)) : std::numeric_limits<float>::quiet_NaN();
  }
  static float variance(const Cell& c) { return c.variance_m2; }
};

}  // namespace hazmap

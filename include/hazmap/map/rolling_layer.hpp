#pragma once
// A layer whose cells follow update rule `Rule` (rules/*.hpp). What a rule must provide
// is written down, and checked at compile time, in rules/update_rule.hpp.
//
// Insertion works on chunks of points in two passes. Pass 1 maps every point to its
// storage slot with straight-line SIMD arithmetic (internal/chunk_slots.hpp): one multiply per
// axis (no division by the resolution), a floor, a bounds test and a conditional
// subtract for the ring wrap (no modulo, no table, no branch). Pass 2 works
// on the runs of equal slots (scan lines cross cells in runs). Rules whose merge does not
// depend on how a frame's points are grouped (Rule::kMergePerRun: Kalman, the baseline)
// list the chunk's runs and sum them without a branch on where runs end
// (internal/chunk_runs.hpp), then merge each run straight into its cell. The others (CCM and OMG
// apply their weight cap once per frame, SPEC 6.3-6.4) sum each run in registers into
// the cell's frame accumulator and merge each touched cell once per frame. Ageing (time
// inflation, decay) is lazy, see begin_frame. All buffers are allocated in the
// constructor.
//
// SPEC 4 gates: pass 1 drops points whose lateral variance exceeds the layer's gate (any
// rule; without a gate pass 1 does not read it). Rules with Rule::kHeightGate (Kalman,
// OMG) with gate_sigma > 0 then run a simpler pass between pass 1 and 2 that drops
// (slot -1) points inconsistent with their cell as it stands at the start of the chunk
// (Kalman merges run by run, so earlier chunks of the frame count) or of the frame (OMG
// merges once per frame); see gate_heights. With gate_sigma = 0 that pass is skipped.

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <vector>

#include "hazmap/map/internal/chunk_runs.hpp"
#include "hazmap/map/internal/chunk_slots.hpp"
#include "hazmap/map/internal/lazy_ageing.hpp"
#include "hazmap/map/internal/run_sums.hpp"
#include "hazmap/map/layer.hpp"
#include "hazmap/rules/update_rule.hpp"

namespace hazmap {

template <class Rule>
class RollingLayer final : public Layer {
  static_assert(check_update_rule<Rule>(),
                "RollingLayer<Rule>: Rule is not an update rule (see the messages above and "
                "include/hazmap/rules/update_rule.hpp)");

 public:
  /// `gate_std_m` > 0 drops points whose lateral standard deviation exceeds it (SPEC 4
  /// max_std_ratio); `pooled` allocates the prior and coverage state of finest_then_pool.
  /// The consistency gate's gate_sigma comes from the rule's config (Rule::kHeightGate).
  RollingLayer(int size, double resolution_m, const typename Rule::Config& config,
               double gate_std_m = 0.0, bool pooled = false)
      : grid_(size, resolution_m),
        config_(config),
        inv_resolution_(1.0 / resolution_m),
        gate_var_(gate_std_m > 0 ? static_cast<float>(gate_std_m * gate_std_m)
                                 : std::numeric_limits<float>::infinity()),
        cells_(cell_count()),
        accumulators_(Rule::kMergePerRun ? 0 : cell_count()),
        updated_frame_(Rule::kStampInCell ? 0 : cell_count(), 0),
        frame_index_(Rule::kMergePerRun ? 0 : cell_count(), 0),
        touched_(Rule::kMergePerRun ? 0 : cell_count(), 0),
        slot_buf_(PointChunk::kStride, kNoSlot),
        x_buf_(PointChunk::kStride, 0.0f),
        y_buf_(PointChunk::kStride, 0.0f),
        runs_(Rule::kUsesHeightSums) {
    if (pooled) {
      prior_.resize(cell_count());
      covered_.assign(cell_count(), 0);
    }
  }

  void begin_frame(double robot_x_m, double robot_y_m, std::uint32_t frame) override {
    frame_ = frame;
    const NewRegions regions = grid_.move_to(robot_x_m, robot_y_m);
    for (int k = 0; k < regions.count; ++k) clear(regions.ranges[k]);
    // Time inflation / decay (Rule::age) is lazy: a cell catches up on the frames since
    // its last merge when it is next merged or read, so a frame costs nothing per cell.
    // Pooled layers keep the per-frame pass: their covered cells are rebuilt from a prior
    // every frame, which is not a merge.
    if (!covered_.empty())
      for (auto& cell : cells_) Rule::age(config_, cell, 1);
  }

  void begin_insert() override {
    touched_count_ = 0;
    gates_ = GateCounts{};
  }

  GateCounts gate_counts() const override { return gates_; }

  std::size_t insert_chunk(const PointChunk& chunk) override {
    const int n = grid_.size();
    int* const slot = slot_buf_.data();
    float* const cx = x_buf_.data();
    float* const cy = y_buf_.data();
    // Pass 1: each point's storage slot (-1: outside or gated) and cell-centred x, y.
    WindowIndex window;
    window.x0_m = static_cast<double>(grid_.origin_x()) * grid_.resolution_m();
    window.y0_m = static_cast<double>(grid_.origin_y()) * grid_.resolution_m();
    window.inv_resolution = inv_resolution_;
    window.size = n;
    window.wrap_x = wrap_index(grid_.origin_x(), n);
    window.wrap_y = wrap_index(grid_.origin_y(), n);
    int gated;
    if constexpr (Rule::kHasPlane)
      gated = locate_points(chunk, window, gate_var_, slot, cx, cy);
    else
      gated = locate_points(chunk, window, gate_var_, slot, nullptr, nullptr);
    gates_.std_gate += static_cast<std::size_t>(gated);
    if constexpr (Rule::kHeightGate)
      if (config_.gate_sigma > 0) gate_heights(chunk);
    if constexpr (Rule::kMergePerRun)
      return merge_runs(chunk);
    else
      return accumulate_runs(chunk);
  }

  void end_insert() override {
    const double r = grid_.resolution_m();
    for (int k = 0; k < touched_count_; ++k) {
      const int slot = touched_[k];
      __builtin_prefetch(&cells_[touched_[std::min(k + kPrefetchCells, touched_count_ - 1)]], 1);
      const Accumulator& a = accumulators_[k];
      catch_up(slot);
      Rule::merge_frame(config_, cells_[slot], a.sums, a.z_ref, r);
      stamp(cells_.data(), updated_frame_.data(), slot) = frame_;
    }
  }

  void update_coverage(const RollingGrid& finer) override {
    if (covered_.empty()) return;
    const int n = grid_.size();
    const auto ratio =
        static_cast<CellIndex>(std::llround(grid_.resolution_m() / finer.resolution_m()));
    const CellIndex f0x = finer.origin_x(), f0y = finer.origin_y(), fn = finer.size();
    for (int ly = 0; ly < n; ++ly) {
      const CellIndex iy = grid_.origin_y() + ly;
      const bool in_y = iy * ratio >= f0y && iy * ratio + ratio <= f0y + fn;
      for (int lx = 0; lx < n; ++lx) {
        const CellIndex ix = grid_.origin_x() + lx;
        const bool now = in_y && ix * ratio >= f0x && ix * ratio + ratio <= f0x + fn;
        const int slot = grid_.slot(ix, iy);
        if (now && !covered_[slot]) prior_[slot] = cells_[slot];  // SPEC 5: prior at covering
        covered_[slot] = now;
      }
    }
  }

  void pool_into(PoolGrid& pool, const Layer& parent) const override {
    const RollingGrid& pg = parent.grid();
    const double rc = grid_.resolution_m(), rp = pg.resolution_m();
    const auto ratio = static_cast<CellIndex>(std::llround(rp / rc));
    const int n = grid_.size();
    for (int ly = 0; ly < n; ++ly) {
      const CellIndex iy = grid_.origin_y() + ly;
      const CellIndex py = floor_div(iy, ratio);
      for (int lx = 0; lx < n; ++lx) {
        const CellIndex ix = grid_.origin_x() + lx;
        const CellIndex px = floor_div(ix, ratio);
        if (!pg.contains(px, py)) continue;
        const int pslot = pg.slot(px, py);
        if (!parent.covered(pslot)) continue;
        const typename Rule::Cell c = current(grid_.slot(ix, iy));
        if (!Rule::known(c)) continue;
        Moments m = Rule::to_moments(c);
        // Child-centric -> parent-centric coordinates.
        m.shift(cell_center(ix, rc) - cell_center(px, rp),
                cell_center(iy, rc) - cell_center(py, rp));
        pool.cells[pslot].merge(m);
      }
    }
  }

  void rebuild_covered(PoolGrid& pool) override {
    if (covered_.empty()) return;
    if (pool.cells.size() != cell_count()) pool.cells.assign(cell_count(), Moments{});
    for (std::size_t slot = 0; slot < cell_count(); ++slot) {
      if (!covered_[slot]) continue;
      Moments m = Rule::to_moments(prior_[slot]);
      m.merge(pool.cells[slot]);
      Rule::from_moments(config_, cells_[slot], m);
      pool.cells[slot] = Moments{};  // ready for the next frame
    }
  }

  bool covered(int slot) const override { return !covered_.empty() && covered_[slot]; }

  void export_grids(LayerGrids& out, const PoseUncertainty* pose, double robot_x_m,
                    double robot_y_m) const override {
    const int n = grid_.size();
    const double r = grid_.resolution_m();
    const float nan = std::numeric_limits<float>::quiet_NaN();
    auto reset = [&](DenseGrid& g) {
      g.reset(n, n, r, grid_.center_x_m(), grid_.center_y_m(), nan);
    };
    reset(out.height);
    reset(out.variance);
    if constexpr (Rule::kHasPlane) {
      for (DenseGrid* g : plane_grids(out)) reset(*g);
    } else {
      for (DenseGrid* g : plane_grids(out)) g->reset(0, 0, r, grid_.center_x_m(), grid_.center_y_m(), nan);
    }
    export_cells(out, GridRect::full(n, n));
    if (pose) inflate_variance(out, *pose, robot_x_m, robot_y_m);
  }

  void export_region(LayerGrids& out, const GridRect& rect) const override {
    const float nan = std::numeric_limits<float>::quiet_NaN();
    const GridRect cut = rect.clipped(grid_.size(), grid_.size());
    if (cut.empty()) return;
    // Like export_grids: every grid gets the window's centre, also the plane grids a layer
    // without a plane leaves empty.
    auto clear = [&](DenseGrid& g) {
      g.center_x_m = grid_.center_x_m();
      g.center_y_m = grid_.center_y_m();
      if (g.rows > 0) g.fill_rect(cut.row0, cut.row1, cut.col0, cut.col1, nan);
    };
    clear(out.height);
    clear(out.variance);
    for (DenseGrid* g : plane_grids(out)) clear(*g);
    export_cells(out, cut);
  }

  bool ages_exports() const override { return Rule::ages_exports(config_); }

  Moments cell_moments(CellIndex ix, CellIndex iy) const override {
    if (!grid_.contains(ix, iy)) return Moments{};
    return Rule::to_moments(current(grid_.slot(ix, iy)));
  }

  const char* rule_name() const override { return Rule::kName; }
  bool has_plane() const override { return Rule::kHasPlane; }
  const RollingGrid& grid() const override { return grid_; }

  /// The cell at a global index as of this frame (tests). Requires grid().contains(ix, iy).
  typename Rule::Cell cell(CellIndex ix, CellIndex iy) const { return current(grid_.slot(ix, iy)); }
  const typename Rule::Config& config() const { return config_; }

 private:
  /// Writes the known cells of `rect` into grids that hold NaN there.
  void export_cells(LayerGrids& out, const GridRect& rect) const {
    const int n = grid_.size();
    const double r = grid_.resolution_m();
    for (int row = rect.row0; row < rect.row1; ++row) {
      const CellIndex iy = grid_.origin_y() + (n - 1 - row);
      for (int col = rect.col0; col < rect.col1; ++col) {
        const CellIndex ix = grid_.origin_x() + col;
        const typename Rule::Cell c = current(grid_.slot(ix, iy));
        if (!Rule::known(c)) continue;
        if constexpr (Rule::kHasPlane) {
          // SPEC 6.4: an evaluable cell publishes its plane at the centre; any other its
          // mean height, no slopes, and a variance that covers the unmeasured tilt.
          const bool evaluable = Rule::evaluable(config_, c, r);
          if (evaluable) {
            double a, b;
            Rule::slopes(config_, c, &a, &b);
            out.height.at(row, col) = static_cast<float>(Rule::height_at(config_, c, 0.0, 0.0));
            out.slope_x.at(row, col) = static_cast<float>(a);
            out.slope_y.at(row, col) = static_cast<float>(b);
          } else {
            out.height.at(row, col) = static_cast<float>(Rule::mean_z(c));
          }
          out.variance.at(row, col) =
              static_cast<float>(Rule::published_variance(config_, c, r, evaluable));
          out.roughness.at(row, col) = static_cast<float>(Rule::roughness(config_, c));
          out.coverage.at(row, col) = static_cast<float>(Rule::coverage(c, r));
          out.evaluable.at(row, col) = evaluable ? 1.0f : 0.0f;
          out.count.at(row, col) = static_cast<float>(c.count);
          out.noise_variance.at(row, col) = c.noise_var_m2;
          out.lateral_xx.at(row, col) = c.sxx / c.w;
          out.lateral_yy.at(row, col) = c.syy / c.w;
          out.lateral_xy.at(row, col) = c.sxy / c.w;
          out.lateral_xz.at(row, col) = c.sxz / c.w;
          out.lateral_yz.at(row, col) = c.syz / c.w;
        } else {
          out.height.at(row, col) = Rule::height(c);
          out.variance.at(row, col) = Rule::variance(c);
        }
      }
    }
  }

  static constexpr int kPrefetchPoints = 32;  ///< ~4 runs ahead on a 1 cm layer
  static constexpr int kPrefetchRuns = 4;
  static constexpr int kPrefetchCells = 8;

  struct Accumulator {
    typename Rule::Sums sums;
    float z_ref = 0.0f;
  };

  /// The grids only layers with a plane fill.
  static std::array<DenseGrid*, 12> plane_grids(LayerGrids& out) {
    return {&out.count,     &out.slope_x,    &out.slope_y,    &out.roughness,
            &out.coverage,  &out.evaluable,  &out.noise_variance, &out.lateral_xx,
            &out.lateral_yy, &out.lateral_xy, &out.lateral_xz, &out.lateral_yz};
  }

  std::size_t cell_count() const {
    return static_cast<std::size_t>(grid_.size()) * static_cast<std::size_t>(grid_.size());
  }

  static CellIndex floor_div(CellIndex a, CellIndex b) {
    const CellIndex q = a / b;
    return (a % b != 0 && ((a < 0) != (b < 0))) ? q - 1 : q;
  }

  /// Whether points in `slot` go into this layer: inside the window (slot >= 0) and, when
  /// pooling, not covered (a covered cell's points are in the finer layer).
  bool takes(int slot) const {
    return covered_.empty() ? takes<false>(slot, nullptr) : takes<true>(slot, covered_.data());
  }
  template <bool kPooled>
  static bool takes(int slot, const unsigned char* covered) {
    return slot >= 0 && !(kPooled && covered[slot]);
  }

  /// Frames of Rule::age a cell last merged in frame `last` still owes in frame `now`:
  /// none on pooled layers (aged every frame), and none if frame numbers went backwards.
  static std::uint32_t owed_frames(std::uint32_t now, std::uint32_t last, bool pooled) {
    return pooled ? 0 : hazmap::owed_frames(now, last);
  }
  std::uint32_t owed_frames(int slot) const {
    return owed_frames(frame_, last_merge(slot), !covered_.empty());
  }
  /// The frame of a cell's last merge: in the cell (Rule::kStampInCell) or beside it.
  static std::uint32_t& stamp(typename Rule::Cell* cells, std::uint32_t* stamps, int slot) {
    if constexpr (Rule::kStampInCell)
      return cells[slot].stamp;
    else
      return stamps[slot];
  }
  std::uint32_t last_merge(int slot) const {
    if constexpr (Rule::kStampInCell)
      return cells_[slot].stamp;
    else
      return updated_frame_[slot];
  }
  /// Applies the owed ageing before a merge (the merge then stamps the frame).
  void catch_up(int slot) {
    const std::uint32_t owed = owed_frames(slot);
    if (owed > 0) Rule::age(config_, cells_[slot], owed);
  }
  /// The cell as of this frame, for reading.
  typename Rule::Cell current(int slot) const {
    typename Rule::Cell c = cells_[slot];
    Rule::age(config_, c, owed_frames(slot));
    return c;
  }

  void clear(const CellRange& range) {
    for (CellIndex iy = range.y0; iy < range.y1; ++iy)
      for (CellIndex ix = range.x0; ix < range.x1; ++ix) {
        const int slot = grid_.slot(ix, iy);
        Rule::clear(cells_[slot]);
        if (!covered_.empty()) {
          Rule::clear(prior_[slot]);
          covered_[slot] = 0;
        }
      }
  }

  /// SPEC 7: variance += g^T Sigma_lat g + Sigma_zz for the noise added since the
  /// cell's last update; g from the plane (CCM) or central differences of heights.
  void inflate_variance(LayerGrids& out, const PoseUncertainty& pose, double rx, double ry) const {
    const int n = grid_.size();
    const double r = grid_.resolution_m();
    auto h = [&](int row, int col) -> double {
      if (row < 0 || col < 0 || row >= n || col >= n) return std::nan("");
      return out.height.at(row, col);
    };
    auto diff = [](double lo, double mid, double hi, double step) {
      if (!std::isnan(lo) && !std::isnan(hi)) return (hi - lo) / (2 * step);
      if (!std::isnan(hi)) return (hi - mid) / step;
      if (!std::isnan(lo)) return (mid - lo) / step;
      return 0.0;
    };
    for (int row = 0; row < n; ++row) {
      const CellIndex iy = grid_.origin_y() + (n - 1 - row);
      for (int col = 0; col < n; ++col) {
        const float v = out.variance.at(row, col);
        if (std::isnan(out.height.at(row, col))) continue;
        const CellIndex ix = grid_.origin_x() + col;
        double gx = std::nan(""), gy = std::nan("");
        if constexpr (Rule::kHasPlane) {
          gx = out.slope_x.at(row, col);
          gy = out.slope_y.at(row, col);
        }
        // Piecewise-constant cells, and CCM cells without slopes (not evaluable).
        if (std::isnan(gx) || std::isnan(gy)) {
          const double mid = h(row, col);
          gx = diff(h(row, col - 1), mid, h(row, col + 1), r);
          gy = diff(h(row + 1, col), mid, h(row - 1, col), r);  // row 0 = largest y
        }
        const double added =
            pose.added_variance(last_merge(grid_.slot(ix, iy)), cell_center(ix, r) - rx,
                                cell_center(iy, r) - ry, gx, gy);
        out.variance.at(row, col) = static_cast<float>((std::isnan(v) ? 0.0 : v) + added);
      }
    }
  }

  /// SPEC 4 consistency gate (Rule::kHeightGate, gate_sigma > 0): drops (slot -1) each
  /// point with (z - mu)^2 > gate_sigma^2 (var + Sigma_zz) against its cell's (mu, var) as
  /// it stands now (before this chunk's points), if the cell is known. Unknown cells take
  /// every point: a cell's first points are its evidence. Points of covered cells
  /// (pooling) are not this layer's and are not tested. The cell state is read once per
  /// run of equal slots.
  void gate_heights(const PointChunk& chunk) {
    const double g2 = config_.gate_sigma * config_.gate_sigma;
    int* const slot = slot_buf_.data();
    const float* const z = chunk.z;
    const float* const var_z = chunk.var_z;
    int last = -1;
    bool known = false;
    double mu = 0.0, var = 0.0;
    std::size_t rejected = 0;
    for (int i = 0; i < chunk.size; ++i) {
      const int s = slot[i];
      if (s < 0 || (!covered_.empty() && covered_[s])) continue;
      if (s != last) {
        last = s;
        known = Rule::gate_state(config_, cells_[s], owed_frames(s), &mu, &var);
      }
      if (!known) continue;
      const double d = double(z[i]) - mu;
      if (d * d > g2 * (var + double(var_z[i]))) {
        slot[i] = kNoSlot;
        ++rejected;
      }
    }
    gates_.consistency_gate += rejected;
  }

  /// Pass 2 for rules that merge each run straight into its cell: the chunk's runs as
  /// a list (internal/chunk_runs.hpp), then one merge per run.
  std::size_t merge_runs(const PointChunk& chunk) {
    runs_.find(slot_buf_.data(), chunk.size);
    if constexpr (Rule::kUsesHeightSums) runs_.sum_heights(Rule::weights(chunk), chunk.z);
    if constexpr (Rule::kMergesChunks) {
      // The rule merges a whole chunk's runs itself, except on pooled layers.
      if (covered_.empty())
        return Rule::merge_chunk_runs(config_, cells_.data(), frame_, runs_);
      return merge_run_list<true>(chunk);
    } else {
      return covered_.empty() ? merge_run_list<false>(chunk) : merge_run_list<true>(chunk);
    }
  }

  /// The merge loop, compiled apart for pooled layers (whose covered cells take no points
  /// and which owe no ageing) so that the other loop tests neither.
  template <bool kPooled>
  std::size_t merge_run_list(const PointChunk& chunk) {
    // Locals, so that the compiler need not reload members after each store to a cell.
    const typename Rule::Config cfg = config_;
    const double max_precision = Rule::max_precision(cfg);
    typename Rule::Cell* const cells = cells_.data();
    std::uint32_t* const stamps = updated_frame_.data();
    const unsigned char* const covered = covered_.data();
    const int* const run_slot = runs_.slots();
    const int* const starts = runs_.starts();
    const float* const z = chunk.z;
    const std::uint32_t frame = frame_;
    const int count = runs_.size();
    std::size_t used = 0;
    for (int k = 0; k < count; ++k) {
      // Fine layers are larger than the cache: fetch the cell a few runs ahead early.
      const int ahead = run_slot[std::min(k + kPrefetchRuns, count - 1)];
      if (ahead >= 0) {
        __builtin_prefetch(&cells[ahead], 1);
        if (!Rule::kStampInCell) __builtin_prefetch(&stamps[ahead], 1);
      }
      const int s = run_slot[k];
      if (!takes<kPooled>(s, covered)) continue;
      const int first = starts[k];
      used += static_cast<std::size_t>(starts[k + 1] - first);
      std::uint32_t& last = stamp(cells, stamps, s);
      Rule::merge_run(cfg, cells[s], Rule::run_sums(chunk, runs_, k), z[first],
                      owed_frames(frame, last, kPooled), max_precision);
      last = frame;
    }
    return used;
  }

  /// Pass 2 for rules whose weight cap acts once per frame (CCM, OMG): each run, summed
  /// in registers, goes to its cell's frame accumulator; end_insert merges them.
  std::size_t accumulate_runs(const PointChunk& chunk) {
    const int count = chunk.size;
    const int* const slot = slot_buf_.data();
    const float* const cx = x_buf_.data();
    const float* const cy = y_buf_.data();
    const float* const w = Rule::weights(chunk);
    std::size_t used = 0;
    for (int i = 0; i < count;) {
      const int s = slot[i];
      const int end = run_end(slot, i, count);
      const int ahead = slot[std::min(end + kPrefetchPoints, count - 1)];
      if (ahead >= 0) {
        __builtin_prefetch(&cells_[ahead]);
        __builtin_prefetch(&frame_index_[ahead]);
      }
      if (!takes(s)) {
        i = end;
        continue;
      }
      used += static_cast<std::size_t>(end - i);
      // Sparse set: frame_index_[s] is valid only if touched_ points back to s. The
      // frame's accumulators are packed in touch order, so they stay in cache.
      int k = frame_index_[s];
      if (static_cast<unsigned>(k) >= static_cast<unsigned>(touched_count_) || touched_[k] != s) {
        k = touched_count_++;
        frame_index_[s] = k;
        touched_[k] = s;
        Accumulator& fresh = accumulators_[k];
        fresh.sums = typename Rule::Sums{};
        fresh.z_ref = Rule::known(cells_[s]) ? Rule::reference_z(cells_[s]) : chunk.z[i];
      }
      Accumulator& a = accumulators_[k];
      Rule::add_run(a.sums, RunPoints{w, cx, cy, chunk.z, i, end, chunk.var_z}, a.z_ref);
      i = end;
    }
    return used;
  }

  RollingGrid grid_;
  typename Rule::Config config_;
  double inv_resolution_;
  float gate_var_;
  GateCounts gates_;  ///< this insertion's gate drops
  std::uint32_t frame_ = 0;
  std::vector<typename Rule::Cell> cells_;
  std::vector<Accumulator> accumulators_;
  std::vector<std::uint32_t> updated_frame_;  ///< each cell's last merge, unless in the cell
  std::vector<int> frame_index_;  ///< slot -> its accumulator this frame (see accumulate_runs)
  std::vector<int> touched_;      ///< accumulator -> slot, in order of first touch
  int touched_count_ = 0;
  // Per-chunk scratch: slot (-1: dropped) and cell-centred x, y of each point.
  std::vector<int> slot_buf_;
  std::vector<float> x_buf_, y_buf_;
  ChunkRuns runs_;  ///< the chunk's runs (merge-per-run rules)
  std::vector<typename Rule::Cell> prior_;
  std::vector<unsigned char> covered_;
};

}  // namespace hazmap

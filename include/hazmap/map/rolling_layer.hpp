#pragma once
// A layer whose cells follow update rule `Rule` (rules/*.hpp): a square window of cells
// that moves with the robot (RollingGrid, a ring buffer), fed chunk by chunk with map
// points and read as published grids. What a rule must provide is written down, and
// checked at compile time, in rules/update_rule.hpp.
//
// This class is the public surface and says what happens when; the work is done in
// map/internal/ (docs/insertion.md draws a point's way to its cell):
//   layer_cells.hpp      the cells and their lazy ageing: Rule::age catches up when a
//                        cell is next merged or read, so a frame costs nothing per cell
//   chunk_slots.hpp      insertion pass 1: each point -> its storage slot (SIMD), or
//                        kNoSlot outside the window or over the lateral-variance gate
//   layer_insertion.hpp  the SPEC 4 consistency gate, then pass 2: the runs of equal slots
//                        to the cells, as the rule's merge policy says (Rule::kMerge,
//                        rules/merge_policy.hpp): merged straight into their cells
//                        (per_run, per_chunk: the baseline, Kalman) or summed into
//                        per-frame accumulators and merged once per frame (per_frame:
//                        CCM, OMG)
//   layer_export.hpp     the cells -> published grids, plus the pose uncertainty (SPEC 7)
// All buffers are allocated in the constructor.
//
// SPEC 4 gates: pass 1 drops points whose lateral variance exceeds the layer's gate (any
// rule). Rules with Rule::kHeightGate (Kalman, OMG) and gate_sigma > 0 then drop points
// inconsistent with their cell as it stands at the start of the chunk (Kalman merges run
// by run, so earlier chunks of the frame count) or of the frame (OMG merges once per
// frame).
//
// Pooling (finest_then_pool, SPEC 5): on a pooled layer, cells a finer layer covers take
// no points; each frame they are rebuilt from their prior and the finer layer's pooled
// cells (update_coverage, pool_into, rebuild_covered).

#include <cmath>
#include <cstddef>
#include <cstdint>
#include <limits>
#include <vector>

#include "hazmap/map/internal/chunk_runs.hpp"
#include "hazmap/map/internal/chunk_slots.hpp"
#include "hazmap/map/internal/layer_cells.hpp"
#include "hazmap/map/internal/layer_export.hpp"
#include "hazmap/map/internal/layer_insertion.hpp"
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
        inv_resolution_(1.0 / resolution_m),
        gate_var_(gate_std_m > 0 ? static_cast<float>(gate_std_m * gate_std_m)
                                 : std::numeric_limits<float>::infinity()),
        cells_(cell_count(), config, pooled),
        accumulators_(merges_runs(Rule::kMerge) ? 0 : cell_count()),
        slot_buf_(PointChunk::kStride, kNoSlot),
        x_buf_(PointChunk::kStride, 0.0f),
        y_buf_(PointChunk::kStride, 0.0f),
        runs_(/*height_sums=*/Rule::kMerge == MergePolicy::per_chunk),
        prior_(pooled ? cell_count() : 0),
        covered_(pooled ? cell_count() : 0, 0) {}

  /// Whether this layer is pooled (finest_then_pool): its cells that a finer layer covers
  /// take no points and are rebuilt from their prior and the pooled finer cells each frame.
  bool pooled() const { return cells_.pooled(); }

  void begin_frame(double robot_x_m, double robot_y_m, std::uint32_t frame) override {
    cells_.set_frame(frame);
    const NewRegions regions = grid_.move_to(robot_x_m, robot_y_m);
    for (int k = 0; k < regions.count; ++k) clear(regions.ranges[k]);
    // Ageing (Rule::age) is lazy (internal/layer_cells.hpp), except on pooled layers:
    // their covered cells are rebuilt from a prior every frame, which is not a merge.
    if (pooled()) cells_.age_all();
  }

  void begin_insert() override {
    accumulators_.begin();
    gates_ = GateCounts{};
  }

  GateCounts gate_counts() const override { return gates_; }

  std::size_t insert_chunk(const PointChunk& chunk) override {
    int* const slot = slot_buf_.data();
    // Pass 1: each point's storage slot (kNoSlot: outside or gated) and, for plane rules,
    // its cell-centred x, y.
    const WindowIndex window = window_index();
    if constexpr (Rule::kHasPlane)
      gates_.std_gate += static_cast<std::size_t>(
          locate_points(chunk, window, gate_var_, slot, x_buf_.data(), y_buf_.data()));
    else
      gates_.std_gate +=
          static_cast<std::size_t>(locate_points(chunk, window, gate_var_, slot, nullptr, nullptr));
    if constexpr (Rule::kHeightGate)
      if (cells_.config().gate_sigma > 0)
        gates_.consistency_gate += layer_insertion::gate_heights(cells_, covered(), chunk, slot);
    // Pass 2: the runs of equal slots to the cells (internal/layer_insertion.hpp).
    if constexpr (merges_runs(Rule::kMerge))
      return layer_insertion::merge_runs(cells_, covered(), runs_, slot, chunk);
    else
      return accumulators_.add_runs(cells_, covered(), runs_, chunk, slot, x_buf_.data(),
                                    y_buf_.data());
  }

  void end_insert() override {
    if constexpr (Rule::kMerge == MergePolicy::per_frame)
      accumulators_.merge_into(cells_, grid_.resolution_m());
  }

  void update_coverage(const RollingGrid& finer) override {
    if (!pooled()) return;
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
        if (now && !covered_[slot]) prior_[slot] = cells_.raw(slot);  // SPEC 5: prior at covering
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
        const typename Rule::Cell c = cells_.current(grid_.slot(ix, iy));
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
    if (!pooled()) return;
    if (pool.cells.size() != cell_count()) pool.cells.assign(cell_count(), Moments{});
    for (std::size_t slot = 0; slot < cell_count(); ++slot) {
      if (!covered_[slot]) continue;
      Moments m = Rule::to_moments(prior_[slot]);
      m.merge(pool.cells[slot]);
      Rule::from_moments(cells_.config(), cells_.raw(static_cast<int>(slot)), m);
      pool.cells[slot] = Moments{};  // ready for the next frame
    }
  }

  bool covered(int slot) const override { return pooled() && covered_[slot]; }

  void export_grids(LayerGrids& out, const PoseUncertainty* pose, double robot_x_m,
                    double robot_y_m, const SeenWhole* seen_whole = nullptr) const override {
    const int n = grid_.size();
    const double r = grid_.resolution_m();
    const float nan = std::numeric_limits<float>::quiet_NaN();
    auto reset = [&](DenseGrid& g) {
      g.reset(n, n, r, grid_.center_x_m(), grid_.center_y_m(), nan);
    };
    reset(out.height);
    reset(out.variance);
    // Layers without a plane leave the plane grids empty.
    for (DenseGrid* g : layer_export::plane_grids(out)) {
      if constexpr (Rule::kHasPlane)
        reset(*g);
      else
        g->reset(0, 0, r, grid_.center_x_m(), grid_.center_y_m(), nan);
    }
    layer_export::export_cells(cells_, grid_, out, GridRect::full(n, n), seen_whole);
    if (pose) layer_export::inflate_variance(cells_, grid_, out, *pose, robot_x_m, robot_y_m);
  }

  void export_region(LayerGrids& out, const GridRect& rect,
                     const SeenWhole* seen_whole = nullptr) const override {
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
    for (DenseGrid* g : layer_export::plane_grids(out)) clear(*g);
    layer_export::export_cells(cells_, grid_, out, cut, seen_whole);
  }

  bool ages_exports() const override { return Rule::ages_exports(cells_.config()); }

  Moments cell_moments(CellIndex ix, CellIndex iy) const override {
    if (!grid_.contains(ix, iy)) return Moments{};
    return Rule::to_moments(cells_.current(grid_.slot(ix, iy)));
  }

  const char* rule_name() const override { return Rule::kName; }
  bool has_plane() const override { return Rule::kHasPlane; }
  const RollingGrid& grid() const override { return grid_; }

  /// The cell at a global index as of this frame (tests). Requires grid().contains(ix, iy).
  typename Rule::Cell cell(CellIndex ix, CellIndex iy) const {
    return cells_.current(grid_.slot(ix, iy));
  }
  const typename Rule::Config& config() const { return cells_.config(); }

 private:
  std::size_t cell_count() const {
    return static_cast<std::size_t>(grid_.size()) * static_cast<std::size_t>(grid_.size());
  }

  static CellIndex floor_div(CellIndex a, CellIndex b) {
    const CellIndex q = a / b;
    return (a % b != 0 && ((a < 0) != (b < 0))) ? q - 1 : q;
  }

  /// The window's position in the form pass 1 needs.
  WindowIndex window_index() const {
    const int n = grid_.size();
    WindowIndex window;
    window.x0_m = static_cast<double>(grid_.origin_x()) * grid_.resolution_m();
    window.y0_m = static_cast<double>(grid_.origin_y()) * grid_.resolution_m();
    window.inv_resolution = inv_resolution_;
    window.size = n;
    window.wrap_x = wrap_index(grid_.origin_x(), n);
    window.wrap_y = wrap_index(grid_.origin_y(), n);
    return window;
  }

  /// A pooled layer's coverage for the insertion loops, nullptr when not pooled.
  const unsigned char* covered() const { return pooled() ? covered_.data() : nullptr; }

  /// Forgets the cells of `range` (they left the window and come in anew).
  void clear(const CellRange& range) {
    for (CellIndex iy = range.y0; iy < range.y1; ++iy)
      for (CellIndex ix = range.x0; ix < range.x1; ++ix) {
        const int slot = grid_.slot(ix, iy);
        Rule::clear(cells_.raw(slot));
        if (pooled()) {
          Rule::clear(prior_[slot]);
          covered_[slot] = 0;
        }
      }
  }

  RollingGrid grid_;
  double inv_resolution_;
  float gate_var_;
  GateCounts gates_;  ///< this insertion's gate drops
  LayerCells<Rule> cells_;
  layer_insertion::FrameAccumulators<Rule> accumulators_;  ///< MergePolicy::per_frame only
  // Per-chunk scratch: slot (kNoSlot: dropped) and cell-centred x, y of each point.
  std::vector<int> slot_buf_;
  std::vector<float> x_buf_, y_buf_;
  ChunkRuns runs_;  ///< the chunk's runs
  // Pooled layers only (finest_then_pool, SPEC 5): each cell's state when a finer layer
  // came to cover it, and whether one covers it now.
  std::vector<typename Rule::Cell> prior_;
  std::vector<unsigned char> covered_;
};

}  // namespace hazmap

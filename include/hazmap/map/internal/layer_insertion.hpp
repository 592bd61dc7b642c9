#pragma once
// Part of RollingLayer's implementation; the public rolling_layer.hpp includes it (the layer
// is a template), so it is installed and visible, but it is no interface to build on.
// The loops of a layer's insertion after pass 1 (internal/chunk_slots.hpp has given every
// point its slot, kNoSlot when dropped): the SPEC 4 consistency gate, and pass 2, which
// lists the chunk's runs of equal slots (ChunkRuns::find, one list for both paths) and
// takes them to the cells in one of two ways (docs/insertion.md):
//
//   merge_runs           MergePolicy::per_run, per_chunk (the baseline, Kalman): the
//                        chunk's run list (ChunkRuns), then each run merged straight
//                        into its cell.
//   FrameAccumulators    MergePolicy::per_frame (CCM, OMG; caps that act once per frame,
//                        SPEC 6.3-6.4): each run summed into its cell's frame accumulator;
//                        merge_into merges each touched cell once, at the frame's end.
//
// `covered` is a pooled layer's coverage (a covered cell's points are in the finer layer
// and are not this layer's), nullptr on a layer that does not pool.

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <vector>

#include "hazmap/map/internal/chunk_runs.hpp"
#include "hazmap/map/internal/chunk_slots.hpp"
#include "hazmap/map/internal/layer_cells.hpp"
#include "hazmap/map/internal/run_sums.hpp"
#include "hazmap/map/point_chunk.hpp"
#include "hazmap/rules/merge_policy.hpp"

namespace hazmap {
namespace layer_insertion {

constexpr int kPrefetchRuns = 4;  ///< cells fetched this many runs ahead
constexpr int kPrefetchCells = 8;

/// Whether points in `slot` go into the layer: inside the window (slot >= 0) and, when
/// pooling (kPooled), not covered.
template <bool kPooled>
inline bool takes(int slot, const unsigned char* covered) {
  return slot >= 0 && !(kPooled && covered[slot]);
}

/// SPEC 4 consistency gate (Rule::kHeightGate, gate_sigma > 0): drops (slot kNoSlot) each
/// point with (z - mu)^2 > gate_sigma^2 (var + Sigma_zz) against its cell's (mu, var) as
/// it stands now (before this chunk's points), if the cell is known. Unknown cells take
/// every point: a cell's first points are its evidence. Points of covered cells are not
/// this layer's and are not tested. The cell state is read once per run of equal slots.
/// Returns how many points it dropped.
template <class Rule>
std::size_t gate_heights(const LayerCells<Rule>& cells, const unsigned char* covered,
                         const PointChunk& chunk, int* slot) {
  const auto& config = cells.config();
  const double g2 = config.gate_sigma * config.gate_sigma;
  const float* const z = chunk.z;
  const float* const var_z = chunk.var_z;
  int last = -1;
  bool known = false;
  double mu = 0.0, var = 0.0;
  std::size_t rejected = 0;
  for (int i = 0; i < chunk.size; ++i) {
    const int s = slot[i];
    if (s < 0 || (covered != nullptr && covered[s])) continue;
    if (s != last) {
      last = s;
      known = Rule::gate_state(config, cells.raw(s), cells.owed_frames(s), &mu, &var);
    }
    if (!known) continue;
    const double d = double(z[i]) - mu;
    if (d * d > g2 * (var + double(var_z[i]))) {
      slot[i] = kNoSlot;
      ++rejected;
    }
  }
  return rejected;
}

/// The per-run merge loop, compiled apart for pooled layers (whose covered cells take no
/// points and which owe no ageing) so that the other loop tests neither.
template <class Rule, bool kPooled>
std::size_t merge_run_list(LayerCells<Rule>& cells_in, const unsigned char* covered,
                           const ChunkRuns& runs, const PointChunk& chunk) {
  // Locals, so that the compiler need not reload members after each store to a cell.
  const typename Rule::Config cfg = cells_in.config();
  const double max_precision = Rule::max_precision(cfg);
  typename Rule::Cell* const cells = cells_in.data();
  std::uint32_t* const stamps = cells_in.stamps();
  const int* const run_slot = runs.slots();
  const int* const starts = runs.starts();
  const float* const z = chunk.z;
  const std::uint32_t frame = cells_in.frame();
  const int count = runs.size();
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
    std::uint32_t& last = LayerCells<Rule>::stamp(cells, stamps, s);
    Rule::merge_run(cfg, cells[s], Rule::run_sums(chunk, runs, k), z[first],
                    LayerCells<Rule>::owed_frames(frame, last, kPooled), max_precision);
    last = frame;
  }
  return used;
}

/// Pass 2 for rules that merge each run straight into its cell (MergePolicy::per_run,
/// per_chunk): the chunk's runs as a list (internal/chunk_runs.hpp), then one merge per
/// run, or (per_chunk, unpooled) the whole list to the rule. Returns the points merged.
template <class Rule>
std::size_t merge_runs(LayerCells<Rule>& cells, const unsigned char* covered, ChunkRuns& runs,
                       const int* slot, const PointChunk& chunk) {
  runs.find(slot, chunk.size);
  if constexpr (Rule::kMerge == MergePolicy::per_chunk) {
    runs.sum_heights(Rule::weights(chunk), chunk.z);
    // The rule merges a whole chunk's runs itself, except on pooled layers.
    if (covered == nullptr)
      return Rule::merge_chunk_runs(cells.config(), cells.data(), cells.frame(), runs);
    return merge_run_list<Rule, true>(cells, covered, runs, chunk);
  } else {
    return covered == nullptr ? merge_run_list<Rule, false>(cells, covered, runs, chunk)
                              : merge_run_list<Rule, true>(cells, covered, runs, chunk);
  }
}

/// Pass 2 for rules whose weight cap acts once per frame (MergePolicy::per_frame: CCM,
/// OMG): a frame's sums per touched cell. A sparse set: frame_index_[slot] is valid only
/// if touched_ points back to slot; the accumulators are packed in touch order, so they
/// stay in cache. Sized once, one entry per cell (none for rules that merge per run).
template <class Rule>
class FrameAccumulators {
 public:
  explicit FrameAccumulators(std::size_t cells)
      : accumulators_(cells), frame_index_(cells, 0), touched_(cells, 0) {}

  /// Forgets the frame's sums (begin_insert).
  void begin() { touched_count_ = 0; }

  /// Lists the chunk's runs and adds each, summed in registers, to its cell's
  /// accumulator. `slot`, `cx`, `cy`: pass 1's output. Returns the points taken.
  std::size_t add_runs(const LayerCells<Rule>& cells, const unsigned char* covered,
                       ChunkRuns& runs, const PointChunk& chunk, const int* slot,
                       const float* cx, const float* cy) {
    runs.find(slot, chunk.size);
    return covered == nullptr ? add_runs<false>(cells, covered, runs, chunk, cx, cy)
                              : add_runs<true>(cells, covered, runs, chunk, cx, cy);
  }

  /// Merges each touched cell's sums once, after its catch-up ageing, and stamps it.
  void merge_into(LayerCells<Rule>& cells, double cell_m) const {
    for (int k = 0; k < touched_count_; ++k) {
      const int slot = touched_[k];
      __builtin_prefetch(&cells.raw(touched_[std::min(k + kPrefetchCells, touched_count_ - 1)]),
                         1);
      const Accumulator& a = accumulators_[k];
      cells.catch_up(slot);
      Rule::merge_frame(cells.config(), cells.raw(slot), a.sums, a.z_ref, cell_m);
      LayerCells<Rule>::stamp(cells.data(), cells.stamps(), slot) = cells.frame();
    }
  }

 private:
  struct Accumulator {
    typename Rule::Sums sums;
    float z_ref = 0.0f;
  };

  template <bool kPooled>
  std::size_t add_runs(const LayerCells<Rule>& cells, const unsigned char* covered,
                       const ChunkRuns& runs, const PointChunk& chunk, const float* cx,
                       const float* cy) {
    const float* const w = Rule::weights(chunk);
    const int* const run_slot = runs.slots();
    const int* const starts = runs.starts();
    const int count = runs.size();
    std::size_t used = 0;
    for (int k = 0; k < count; ++k) {
      const int ahead = run_slot[std::min(k + kPrefetchRuns, count - 1)];
      if (ahead >= 0) {
        __builtin_prefetch(&cells.raw(ahead));
        __builtin_prefetch(&frame_index_[ahead]);
      }
      const int s = run_slot[k];
      if (!takes<kPooled>(s, covered)) continue;
      const int i = starts[k], end = starts[k + 1];
      used += static_cast<std::size_t>(end - i);
      int a = frame_index_[s];
      if (static_cast<unsigned>(a) >= static_cast<unsigned>(touched_count_) || touched_[a] != s) {
        a = touched_count_++;
        frame_index_[s] = a;
        touched_[a] = s;
        Accumulator& fresh = accumulators_[a];
        fresh.sums = typename Rule::Sums{};
        fresh.z_ref = Rule::known(cells.raw(s)) ? Rule::reference_z(cells.raw(s)) : chunk.z[i];
      }
      Accumulator& acc = accumulators_[a];
      Rule::add_run(cells.config(), acc.sums, RunPoints{w, cx, cy, chunk.z, i, end, chunk.var_z},
                    acc.z_ref);
    }
    return used;
  }

  std::vector<Accumulator> accumulators_;
  std::vector<int> frame_index_;  ///< slot -> its accumulator this frame
  std::vector<int> touched_;      ///< accumulator -> slot, in order of first touch
  int touched_count_ = 0;
};

}  // namespace layer_insertion
}  // namespace hazmap
